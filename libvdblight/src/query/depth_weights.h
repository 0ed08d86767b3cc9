// Visibility-weighted trilinear interpolation (depth_moments.h), shared by the SH lookups.
// (Internal to the query module.)
#pragma once

#include "lattice_locate.h"
#include "vdblight/depth_moments.h"

namespace vdblight::query_detail {

/// Whether depth weights apply in a leaf cell of level `level` of a volume with `levels`
/// levels: only in cells of the finest level. Refinement is complete (every cell with geometry
/// is refined, layout_levels.h), so a leaf cell of a coarser level holds no geometry and every
/// corner sees every point of it; its corners' depth moments, measured over pyramids reaching
/// into the refined neighbours, could only darken a corner wrongly. The lookups keep only the
/// finest level's depth for that reason.
inline bool depthWeightsApplyAt(std::size_t level, std::size_t levels) { return level + 1 == levels; }

/// Multiplies the eight trilinear weights w[c] (corner c = x bit 0, y bit 1, z bit 2 of the
/// cell, fractions fx, fy, fz of the query point in it) by each corner's visibility plus
/// depth::kDepthFloor and renormalises them to sum 1. depth[c]: the corner's depth values.
inline void weightByDepth(float w[8], const float* const depth[8], float fx, float fy, float fz) {
    float sum = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const float v = depth::visibility(depth[c], fx - float(c & 1), fy - float((c >> 1) & 1), fz - float(c >> 2));
        w[c] *= v + depth::kDepthFloor;
        sum += w[c];
    }
    const float inv = 1.0f / sum;
    for (int c = 0; c < 8; ++c) w[c] *= inv;
}

/// weightByDepth for the exact (double) corners of x (trilinearCorners): the weights go
/// through float, as the fast lookups' do, with the fractions of locateExact.
inline void weightCornersByDepth(TrilinearCorners& corners, const float* const depth[8], const GridSpec& grid, const Vec3d& x,
                                 OutsidePolicy outside) {
    int lo[3];
    double frac[3];
    locateExact(grid, x, outside, lo, frac);
    float w[8];
    for (int c = 0; c < 8; ++c) w[c] = float(corners.weight[c]);
    weightByDepth(w, depth, float(frac[0]), float(frac[1]), float(frac[2]));
    for (int c = 0; c < 8; ++c) corners.weight[c] = w[c];
}

}  // namespace vdblight::query_detail
