#include "vdblight/basis/irradiance_vectors.h"

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"

namespace vdblight {
namespace iv {

BasisDesc basis() {
    static const char* kAxis[3] = {"x", "y", "z"};
    static const char* kColour[3] = {"r", "g", "b"};
    BasisDesc desc;
    desc.kind = "irradiance_vectors";
    for (int d = 0; d < kDirections; ++d)
        for (int c = 0; c < 3; ++c)
            desc.channelNames.push_back(std::string("iv_") + kAxis[d / 2] + (d % 2 ? "neg" : "pos") + "_" + kColour[c]);
    return desc;
}

namespace {
Rgb paperBlend(const float* v, const Vec3f& n) {
    Rgb e{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        const float w = n[a] * n[a];
        if (w == 0.0f) continue;
        const float* p = v + 9 * direction(a, n[a] < 0.0f);
        e += Rgb(p[0] * n.x + p[1] * n.y + p[2] * n.z, p[3] * n.x + p[4] * n.y + p[5] * n.z,
                 p[6] * n.x + p[7] * n.y + p[8] * n.z) * w;
    }
    return e;
}

// E = 1/2 V.n + 1/4 n^T G n + 1/4 sum_a G_aa n_a^2 (irradiance_vectors.h), per colour.
float quadratic(const float* v, const Vec3f& n, int colour) {
    float g[3][3], vn = 0.0f;
    for (int a = 0; a < 3; ++a) {
        const float* p = v + 9 * direction(a, false) + 3 * colour;
        const float* m = v + 9 * direction(a, true) + 3 * colour;
        for (int b = 0; b < 3; ++b) g[a][b] = p[b] - m[b];
        vn += (p[a] + m[a]) * n[a];
    }
    float quad = 0.0f;
    for (int a = 0; a < 3; ++a) {
        quad += 2.0f * g[a][a] * n[a] * n[a];
        for (int b = a + 1; b < 3; ++b) quad += (g[a][b] + g[b][a]) * n[a] * n[b];
    }
    return 0.5f * vn + 0.25f * quad;
}

// What the six vectors prove about E(n) for non-negative radiance (irradiance_vectors.h):
// lo = max(0, max_delta <I_delta, n>), hi = sum_a |n_a| E_(a, sign n_a).
void bounds(const float* v, const Vec3f& n, int colour, float& lo, float& hi) {
    lo = 0.0f, hi = 0.0f;
    for (int d = 0; d < kDirections; ++d) {
        const float* p = v + 9 * d + 3 * colour;
        lo = std::max(lo, p[0] * n.x + p[1] * n.y + p[2] * n.z);
    }
    for (int a = 0; a < 3; ++a) {
        const bool negative = n[a] < 0.0f;
        const float e = v[9 * direction(a, negative) + 3 * colour + a];  // (I_delta)_a = +-E_delta
        hi += std::abs(n[a]) * (negative ? -e : e);
    }
}
}  // namespace

Rgb irradiance(const float* v, const Vec3f& n, Blend blend) {
    if (blend == Blend::Paper) return paperBlend(v, n);
    Rgb e(quadratic(v, n, 0), quadratic(v, n, 1), quadratic(v, n, 2));
    if (blend == Blend::Bounded)
        for (int c = 0; c < 3; ++c) {
            float lo, hi;
            bounds(v, n, c, lo, hi);
            // hi >= lo for consistent vectors; noisy ones may not be: the lower bound wins.
            e[c] = std::max(lo, std::min(e[c], hi));
        }
    return e;
}

Rgbd referenceIrradiance(const double* v, const Vec3d& n, Blend blend) {
    Rgbd e{0, 0, 0};
    for (int c = 0; c < 3; ++c) {
        auto at = [&](int d, int k) { return v[9 * d + 3 * c + k]; };  // component k of I_d, colour c
        double sum = 0;
        if (blend == Blend::Paper) {
            for (int a = 0; a < 3; ++a) {
                const int d = direction(a, n[a] < 0.0);
                sum += n[a] * n[a] * (at(d, 0) * n.x + at(d, 1) * n.y + at(d, 2) * n.z);
            }
        } else {
            // Axis terms from E_{+a}, E_{-a}; cross terms from the in-plane components.
            for (int a = 0; a < 3; ++a) {
                const double ePos = at(direction(a, false), a), eNeg = -at(direction(a, true), a);
                sum += 0.5 * (ePos - eNeg) * n[a] + 0.5 * (ePos + eNeg) * n[a] * n[a];
            }
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    if (a != b) {
                        const double gab = at(direction(a, false), b) - at(direction(a, true), b);
                        sum += 0.25 * gab * n[a] * n[b];
                    }
        }
        if (blend == Blend::Bounded) {
            double lo = 0, hi = 0;
            for (int d = 0; d < kDirections; ++d) lo = std::max(lo, at(d, 0) * n.x + at(d, 1) * n.y + at(d, 2) * n.z);
            for (int a = 0; a < 3; ++a) {
                const int d = direction(a, n[a] < 0.0);
                hi += std::abs(n[a]) * (n[a] < 0.0 ? -at(d, a) : at(d, a));  // |n_a| E_delta
            }
            sum = std::max(lo, std::min(sum, hi));
        }
        e[c] = sum;
    }
    return e;
}

const char* blendName(Blend blend) {
    switch (blend) {
        case Blend::Bounded: return "bounded";
        case Blend::Quadratic: return "quadratic";
        case Blend::Paper: return "paper";
    }
    return "";
}

Blend parseBlend(const std::string& name) {
    if (name == "bounded") return Blend::Bounded;
    if (name == "quadratic") return Blend::Quadratic;
    if (name == "paper") return Blend::Paper;
    throw ValueError("the irradiance-vector blend must be bounded, quadratic or paper, got '" + name + "'");
}

}  // namespace iv
}  // namespace vdblight
