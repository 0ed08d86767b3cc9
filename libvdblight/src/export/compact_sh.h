// The engine-size SH layouts sh1-16 and sh2-32 (docs/engines.md): L0 in half floats, the
// higher bands divided by L0 into UNORM8, in the arrangement of Unity's Adaptive Probe
// Volumes (L0 + L1 in 16 B per probe, L2 in 16 B more). Not public API.
//
// The values encoded are the sh2-packed terms (layouts.cpp) of each colour channel c:
//   a   = A0 c0 L0                   (band 0: the mean irradiance)
//   b   = A1 c1 (L3, L1, L2)         (coefficients of n.x, n.y, n.z)
//   B   = A2 (c2 L4, c2 L5, c3 L6, c2 L7)   (coefficients of n.x n.y, n.y n.z, 3 n.z^2 - 1, n.z n.x)
//   C   = A2 c4 L8                   (coefficient of n.x^2 - n.y^2)
// Each of b, B, C is stored as t = clamp(v / (range * a) + 0.5, 0, 1), decoded as
// v = (t - 0.5) * range * a. The ranges are the largest |v / a| of any non-negative radiance
// (a single direction attains them), so a bake never clips: |b/a| <= 2, |B_xy/a| <= 15/8,
// |B_zz/a| <= 5/8, |C/a| <= 15/16 (docs/engines.md derives them).
#pragma once

#include "export_internal.h"

namespace vdblight::exporter {

namespace compact_sh {
constexpr double kL1Range = 4.0;                               ///< b / a in [-2, 2]
constexpr double kL2Range[4] = {3.75, 3.75, 1.25, 3.75};       ///< B / a: xy, yz, the L6 term, zx
constexpr double kL2CRange = 1.875;                            ///< C / a in [-15/16, 15/16]
}  // namespace compact_sh

/// True for sh1-16 and sh2-32.
bool isCompactSh(ExportLayout layout);
/// Their textures: L0_L1Rx (half / float), L1G_L1Ry, L1B_L1Rz and for sh2-32 L2_R, L2_G,
/// L2_B, L2_C (UNORM8 except in the EXR atlas).
std::vector<TextureDesc> compactShTextures(ExportLayout layout);
/// Nine SH order-2 radiance coefficients -> the layout's texels (4 floats per texture, in
/// compactShTextures order), before rounding to the textures' formats.
void packCompactTexel(ExportLayout layout, const Rgb L[9], float* out);
/// The inverse on texels as stored (already rounded): the SH order-2 radiance coefficients
/// they decode to (band 2 zero for sh1-16).
void unpackCompactTexel(ExportLayout layout, const float* texel, Rgb L[9]);

}  // namespace vdblight::exporter
