// The fast SH order-2 irradiance of a cell, shared by ShUniformLookup, ShLevelsLookup and the
// streamed lookups (sh_stream_lookup.cpp).
// (Internal to the query module.)
#pragma once

#include <cstddef>

#include "depth_weights.h"
#include "float4.h"
#include "vdblight/core/math.h"
#include "basis/sh.h"

namespace vdblight::query_detail {

constexpr int kShFloats = sh::kCoeffs * 3;

/// The blend of the 8 corner nodes of a cell (corner c = x bit 0, y bit 1, z bit 2; each 27
/// coefficients with the cosine-lobe constants folded in, channel-major [c][rgb]) with the
/// given weights, then one 9-term dot product per colour with y = Y(n). kBlendFloats: 27, or 28
/// for node records padded with a zero (ShUniformLookup), whose blend runs on whole vectors.
/// Every SH order-2 lookup's fast path ends here, in memory or streamed, so all give the same bits.
template <int kBlendFloats = kShFloats>
inline Rgb blendShCorners(const float* const corners[8], const float weights[8], const float y[sh::kCoeffs]) {
    static_assert(kBlendFloats == kShFloats || kBlendFloats == kShFloats + 1, "27 coefficients, or 27 and a zero");
    // Interpolate the 27 coefficients first, then the dot product. One pass over the floats with
    // the eight corners inside, as ShFourUniformLookup blends: GCC 12 vectorises it
    // (-fopt-info-vec), where it left the loop over the floats of one corner at a time scalar:
    // sh2 about 9 -> 15-19 M lookups/s in vdblight_bench --only query (README). Each float is
    // still summed over the corners in order c = 0..7; starting from the first product instead
    // of from +0 changes at most the sign of an all-zero sum, which the dot product below (from
    // +0) cannot show: the same bits as before.
    float interp[kShFloats + 1];
    for (int f = 0; f < kBlendFloats; ++f) {
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
    if (kBlendFloats == kShFloats) interp[kShFloats] = 0.0f;
    // The colours of a coefficient side by side in the lanes of one vector, each summed over the
    // coefficients in order from +0 (lane 3 picks up the next coefficient's red, and is not
    // read): the sums of e += Rgb(...) * y[c], without the shuffles GCC made of them.
    Float4 e = {0, 0, 0, 0};
#pragma GCC unroll 9
    for (int c = 0; c < sh::kCoeffs; ++c) e += load4(interp + 3 * c) * y[c];
    return Rgb(e[0], e[1], e[2]);
}

/// Trilinear blend of the 8 corner nodes of a cell (blendShCorners). `depth`: the corners'
/// depth moments (depth::kFloatsPerNode floats each) to weight them by (depth_weights.h), or
/// null for plain trilinear.
inline Rgb interpolateShCorners(const float* const corners[8], const float* const* depth, float fx, float fy, float fz,
                                const float y[sh::kCoeffs]) {
    float weights[8];
    trilinearWeights(fx, fy, fz, weights);
    if (depth) weightByDepth(weights, depth, fx, fy, fz);
    return blendShCorners(corners, weights, y);
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
