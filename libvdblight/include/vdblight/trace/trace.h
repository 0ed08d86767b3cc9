// Ray tracing against a Scene's triangles with Embree 3.
//
// One Tracer owns one Embree device and one committed scene; it is immutable after
// construction and safe to use from any number of threads.
#pragma once

#include <cstdint>
#include <memory>

#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;

struct Ray {
    Vec3f origin;
    Vec3f direction;  ///< need not be unit length; t is measured in its units
    float tnear = 0.0f;
    float tfar = std::numeric_limits<float>::infinity();
};

struct Hit {
    static constexpr uint32_t kNone = 0xffffffffu;
    uint32_t triangle = kNone;  ///< index into Scene triangles, kNone on a miss
    float t = std::numeric_limits<float>::infinity();
    float u = 0, v = 0;         ///< barycentrics of vertex 1 and 2
    Vec3f geometricNormal;      ///< unnormalised (p1 - p0) x (p2 - p0)

    bool hit() const { return triangle != kNone; }
};

struct TracerOptions {
    /// Embree's robust (watertight) intersection mode. false = its faster default mode, which
    /// may let a ray slip through an edge between triangles: other bits, ~14 % less bake CPU
    /// time on the paper configuration (vdblight_bench_bake_speed). An option, not the default.
    bool robust = true;
};

class Tracer {
public:
    /// Builds the BVH (high quality build). Throws Error if Embree reports one.
    explicit Tracer(const Scene& scene, TracerOptions options = {});
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    /// Closest hit along the ray within [tnear, tfar].
    Hit intersect(const Ray& ray) const;
    /// True if anything blocks the ray within [tnear, tfar].
    bool occluded(const Ray& ray) const;
    /// blocked[i] = occluded(rays[i]) for i < count, traced as 16-ray packets
    /// (rtcOccluded16): the same answers, less per-ray overhead for rays that share an end.
    void occluded(const Ray* rays, std::size_t count, bool* blocked) const;

    /// hits[i] = intersect(rays[i]) for i < count, traced as 16-ray packets (rtcIntersect16,
    /// incoherent mode): the same hits bit for bit (trace_packet_test), less per-ray overhead.
    void intersect(const Ray* rays, std::size_t count, Hit* hits) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Offsets a ray origin off a surface along its normal so that it does not self-intersect,
/// scaled to the magnitude of the coordinates (float rounding grows with it).
Vec3f offsetRayOrigin(const Vec3f& p, const Vec3f& unitNormal, const Vec3f& towards);

}  // namespace vdblight
