#include "basis/sh.h"

#include <cmath>
#include <vector>

namespace vdblight {
namespace sh {

namespace {
// Normalisation constants of the order-2 real basis (see the table in sh.h).
constexpr float kY00 = 0.282094791773878f;   // 1 / (2 sqrt(pi))
constexpr float kY1 = 0.488602511902920f;    // sqrt(3 / (4 pi))
constexpr float kY2a = 1.092548430592079f;   // sqrt(15 / (4 pi))
constexpr float kY20 = 0.315391565252520f;   // sqrt(5 / (16 pi))
constexpr float kY22 = 0.546274215296040f;   // sqrt(15 / (16 pi))

double factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= i;
    return f;
}

// Associated Legendre P_l^m(x) for m >= 0 *without* the Condon-Shortley phase
// (standard three-term recurrences).
double legendre(int l, int m, double x) {
    double pmm = 1.0;
    if (m > 0) {
        const double somx2 = std::sqrt(std::max(0.0, (1.0 - x) * (1.0 + x)));
        double fact = 1.0;
        for (int i = 1; i <= m; ++i) {
            pmm *= fact * somx2;
            fact += 2.0;
        }
    }
    if (l == m) return pmm;
    double pmmp1 = x * (2.0 * m + 1.0) * pmm;
    if (l == m + 1) return pmmp1;
    double pll = 0.0;
    for (int ll = m + 2; ll <= l; ++ll) {
        pll = ((2.0 * ll - 1.0) * x * pmmp1 - (ll + m - 1.0) * pmm) / (ll - m);
        pmm = pmmp1;
        pmmp1 = pll;
    }
    return pll;
}

double normalisation(int l, int m) {
    return std::sqrt((2.0 * l + 1.0) * factorial(l - m) / (4.0 * kPi * factorial(l + m)));
}
}  // namespace

void evalUnrolled(const Vec3f& d, float out[kCoeffs]) {
    const float x = d.x, y = d.y, z = d.z;
    out[0] = kY00;
    out[1] = kY1 * y;
    out[2] = kY1 * z;
    out[3] = kY1 * x;
    out[4] = kY2a * x * y;
    out[5] = kY2a * y * z;
    out[6] = kY20 * (3.0f * z * z - 1.0f);
    out[7] = kY2a * x * z;
    out[8] = kY22 * (x * x - y * y);
}

void evalGeneric(int lmax, const Vec3d& d, double* out) {
    // Y_l^m = sqrt(2) K_l^|m| P_l^|m|(cos theta) * (cos(m phi) for m > 0, sin(|m| phi) for m < 0)
    // with theta measured from +z and phi from +x towards +y.
    const double cosTheta = std::max(-1.0, std::min(1.0, d.z));
    const double phi = std::atan2(d.y, d.x);
    for (int l = 0; l <= lmax; ++l) {
        out[l * (l + 1)] = normalisation(l, 0) * legendre(l, 0, cosTheta);
        for (int m = 1; m <= l; ++m) {
            const double common = std::sqrt(2.0) * normalisation(l, m) * legendre(l, m, cosTheta);
            out[l * (l + 1) + m] = common * std::cos(m * phi);
            out[l * (l + 1) - m] = common * std::sin(m * phi);
        }
    }
}

void irradianceWeights(const Vec3f& n, float out[kCoeffs]) {
    evalUnrolled(n, out);
    for (int j = 0; j < kCoeffs; ++j) out[j] *= float(kCosineLobe[bandOf(j)]);
}

Rgb irradiance(const Rgb coeffs[kCoeffs], const Vec3f& n) {
    float w[kCoeffs];
    irradianceWeights(n, w);
    Rgb e{0, 0, 0};
    for (int j = 0; j < kCoeffs; ++j) e += coeffs[j] * w[j];
    return e;
}

Rgb radiance(const Rgb coeffs[kCoeffs], const Vec3f& d) {
    float y[kCoeffs];
    evalUnrolled(d, y);
    Rgb l{0, 0, 0};
    for (int j = 0; j < kCoeffs; ++j) l += coeffs[j] * y[j];
    return l;
}

const char* gridName(int j) {
    static const char* const names[kCoeffs] = {"sh_l0m0",     "sh_l1m_neg1", "sh_l1m0", "sh_l1m1", "sh_l2m_neg2",
                                               "sh_l2m_neg1", "sh_l2m0",     "sh_l2m1", "sh_l2m2"};
    return (j >= 0 && j < kCoeffs) ? names[j] : "";
}

}  // namespace sh
}  // namespace vdblight
