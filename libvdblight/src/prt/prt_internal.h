// Pieces shared by the PRT bake and relight files.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "vdblight/prt.h"
#include "vdblight/trace.h"

namespace vdblight::prt_detail {

/// Shadow rays to a point light end just short of it (as radiance_estimator.cpp).
constexpr float kShadowEnd = 1.0f - 1e-4f;

inline int threadCount(int threads) { return threads > 0 ? threads : tbb::this_task_arena::max_concurrency(); }

/// f(i) for i in [0, n) on `threads` threads; each i writes only its own outputs.
template <typename F>
void parallelFor(std::size_t n, int threads, F&& f) {
    tbb::task_arena arena(threadCount(threads));
    arena.execute([&] { tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); }); });
}

/// True if the segment between two surface points (each offset along its normal) is free.
inline bool visibleBetween(const Tracer& tracer, const Vec3f& p, const Vec3f& np, const Vec3f& q, const Vec3f& nq) {
    const Vec3f a = offsetRayOrigin(p, np, q - p);
    const Vec3f b = offsetRayOrigin(q, nq, p - q);
    Ray ray{a, b - a, 0.0f, 0.9999f};
    return !tracer.occluded(ray);
}

/// True if a point light at `l` reaches the surface point (p, n) (n faces it).
inline bool visibleToLight(const Tracer& tracer, const Vec3f& p, const Vec3f& n, const Vec3f& l) {
    const Vec3f a = offsetRayOrigin(p, n, l - p);
    Ray ray{a, l - a, 0.0f, 0.9999f};
    return !tracer.occluded(ray);
}

/// Direct irradiance per unit intensity from a point at l (cos / d^2, no visibility), or 0
/// behind the surface. Also the local direction and distance if asked.
inline float unshadowedUnit(const Vec3f& p, const Vec3f& n, const Vec3f& l, float* dist = nullptr) {
    const Vec3f w = l - p;
    const float d2 = dot(w, w);
    if (d2 <= 0.0f) return 0.0f;
    const float d = std::sqrt(d2);
    const float c = dot(n, w) / d;
    if (dist) *dist = d;
    return c > 0.0f ? c / d2 : 0.0f;
}

}  // namespace vdblight::prt_detail

namespace vdblight {
/// Fills prt.transfer (and prt.volumeTransfer for prt.volumeGrid if `volume`) with
/// `bounces` diffuse bounces from the light bases (multi_bounce.cpp).
void bakeMultiBounceTransfer(PrtData& prt, const Tracer& tracer, int bounces, bool volume, bool normalise,
                             int threads, Interrupter* interrupter);
}  // namespace vdblight
