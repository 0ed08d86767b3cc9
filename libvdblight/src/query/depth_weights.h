// Visibility-weighted trilinear interpolation (depth_moments.h), shared by the SH lookups.
// (Internal to the query module.)
#pragma once

#include <cmath>

#include "lattice_locate.h"
#include "vdblight/basis/depth_moments.h"

namespace vdblight::query_detail {

/// Whether depth weights apply in a leaf cell of level `level` of a volume with `levels`
/// levels: only in cells of the finest level. Refinement is complete (every cell with geometry
/// is refined, layout_levels.h), so a leaf cell of a coarser level holds no geometry and every
/// corner sees every point of it; its corners' depth moments, measured over pyramids reaching
/// into the refined neighbours, could only darken a corner wrongly. The lookups keep only the
/// finest level's depth for that reason.
inline bool depthWeightsApplyAt(std::size_t level, std::size_t levels) { return level + 1 == levels; }

/// The 24 axis tests of weightByDepth (lane 8 a + c: axis a of corner c, at distance dist from
/// the corner, against the face's mean mu and s2 = sigma^2 + kDepthMinSigma^2), then the
/// corners' visibility times w, renormalised: the part that weightByDepth and
/// weightByPreparedDepth share once their lanes are gathered.
inline void weightByDepthLanes(float w[8], const float dist[24], const float mu[24], const float s2[24]) {
    // A passing axis (e <= 0) computes its bound at e = 0: s2 / s2, exactly 1 (s2 >= kDepthMinSigma^2
    // > 0). max(e, 0) is written as (e + |e|) / 2, exact for |e| <= 2, because GCC keeps a float
    // compare (which may trap) as a branch and would leave the loop scalar.
    float pass[24];
    for (int i = 0; i < 24; ++i) {
        const float e = dist[i] - mu[i] - depth::kDepthBias;
        const float behind = 0.5f * (e + std::fabs(e));
        pass[i] = s2[i] / (s2[i] + behind * behind);
    }
    float v[8];
    for (int c = 0; c < 8; ++c) {
        const float p = pass[c] * pass[8 + c] * pass[16 + c];
        v[c] = p * p * p;
    }
    float sum = 0.0f;
    for (int c = 0; c < 8; ++c) {
        w[c] *= v[c] + depth::kDepthFloor;
        sum += w[c];
    }
    const float inv = 1.0f / sum;
    for (int c = 0; c < 8; ++c) w[c] *= inv;
}

/// Multiplies the eight trilinear weights w[c] (corner c = x bit 0, y bit 1, z bit 2 of the
/// cell, fractions fx, fy, fz in [0, 1] of the query point in it) by each corner's visibility
/// plus depth::kDepthFloor and renormalises them to sum 1. depth[c]: the corner's depth values.
///
/// depth::visibility's arithmetic, bit for bit, arranged for speed (every SH lookup with depth
/// moments spends most of its time here): along an axis, a corner with bit 0 sees the point on
/// its positive side at distance f, a corner with bit 1 on its negative side at 1 - f (the same
/// float as |f - 1|; at f = 1 the distance is 0 and every face passes, so the face chosen does
/// not matter), so the faces are known without a test; the 24 axis tests then run branch-free
/// in one loop that the compiler vectorises (an axis that passes multiplies by exactly 1, as
/// skipping it does).
inline void weightByDepth(float w[8], const float* const depth[8], float fx, float fy, float fz) {
    // Lane 8 a + c: axis a of corner c.
    const float near[3] = {fx, fy, fz}, far[3] = {1.0f - fx, 1.0f - fy, 1.0f - fz};
    float dist[24], mu[24], sigma[24];
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 8; ++c) {
            const bool negative = (c >> a) & 1;
            dist[8 * a + c] = negative ? far[a] : near[a];
            mu[8 * a + c] = depth[c][(negative ? depth::kMeanNegative : depth::kMeanPositive) * 3 + a];
            sigma[8 * a + c] = depth[c][(negative ? depth::kSigmaNegative : depth::kSigmaPositive) * 3 + a];
        }
    float s2[24];
    for (int i = 0; i < 24; ++i) s2[i] = sigma[i] * sigma[i] + depth::kDepthMinSigma * depth::kDepthMinSigma;
    weightByDepthLanes(w, dist, mu, s2);
}

/// A node's depth values as weightByPreparedDepth reads them, made once when a lookup is built:
/// the means of the faces +x +y +z, -x -y -z, then s2 = sigma^2 + kDepthMinSigma^2 of the same
/// faces (weightByDepth's s2, the same float operations, so the same bits).
constexpr int kPreparedDepthFloats = 12;
inline void prepareDepth(const float* depth, float out[kPreparedDepthFloats]) {
    for (int a = 0; a < 3; ++a) {
        out[a] = depth[depth::kMeanPositive * 3 + a];
        out[3 + a] = depth[depth::kMeanNegative * 3 + a];
        const float sp = depth[depth::kSigmaPositive * 3 + a], sn = depth[depth::kSigmaNegative * 3 + a];
        out[6 + a] = sp * sp + depth::kDepthMinSigma * depth::kDepthMinSigma;
        out[9 + a] = sn * sn + depth::kDepthMinSigma * depth::kDepthMinSigma;
    }
}

/// weightByDepth on prepared depth values (prepareDepth), bit for bit: the default lookup's
/// hot spot (issue 33, part 4: the gather of the 24 lanes' means and deviations was 259 of its
/// 2 450 instructions, their squares 48 more). The lanes' offsets into a corner's 12 floats are
/// constants, so the gather is 48 plain loads.
inline void weightByPreparedDepth(float w[8], const float* const prepared[8], float fx, float fy, float fz) {
    const float near[3] = {fx, fy, fz}, far[3] = {1.0f - fx, 1.0f - fy, 1.0f - fz};
    float dist[24], mu[24], s2[24];
#pragma GCC unroll 24
    for (int i = 0; i < 24; ++i) {  // lane i = 8 a + c, as in weightByDepth
        const int a = i >> 3, c = i & 7;
        const bool negative = (c >> a) & 1;
        dist[i] = negative ? far[a] : near[a];
        mu[i] = prepared[c][(negative ? 3 : 0) + a];
        s2[i] = prepared[c][(negative ? 9 : 6) + a];
    }
    weightByDepthLanes(w, dist, mu, s2);
}

/// weightByDepth for the exact (double) corners of x (trilinearCorners): the weights go
/// through float, as the fast lookups' do, with the fractions of locateExact. `prepared`: depth
/// points at prepared values (prepareDepth; weightByPreparedDepth).
inline void weightCornersByDepth(TrilinearCorners& corners, const float* const depth[8], const GridSpec& grid, const Vec3d& x,
                                 OutsidePolicy outside, bool prepared = false) {
    int lo[3];
    double frac[3];
    locateExact(grid, x, outside, lo, frac);
    float w[8];
    for (int c = 0; c < 8; ++c) w[c] = float(corners.weight[c]);
    if (prepared)
        weightByPreparedDepth(w, depth, float(frac[0]), float(frac[1]), float(frac[2]));
    else
        weightByDepth(w, depth, float(frac[0]), float(frac[1]), float(frac[2]));
    for (int c = 0; c < 8; ++c) corners.weight[c] = w[c];
}

}  // namespace vdblight::query_detail
