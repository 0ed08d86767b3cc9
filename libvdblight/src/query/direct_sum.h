// The direct part of an occlusion lookup, shared by OcclusionLookup and its streamed twin
// (occlusion_stream_lookup.cpp) so that both sum it alike.
// (Internal to the query module.)
#pragma once

#include <vector>

#include "vdblight/light/direct_light.h"

namespace vdblight::query_detail {

/// Each light's exact irradiance `exactOf(i, x, nd)` (nd: n normalised in double) into e[3 i ..
/// 3 i + 2]; true if any is not zero.
template <class Exact>
inline bool exactLights(std::size_t count, const Vec3d& x, const Vec3f& n, Exact&& exactOf, float* e) {
    const Vec3d nd = normalize(Vec3d(n));
    bool any = false;
    for (std::size_t i = 0; i < count; ++i) {
        const Rgb r = exactOf(i, x, nd);
        e[3 * i] = r.x, e[3 * i + 1] = r.y, e[3 * i + 2] = r.z;
        any = any || r != Rgb(0, 0, 0);
    }
    return any;
}

/// Sum over the lights of their exact irradiance e (exactLights) times their visibility v.
inline Rgb visibleSum(std::size_t count, const float* e, const float* v) {
    Rgb sum(0, 0, 0);
    for (std::size_t i = 0; i < count; ++i)
        if (v[i] > 0) sum += Rgb(e[3 * i], e[3 * i + 1], e[3 * i + 2]) * v[i];
    return sum;
}

/// Room for the per-light floats of exactLights and the visibility: inline up to 16 lights.
struct LightScratch {
    static constexpr std::size_t kInline = 16;
    float inlineVis[kInline], inlineExact[3 * kInline];  // not zeroed: each entry read is written first
    std::vector<float> many;
    float* v = inlineVis;
    float* e = inlineExact;
    explicit LightScratch(std::size_t count) {
        if (count > kInline) {
            many.resize(4 * count);
            v = many.data();
            e = v + count;
        }
    }
};

/// Sum over the `count` lights of their exact irradiance `exactOf(i, x, nd)` (nd: n normalised in
/// double) times the visibility `fill(v)` writes (one float per light). Each light's exact irradiance first: where the normal faces away from
/// every light (half of all normals, for a light on the ceiling) the visibility is not needed
/// at all. Adding a light's zero would not change the sum's bits, so skipping it gives the
/// same answer.
template <class Exact, class Fill>
inline Rgb directLight(std::size_t count, const Vec3d& x, const Vec3f& n, Exact&& exactOf, Fill&& fill) {
    LightScratch s(count);
    if (!exactLights(count, x, n, exactOf, s.e)) return Rgb(0, 0, 0);
    fill(s.v);
    return visibleSum(count, s.e, s.v);
}

}  // namespace vdblight::query_detail
