// Light transport: the radiance L(x, w) that a volume stores, estimated by path tracing
// with next-event estimation (NEE).
//
// The estimator splits incident radiance at a point into two parts that are estimated
// differently and never counted twice:
//  - direct light from emitters: emissive triangles (sampled by area, chosen in proportion
//    to power), punctual lights (point, spot, directional; delta distributions, evaluated
//    exactly with one shadow ray each, or -- with many point/spot lights -- one of them
//    chosen per vertex by a light tree, see TransportOptions::exactLightLimit);
//  - everything else: light reflected by surfaces (recursively, with NEE at every bounce)
//    and the sky where rays escape. Gathered by tracing rays in chosen directions.
// Emissive triangles are reached both ways: by NEE samples and by gathered rays that hit
// them. The two are combined by multiple importance sampling (power heuristic), so that
// small lights converge through NEE and large, near lights (a white furnace's walls)
// through the gathered rays, without counting anything twice.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "vdblight/math.h"
#include "vdblight/sampling.h"

namespace vdblight {

struct Scene;
class Tracer;
struct Hit;
class PunctualLightSampler;
class LightTree;

struct TransportOptions {
    /// Maximum number of diffuse reflections on a path from a light to the receiver:
    /// 0 = direct light only (emitters and sky seen directly), 1 = plus light reflected once...
    int maxBounces = 8;
    /// Bounce from which Russian roulette may end a path (unbiased: survivors are reweighted).
    int rouletteStart = 3;
    /// Scenes with at most this many point + spot lights evaluate every one of them exactly
    /// (one shadow ray each) at every vertex. Above it, each vertex picks ONE of them with
    /// the power- and distance-aware sampler of light/punctual_sampler.h (unbiased; cost per
    /// vertex independent of the light count). Directional lights are always exact.
    uint32_t exactLightLimit = 16;
    /// Light selection among many (light/light_tree.h): true = a tree with orientation cones
    /// whose importance accounts for distance, power, emission direction and, at surface
    /// vertices, the receiver's normal, used for point/spot lights above exactLightLimit and
    /// for emissive triangles above emitterTreeMin; false = the earlier tree for point/spot
    /// lights (power / distance only) and the global power CDF for emissive triangles (kept
    /// for the before/after comparison in vdblight_bench_converge).
    bool orientedLightTree = true;
    /// Scenes with more emissive triangles than this, spread over a box at least 8 times their
    /// mean size, choose the one to sample with the light tree at each point; others use the
    /// global power CDF (position-independent; better for one compact tessellated emitter).
    uint32_t emitterTreeMin = 16;
};

/// Counts rays per calling context; summed deterministically by the caller.
struct RayCount {
    uint64_t intersect = 0;
    uint64_t occluded = 0;
    uint64_t total() const { return intersect + occluded; }
    RayCount& operator+=(const RayCount& o) { intersect += o.intersect; occluded += o.occluded; return *this; }
};

/// One direct-light sample at a point: light arrives *from* `direction` (unit) and
/// `weight` = L / pdf, so that sum(weight * g(direction)) / N estimates the integral of
/// L_direct * g over the sphere. For delta lights the pdf is a delta and the weight is the
/// irradiance at normal incidence.
struct LightSample {
    Vec3f direction;
    Rgb weight;
    float pdf = 0;  ///< solid-angle pdf of the light sampling (0 for delta lights)
};

/// Power-heuristic MIS weight of a sample drawn with pdf `a` against a strategy with pdf `b`.
inline float misWeight(float a, float b) {
    if (!(a > 0)) return 0.0f;
    const float a2 = a * a, b2 = b * b;
    return std::isinf(a2) ? 1.0f : a2 / (a2 + b2);
}

class RadianceEstimator {
public:
    RadianceEstimator(const Scene& scene, const Tracer& tracer, TransportOptions options = {});

    /// Radiance arriving at `origin` along the ray leaving it in unit direction `dir`, which
    /// the caller drew with solid-angle pdf `dirPdf`. Emission of a directly hit emissive
    /// triangle is MIS-weighted against NEE (the caller's NEE sample carries the rest).
    /// If `firstHit` is given, it is the caller's result of tracing Ray{origin, dir} (already
    /// counted by the caller), which is used instead of tracing that ray again (the
    /// anti-aliased pass classifies origins with the same hits; bake_antialiased.h).
    Rgb gatherRadiance(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng, RayCount& rays,
                       const Hit* firstHit = nullptr) const;

    /// One NEE sample of emissive triangles as seen from a point in free space, using the
    /// stratified pair (u, v) for the point on the light and `w` to choose the triangle.
    /// The weight is L / pdf *without* MIS weight; the caller applies
    /// misWeight(out.pdf, its own direction pdf).
    /// Returns false if there are no emissive triangles or the sample is occluded/back-facing.
    /// `w` is a double so that a tree over thousands of triangles can use 53 bits of it.
    /// If `facing` is given (the normal of a receiving surface), a sample with
    /// dot(*facing, direction) <= 0 is rejected before its shadow ray: it would add 0 there.
    bool sampleEmissiveTriangles(const Vec3f& x, float u, float v, double w, LightSample& out,
                                 RayCount& rays, const Vec3f* facing = nullptr) const;

    /// Appends the exactly evaluated, unoccluded punctual lights at free-space point x.
    /// With `skipSampled`, the point and spot lights are left out when samplesPunctualLights()
    /// (the caller adds samplePunctualLight() per sample instead).
    void punctualLights(const Vec3f& x, std::vector<LightSample>& out, RayCount& rays,
                        bool skipSampled = false) const;

    /// True when the scene has more point + spot lights than options().exactLightLimit.
    bool samplesPunctualLights() const { return bool(punctualSampler_) || bool(punctualTree_); }
    /// Number of point + spot lights in the scene.
    std::size_t pointAndSpotLightCount() const;
    /// One sample of the point and spot lights at x with u in [0, 1): one light chosen by
    /// the many-light sampler, weight = its irradiance at normal incidence / pmf (pdf = 0:
    /// a delta). False if the chosen light is occluded, dark or behind its spot cone.
    /// At a surface, `normal` (unit, the side that receives) lets the oriented tree skip lights
    /// behind it; in free space pass nullptr.
    bool samplePunctualLight(const Vec3f& x, double u, LightSample& out, RayCount& rays,
                             const Vec3f* normal = nullptr) const;

    /// Solid-angle pdf with which sampleEmissiveTriangles picks the point at distance t
    /// along unit direction dir from x on triangle `tri` (0 if it is not an emitter). With an
    /// emitter tree the choice depends on x: pass it (nullptr only without a tree).
    float emitterPdf(uint32_t tri, float t, const Vec3f& dir, const Vec3f* x = nullptr) const;
    /// True when emissive triangles are chosen by the light tree (emitterTreeMin).
    bool usesEmitterTree() const { return bool(emitterTree_); }
    /// Emitted radiance of triangle `tri` towards -dir (0 from a one-sided emitter's back).
    Rgb emittedRadiance(uint32_t tri, const Vec3f& dir) const;

    bool hasEmissiveTriangles() const { return !emitters_.empty(); }
    const TransportOptions& options() const { return options_; }

private:
    Rgb directAtSurface(const Vec3f& p, const Vec3f& n, Rng& rng, RayCount& rays) const;

    const Scene& scene_;
    const Tracer& tracer_;
    TransportOptions options_;
    std::vector<uint32_t> emitters_;   ///< emissive triangle ids
    std::vector<float> emitterCdf_;    ///< cumulative power, normalised to 1
    std::vector<float> emitterPmf_;    ///< per emitter, probability of choosing it
    std::vector<float> emitterArea_;
    std::vector<Vec3f> unitNormals_;   ///< per triangle, front-face orientation
    std::vector<int32_t> emitterOf_;   ///< per triangle, index into emitters_ or -1
    std::shared_ptr<const PunctualLightSampler> punctualSampler_;  ///< !orientedLightTree
    std::shared_ptr<const LightTree> punctualTree_;   ///< orientedLightTree; both null: lights exact
    std::shared_ptr<const LightTree> emitterTree_;    ///< null: the global power CDF
    /// Probability of choosing emitter e at x (tree or CDF).
    double emitterChoicePmf(std::size_t e, const Vec3f& x) const;
};

}  // namespace vdblight
