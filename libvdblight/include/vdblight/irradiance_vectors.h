// Irradiance vectors (Pacanowski et al. 2009, sections 3.1, 3.2 and 4.1).
//
// At every node, six irradiance vectors per colour channel, one per axis direction
// delta = +x, -x, +y, -y, +z, -z:
//   I_delta(p) = integral over the hemisphere around delta of L(p <- w) w dw
// where w points *towards* where the light comes from. <I_delta, delta> is the irradiance on
// a surface facing delta. A lookup for a unit normal n picks, per axis, the vector of the
// sign of n's component and blends them by n^2 (section 4.1):
//   I_n = I_x n_x^2 + I_y n_y^2 + I_z n_z^2,   E(n) = <I_n, n>
// which is exact for n = +-x, +-y, +-z.
//
// Channel c of a volume (docs/format.md) is direction d = c / 3 and colour c % 3; its three
// floats are the vector's world x, y, z components. Direction d is axis d / 2, negative if d
// is odd: 0 = +x, 1 = -x, 2 = +y, 3 = -y, 4 = +z, 5 = -z.
#pragma once

#include "vdblight/math.h"
#include "vdblight/basis_desc.h"

namespace vdblight {
namespace iv {

constexpr int kDirections = 6;
constexpr int kChannels = kDirections * 3;   ///< (direction, colour) pairs
constexpr int kFloatsPerNode = kChannels * 3;

/// Direction index of axis a (0..2) with the given sign.
constexpr int direction(int axis, bool negative) { return 2 * axis + (negative ? 1 : 0); }
/// Channel index of direction d and colour c (0 = red, 1 = green, 2 = blue).
constexpr int channel(int d, int colour) { return 3 * d + colour; }

/// The volume basis "irradiance_vectors": 18 channels named "iv_<axis><pos|neg>_<r|g|b>",
/// e.g. "iv_xpos_r", "iv_zneg_b", in channel order.
BasisDesc basis();

/// The n^2 blend of section 4.1 for one node's (or one interpolated) set of vectors:
/// `v` holds kFloatsPerNode floats in channel order. Returns E(n) per colour channel.
Rgb irradiance(const float* v, const Vec3f& n);

}  // namespace iv
}  // namespace vdblight
