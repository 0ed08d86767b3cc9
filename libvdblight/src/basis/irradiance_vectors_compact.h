// The compact colour + direction form of an irradiance-vector volume (Pacanowski et al. 2009,
// section 4.2): per node and direction delta, the three vectors I_R, I_G, I_B become
//   colour    c = (|I_R|, |I_G|, |I_B|)
//   direction d = (I_R + I_G + I_B) / |I_R + I_G + I_B|
// and are rebuilt as I_lambda ~ c_lambda d. Two Vec3 grids per delta, written as 16-bit
// halves (the paper's two 16-bit textures per delta): 36 halves = 72 bytes per node instead
// of 54 floats = 216. Exact where the three colour vectors are parallel (one light, or
// lights of one colour); elsewhere it keeps each colour's magnitude and a common direction.
//
// Channel 2 d + 0 is the colour of direction d, channel 2 d + 1 its direction (d as in
// basis/irradiance_vectors.h: 0 = +x, 1 = -x, ..., 5 = -z); names "ivc_<axis><pos|neg>_rgb" and
// "ivc_<axis><pos|neg>_dir". A lookup interpolates colour and direction separately
// (trilinear or tricubic, VectorGridLookup), renormalises the direction, rebuilds the vectors
// and reconstructs E(n) as the full form does (basis/irradiance_vectors.h, `Blend`). Compacting a
// whole volume: iv::compact in volume_compact.h.
#pragma once

#include "vdblight/basis/basis.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/core/math.h"

namespace vdblight {
namespace iv {

constexpr int kCompactChannels = kDirections * 2;  ///< (direction, colour | direction) pairs
constexpr int kCompactFloatsPerNode = kCompactChannels * 3;

/// The volume basis "irradiance_vectors_compact": 12 channels in the order above.
BasisDesc compactBasis();

/// Compacts one node: `full` holds kFloatsPerNode floats, `out` gets kCompactFloatsPerNode.
void compactNode(const float* full, float* out);

/// Inverse of compactNode (exact where the node's three colour vectors were parallel):
/// I_d,c = colour_d,c * direction_d, written as kFloatsPerNode floats in channel order.
void expandNode(const float* compactValues, float* full);

/// E(n) per colour channel from one node's (or one interpolated) compact values: each
/// direction is renormalised, I_lambda = c_lambda d, then irradiance() with `blend`.
Rgb compactIrradiance(const float* v, const Vec3f& n, Blend blend = kDefaultBlend);

}  // namespace iv
}  // namespace vdblight
