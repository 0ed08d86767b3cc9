// Real spherical harmonics of order 2 (bands l = 0, 1, 2: nine coefficients).
//
// Convention (docs/format.md "SH convention"): real, orthonormal over the sphere
// (integral of Y_j Y_k = delta_jk), no Condon-Shortley phase, index j = l (l + 1) + m:
//   j  (l, m)   Y_j(x, y, z) for a unit direction
//   0  (0, 0)   0.282095
//   1  (1,-1)   0.488603 y
//   2  (1, 0)   0.488603 z
//   3  (1, 1)   0.488603 x
//   4  (2,-2)   1.092548 x y
//   5  (2,-1)   1.092548 y z
//   6  (2, 0)   0.315392 (3 z^2 - 1)
//   7  (2, 1)   1.092548 x z
//   8  (2, 2)   0.546274 (x^2 - y^2)
// Irradiance for a unit normal n (Ramamoorthi & Hanrahan; Kontkanen & Laine eq. 1):
//   E(n) = sum_j A_l(j) L_j Y_j(n),  A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4.
#pragma once

#include "vdblight/core/math.h"

namespace vdblight {
namespace sh {

constexpr int kBands = 3;
constexpr int kCoeffs = 9;

/// Band (l) of coefficient j.
constexpr int bandOf(int j) { return j == 0 ? 0 : (j < 4 ? 1 : 2); }
/// Cosine-lobe convolution constants A_l (clamped cosine projected and rescaled).
constexpr double kCosineLobe[kBands] = {kPi, 2.0 * kPi / 3.0, kPi / 4.0};

/// The nine basis functions at unit direction d, written out (the fast path).
void evalUnrolled(const Vec3f& d, float out[kCoeffs]);

/// Generic real SH of any order from associated Legendre recurrences (the reference
/// path). Writes (lmax + 1)^2 values in the same j = l (l + 1) + m order.
void evalGeneric(int lmax, const Vec3d& d, double* out);

/// Weights w_j = A_l(j) Y_j(n): irradiance is sum_j w_j L_j.
void irradianceWeights(const Vec3f& n, float out[kCoeffs]);

/// Irradiance E(n) from nine RGB radiance coefficients.
Rgb irradiance(const Rgb coeffs[kCoeffs], const Vec3f& n);

/// Radiance reconstructed in direction d from nine RGB coefficients (no convolution).
Rgb radiance(const Rgb coeffs[kCoeffs], const Vec3f& d);

/// Grid name of coefficient j: "sh_l<l>m<m>" with "neg" for a negative m, e.g. "sh_l1m_neg1".
const char* gridName(int j);

}  // namespace sh
}  // namespace vdblight
