// Real SH of bands 0..4 as explicit float polynomials, and the cosine-lobe factors A_l, in one
// place for the sh:N basis (sh_basis.cpp: its bake and its terms) and the SH order-4 lookup
// (query/sh4_uniform_lookup.cpp), so that both evaluate the same bits.
// (Internal to the basis module; the query module includes it as "../basis/sh_polynomials.h".)
#pragma once

#include <cmath>

#include "vdblight/core/math.h"

namespace vdblight::sh {

/// The cosine-lobe factor A_l of band l (sh_basis.cpp's header comment; A_3 = 0).
inline double cosineLobe(int l) {
    const auto factorial = [](int n) {
        double f = 1.0;
        for (int i = 2; i <= n; ++i) f *= i;
        return f;
    };
    if (l == 0) return kPi;
    if (l == 1) return 2.0 * kPi / 3.0;
    if (l % 2) return 0.0;
    const double sign = (l / 2 - 1) % 2 ? -1.0 : 1.0;
    const double half = factorial(l / 2);
    return 2.0 * kPi * sign / ((l + 2.0) * (l - 1.0)) * factorial(l) / (std::pow(2.0, l) * half * half);
}

/// Y_j(d) for j < (order + 1)^2, order <= 4, as the explicit polynomials of bands 0..4
/// (docs/engines.md, "Shaders for sh:N"; the constants are docs/format.md's K_l^|m|, times
/// sqrt(2) for m != 0, with the polynomial's own factors folded in, to 9 digits), in float: the
/// bake projects every sample and the lookups weigh every term with them. sh_basis_test checks
/// them against sh::evalGeneric (the Legendre recurrence in double). Inline, so that a caller
/// with a constant order keeps only the bands it reads.
/// `band3` false: y[9..15] are left as they are (band 3 carries no irradiance, A_3 = 0: the sh:4
/// lookup, which reads bands 0..2 and 4 only, skips its 7 polynomials; the others keep their bits).
inline void evalPolynomials(int order, const Vec3f& d, float* y, bool band3 = true) {
    const float x = d.x, yy = d.y, z = d.z;
    y[0] = 0.282094792f;
    if (order < 1) return;
    y[1] = 0.488602512f * yy, y[2] = 0.488602512f * z, y[3] = 0.488602512f * x;
    if (order < 2) return;
    const float x2 = x * x, y2 = yy * yy, z2 = z * z;
    y[4] = 1.092548431f * x * yy, y[5] = 1.092548431f * yy * z, y[6] = 0.315391565f * (3 * z2 - 1);
    y[7] = 1.092548431f * x * z, y[8] = 0.546274215f * (x2 - y2);
    if (order < 3) return;
    if (band3) {
        y[9] = 0.590043590f * yy * (3 * x2 - y2), y[10] = 2.890611443f * x * yy * z;
        y[11] = 0.457045799f * yy * (5 * z2 - 1), y[12] = 0.373176333f * z * (5 * z2 - 3);
        y[13] = 0.457045799f * x * (5 * z2 - 1), y[14] = 1.445305721f * z * (x2 - y2);
        y[15] = 0.590043590f * x * (x2 - 3 * y2);
    }
    if (order < 4) return;
    y[16] = 2.503342942f * x * yy * (x2 - y2), y[17] = 1.770130770f * yy * z * (3 * x2 - y2);
    y[18] = 0.946174696f * x * yy * (7 * z2 - 1), y[19] = 0.669046544f * yy * z * (7 * z2 - 3);
    y[20] = 0.105785547f * (35 * z2 * z2 - 30 * z2 + 3), y[21] = 0.669046544f * x * z * (7 * z2 - 3);
    y[22] = 0.473087348f * (x2 - y2) * (7 * z2 - 1), y[23] = 1.770130770f * x * z * (x2 - 3 * y2);
    y[24] = 0.625835735f * (x2 * x2 - 6 * x2 * y2 + y2 * y2);
}

}  // namespace vdblight::sh
