// The fast SH order-2 irradiance of a cell, shared by ShUniformLookup, ShLevelsLookup and the
// streamed lookups (sh_stream_lookup.cpp).
// (Internal to the query module.)
#pragma once

#include <cstddef>

#include "depth_weights.h"
#include "vdblight/core/math.h"
#include "basis/sh.h"

namespace vdblight::query_detail {

constexpr int kShFloats = sh::kCoeffs * 3;

/// Trilinear blend of the 8 corner nodes of a cell (corner c = x bit 0, y bit 1, z bit 2; each
/// 27 coefficients with the cosine-lobe constants folded in), then one 9-term dot product per
/// channel with y = Y(n). `depth`: the corners' depth moments (depth::kFloatsPerNode floats
/// each) to weight them by (depth_weights.h), or null for plain trilinear. Every SH order-2
/// lookup's fast path ends here, in memory or streamed, so all give the same bits.
inline Rgb interpolateShCorners(const float* const corners[8], const float* const* depth, float fx, float fy, float fz,
                                const float y[sh::kCoeffs]) {
    const float wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy}, wz[2] = {1 - fz, fz};
    float weights[8];
    for (int c = 0; c < 8; ++c) weights[c] = wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2];
    if (depth) weightByDepth(weights, depth, fx, fy, fz);
    // Interpolate the 27 coefficients first, then one 9-term dot product per channel. One pass
    // over the floats with the eight corners inside, as ShFourUniformLookup blends: GCC 12
    // vectorises it (-fopt-info-vec), where it left the loop over the floats of one corner at a
    // time scalar: sh2 about 9 -> 15-19 M lookups/s in vdblight_bench --only query (README).
    // Each float is still summed over the corners in order c = 0..7; starting from the first
    // product instead of from +0 changes at most the sign of an all-zero sum, which the dot
    // product below (from +0) cannot show: the same bits as before.
    float interp[kShFloats];
    for (int f = 0; f < kShFloats; ++f) {
        float s = weights[0] * corners[0][f];
        s += weights[1] * corners[1][f];
        s += weights[2] * corners[2][f];
        s += weights[3] * corners[3][f];
        s += weights[4] * corners[4][f];
        s += weights[5] * corners[5][f];
        s += weights[6] * corners[6][f];
        s += weights[7] * corners[7][f];
        interp[f] = s;
    }
    Rgb e{0, 0, 0};
    for (int c = 0; c < sh::kCoeffs; ++c) e += Rgb(interp[3 * c], interp[3 * c + 1], interp[3 * c + 2]) * y[c];
    return e;
}

/// interpolateShCorners for a cell in a node array: base is the lower corner's coefficients,
/// sx, sy, sz the strides to the next node along x, y, z, in floats. `depthBase`: the lower
/// corner's depth moments in an array of the same node order, or null.
inline Rgb interpolateSh(const float* base, std::size_t sx, std::size_t sy, std::size_t sz, float fx, float fy, float fz,
                         const float y[sh::kCoeffs], const float* depthBase = nullptr) {
    const float* corners[8] = {base, base + sx, base + sy, base + sx + sy,
                               base + sz, base + sx + sz, base + sy + sz, base + sx + sy + sz};
    const float* depth[8];
    if (depthBase)
        for (int c = 0; c < 8; ++c)
            depth[c] = depthBase + std::size_t(corners[c] - base) / kShFloats * depth::kFloatsPerNode;
    return interpolateShCorners(corners, depthBase ? depth : nullptr, fx, fy, fz, y);
}

}  // namespace vdblight::query_detail
