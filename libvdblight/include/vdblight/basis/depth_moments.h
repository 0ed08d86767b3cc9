// Per-node depth moments: what a lookup needs so that it does not interpolate across walls
// (issue 15, item 4). A self-contained channel set, stored beside a volume's basis channels
// in VolumeLevel::depth; any basis and layout can carry it.
//
// The published scheme (DDGI, Majercik et al. 2019) keeps, per probe and direction, the mean
// and mean square of the distance to the nearest hit in an octahedral map (16x16 texels of
// two halves, 1 KB), and weights each probe at lookup by a Chebyshev bound on "the query
// point is nearer than the surface". We keep the idea with a six-texel cube map that fits
// the 8-bit budget of 12 B per node:
//   - every ray from the node goes to the face of its dominant axis (+x, +y, +z, -x, -y, -z);
//   - what is averaged is the hit's *axial* depth along that face's axis (the z-depth of a
//     cube shadow map) in units of the level's node spacing, clamped to one cell (a query is
//     never more than a cell from a corner node along any axis; a miss counts as one cell);
//   - per face the mean and the standard deviation, each rounded to k/255 (8-bit unorm).
// Axial depth is exact for a wall facing the axis: every ray of the face sees the same depth,
// sigma is 0 and the test is sharp, wherever the query point lies in the cell. Radial
// distance (DDGI's) varies over a face by up to sqrt(3) and would let a one-texel face pass
// points just behind the wall.
//
// At lookup, corner node p and query point x (offset o = (x - p) / spacing, |o_a| <= 1):
// per axis a, the face s = sign(o_a) gives mean mu and deviation sigma; with
// e = |o_a| - mu - kDepthBias, the axis passes if e <= 0, else with Chebyshev's one-sided
// bound v_a = s2 / (s2 + e^2), s2 = sigma^2 + kDepthMinSigma^2. The node's visibility is
// (v_x v_y v_z)^3 (DDGI sharpens its bound by the cube too). Trilinear weights are multiplied
// by (visibility + kDepthFloor) and renormalised: with every corner hidden it falls back to
// plain trilinear weights.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "vdblight/core/math.h"

namespace vdblight::depth {

/// Floats per node in VolumeLevel::depth: 4 channels of 3 (x, y, z), in this order.
constexpr int kChannels = 4;
constexpr int kFloatsPerNode = kChannels * 3;
/// Bytes per node when stored as 8-bit unorm (the export; the .vdb keeps floats k/255).
constexpr int kBytesPerNode = kFloatsPerNode;
/// Channel c's components x, y, z are the faces +x +y +z (c = 0, 2) or -x -y -z (c = 1, 3).
enum Channel { kMeanPositive = 0, kMeanNegative = 1, kSigmaPositive = 2, kSigmaNegative = 3 };
/// Grid base names of the four channels (level suffix as for basis channels, docs/format.md).
const std::string& channelName(int channel);

/// Tolerance in cells before a point counts as behind the mean depth: covers the rounding to
/// 1/255 and points on the very surface the node sees.
constexpr float kDepthBias = 0.02f;
/// Smallest deviation used in the Chebyshev bound (cells): a wall facing the axis has sigma 0.
constexpr float kDepthMinSigma = 0.02f;
/// Added to every corner's visibility before the weights are renormalised.
constexpr float kDepthFloor = 1e-6f;

/// Rounds a value in cells to the stored 8-bit grid (k/255, clamped into [0, 1]).
inline float quantize(double v) {
    const double c = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
    return float(std::nearbyint(c * 255.0) / 255.0);
}

/// Sums of one node's rays, per face; deterministic if rays are added in a fixed order.
class Accumulator {
public:
    /// A ray from the node in unit direction `dir` whose first hit is at distance `t`
    /// (infinity for a miss); `spacing` is the node's level spacing.
    void add(const Vec3f& dir, float t, double spacing) {
        const float ax = std::fabs(dir.x), ay = std::fabs(dir.y), az = std::fabs(dir.z);
        const int axis = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
        const int face = axis + (dir[axis] < 0.0f ? 3 : 0);
        double d = std::isfinite(t) ? double(t) * double(std::fabs(dir[axis])) / spacing : 1.0;
        if (d > 1.0) d = 1.0;
        sum_[face] += d;
        squares_[face] += d * d;
        ++count_[face];
    }
    /// The node's kFloatsPerNode values, quantised. A face without rays is free (mean 1).
    void finish(float out[kFloatsPerNode]) const {
        for (int face = 0; face < 6; ++face) {
            const int axis = face % 3;
            const bool negative = face >= 3;
            double mean = 1.0, sigma = 0.0;
            if (count_[face] > 0) {
                mean = sum_[face] / count_[face];
                const double var = squares_[face] / count_[face] - mean * mean;
                sigma = var > 0.0 ? std::sqrt(var) : 0.0;
            }
            out[(negative ? kMeanNegative : kMeanPositive) * 3 + axis] = quantize(mean);
            out[(negative ? kSigmaNegative : kSigmaPositive) * 3 + axis] = quantize(sigma);
        }
    }

private:
    double sum_[6] = {}, squares_[6] = {};
    uint32_t count_[6] = {};
};

/// Visibility in [0, 1] of a query point at offset o (in cells, x - node) from a node with
/// depth values `d` (kFloatsPerNode floats). The formula in the header comment; the same
/// arithmetic as the shader in docs/engines.md.
inline float visibility(const float* d, float ox, float oy, float oz) {
    const float o[3] = {ox, oy, oz};
    float v = 1.0f;
    for (int a = 0; a < 3; ++a) {
        const bool negative = o[a] < 0.0f;
        const float mu = d[(negative ? kMeanNegative : kMeanPositive) * 3 + a];
        const float sigma = d[(negative ? kSigmaNegative : kSigmaPositive) * 3 + a];
        const float e = std::fabs(o[a]) - mu - kDepthBias;
        if (e <= 0.0f) continue;
        const float s2 = sigma * sigma + kDepthMinSigma * kDepthMinSigma;
        v *= s2 / (s2 + e * e);
    }
    return v * v * v;
}

}  // namespace vdblight::depth
