// The light module's API: light transport (RadianceEstimator, below) and a scene's lights
// (sceneLights, visibility, the runtime direct light: second part).
//
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

#include "vdblight/light/direct_light.h"
#include "vdblight/core/math.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

struct Scene;
class Tracer;
struct Hit;
class PunctualLightSampler;
class LightTree;

/// The default TransportOptions::maxBounces: a safety cap, not a truncation (issue 15).
/// Russian roulette ends paths without bias; its survival probability is at most
/// kRouletteMaxSurvival per reflection, so a path reaches 1024 reflections with probability
/// below 0.95^1021 ~ 2e-23: the cap only guards against a scene with albedo >= 1 everywhere.
constexpr int kSafetyBounces = 1024;
/// Largest survival probability of Russian roulette: bounds the mean path length to about
/// rouletteStart + 20 reflections even in a closed room of albedo 0.99 (the survivors'
/// weight then grows by 0.99 / 0.95 per reflection, which is unbiased).
constexpr float kRouletteMaxSurvival = 0.95f;

/// Lights whose direct light at the receiver a bake leaves out (`bake --direct runtime |
/// occlusion`, light/direct_light.h): light that reaches the gather point straight from these
/// emitters (emissive triangles hit by the first ray or sampled by the node's NEE, punctual
/// lights evaluated at the node). Their light at later path vertices stays: once reflected it
/// is indirect light. Built by receiverFilter (light/light.h).
struct ReceiverDirectFilter {
    std::vector<uint8_t> triangle;  ///< per scene triangle: 1 = leave its emission out
    std::vector<uint8_t> punctual;  ///< per punctual light (points, spots, directionals): 1 = leave out
    bool skipsTriangle(uint32_t t) const { return t < triangle.size() && triangle[t]; }
    bool skipsPunctual(int32_t i) const { return i >= 0 && std::size_t(i) < punctual.size() && punctual[i]; }
};

struct TransportOptions {
    /// Maximum number of diffuse reflections on a path from a light to the receiver:
    /// 0 = direct light only (emitters and sky seen directly), 1 = plus light reflected once...
    /// The default is a safety cap that no path reaches in practice (kSafetyBounces): Russian
    /// roulette decides where paths end, so no energy is lost. A small value truncates the
    /// series (biased dark by the missing bounces) and is for studies of single bounces.
    int maxBounces = kSafetyBounces;
    /// Reflection from which Russian roulette may end a path (unbiased: survivors are
    /// reweighted by 1 / survival). Survival = min(kRouletteMaxSurvival, largest component of
    /// the path throughput), the throughput carrying earlier reweighting, so it follows the
    /// albedo of the surfaces hit.
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
    /// How rays are traced, not what is computed: true = a gather node's first hits and
    /// all its shadow rays go to Embree in 16-ray packets (shadow rays deferred until a
    /// batch of paths is done; DeferredPaths); false = one ray at a time as each is needed
    /// (the reference path). Both give the same bits (node_batch_test).
    bool packetRays = true;
    /// Direct light left out at the receiver (null: everything is kept, `--direct baked`).
    std::shared_ptr<const ReceiverDirectFilter> skipAtReceiver;
    /// Emitter samples (NEE), each weighted 1 / n, where a cache ends the path at its first hit
    /// (the probe pass: SurfaceCache, `bake --probe-light-samples`); every other vertex takes
    /// one. The probe pass's path is one ray long, so the light sampled at its hit is a large
    /// share of the ray's variance, and a (deferred, packeted) shadow ray costs far less than
    /// the ray and the cache read: 3 samples took the office's `--quality fast` from 2.32 to
    /// 2.05 % RMS over ten seeds for about 6 % more time (docs/time_to_accuracy.md). Punctual
    /// lights are evaluated once, as at every vertex.
    int cacheEndLightSamples = 1;
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
    /// Where it came from: the emissive triangle, or the punctual light's index in the order
    /// points, spots, directionals (ReceiverDirectFilter); -1 if unknown.
    int32_t source = -1;
    bool punctual = false;  ///< source indexes punctual lights (else triangles)
};

/// Power-heuristic MIS weight of a sample drawn with pdf `a` against a strategy with pdf `b`.
inline float misWeight(float a, float b) {
    if (!(a > 0)) return 0.0f;
    const float a2 = a * a, b2 = b * b;
    return std::isinf(a2) ? 1.0f : a2 / (a2 + b2);
}

/// Paths gathered with their direct-light (NEE) shadow rays deferred, so that many shadow
/// rays can be traced together in packets: RadianceEstimator::gatherRadianceDeferred
/// appends a path's terms and shadow rays, trace() answers every shadow ray, then
/// radiance(i) adds path i's terms in the order gatherRadiance adds them (the same bits).
/// Callers may add shadow rays of their own (addShadowRay, blocked).
class DeferredPaths {
public:
    static constexpr uint32_t kNoShadowRay = 0xffffffffu;
    void clear();
    std::size_t pathCount() const { return pathEnd_.size(); }
    std::size_t shadowRayCount() const { return rays_.size(); }
    /// Appends a shadow ray (not counted: the caller counts it); returns its index.
    uint32_t addShadowRay(const Ray& ray);
    /// Traces every shadow ray added since clear() (Tracer::occluded in 16-ray packets).
    void trace(const Tracer& tracer);
    /// After trace(): whether shadow ray `index` is blocked.
    bool blocked(uint32_t index) const { return blocked_[index]; }
    /// After trace(): the radiance of the i-th gathered path.
    Rgb radiance(std::size_t i) const;
    /// The i-th path's directly hit emission (gatherRadiance's firstEmission).
    const Rgb& firstEmission(std::size_t i) const { return firstEmission_[i]; }

    /// With recordFirstVertices(true) (before the paths are added), each path that goes on
    /// past its first surface hit also keeps that vertex, so that after trace()
    /// firstVertexIrradiance gives an unbiased one-sample estimate of the irradiance of
    /// reflected light and sky there: pi x the radiance its continuation brought back (less
    /// the emission of an emitter it hits directly: NEE and MIS at the vertex take that), per
    /// unit albedo. What a SurfaceIrradianceCache holds, sampled where the surface is.
    void recordFirstVertices(bool on) { recordFirst_ = on; }
    /// False if path i kept no first vertex (no hit, no continuation, or not recorded).
    bool firstVertexIrradiance(std::size_t i, Vec3f& p, Vec3f& n, Rgb& irradiance) const;

private:
    friend class RadianceEstimator;
    struct Term {
        Rgb value;       ///< added as is (direct = false) or NEE weight (direct = true)
        Rgb throughput;  ///< direct: radiance += throughput * (unblocked ? value : 0) / pi
        uint32_t shadow; ///< direct: shadow ray index, kNoShadowRay if the sample gave nothing
        bool direct;
    };
    /// A path's first surface vertex: its continuation is terms [from, path end) but `skip`.
    struct FirstVertex {
        Vec3f p, n;
        Rgb albedo;
        uint32_t from = kNoShadowRay, skip = kNoShadowRay;  ///< kNoShadowRay: none
    };
    Rgb termValue(const Term& t) const;
    std::vector<Term> terms_;
    std::vector<FirstVertex> first_;  ///< per path, with recordFirst_
    bool recordFirst_ = false;
    std::vector<uint32_t> pathEnd_;  ///< end of each path's terms
    std::vector<Rgb> firstEmission_; ///< per path
    std::vector<Ray> rays_;
    std::unique_ptr<bool[]> blocked_;
    std::size_t blockedCapacity_ = 0;
};

/// Irradiance at a surface point from reflected light and the sky only: everything that
/// the estimator does not sample there itself by next-event estimation (emissive triangles
/// and punctual lights). With one set (RadianceEstimator::setSurfaceCache), a gathered path
/// ends at its first surface hit: there it takes NEE as usual, traces one cosine-distributed
/// ray only for the emitters' other MIS share (its emission, MIS-weighted), and adds
/// albedo / pi x the cache's irradiance for everything else, instead of continuing --
/// "probe-to-probe bounces" as in DDGI, the cache being an earlier pass's volume
/// (bake/surface_cache.h). Biased by how well the cache represents the light at the hit
/// point; it removes the variance of the rest of the path.
class SurfaceIrradianceCache {
public:
    virtual ~SurfaceIrradianceCache() = default;
    /// Irradiance of reflected light and sky at p (a point offset off a surface along its
    /// unit normal n, on the side rays arrive from). False if the cache has nothing valid
    /// there: the path then continues as without a cache (unbiased fallback).
    virtual bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const = 0;
};

/// Receives one-sample estimates of the irradiance of reflected light and sky at surface
/// points (DeferredPaths::firstVertexIrradiance): a cache built where the surfaces are.
/// Called from many threads at once.
class SurfaceSampleSink {
public:
    virtual ~SurfaceSampleSink() = default;
    virtual void add(const Vec3f& p, const Vec3f& n, const Rgb& irradiance) = 0;
};

class RadianceEstimator {
public:
    RadianceEstimator(const Scene& scene, const Tracer& tracer, TransportOptions options = {});

    /// Radiance arriving at `origin` along the ray leaving it in unit direction `dir`, which
    /// the caller drew with solid-angle pdf `dirPdf`. Emission of a directly hit emissive
    /// triangle is MIS-weighted against NEE (the caller's NEE sample carries the rest).
    /// If `firstHit` is given, it is the caller's result of tracing Ray{origin, dir} (already
    /// counted by the caller), which is used instead of tracing that ray again (the
    /// anti-aliased pass classifies origins with the same hits; bake_antialiased.h).
    /// If `firstEmission` is given, it receives the part of the result that is the directly
    /// hit emitter's MIS-weighted emission (0 if the ray does not hit an emitter): the rest is
    /// reflected light and sky, what a SurfaceIrradianceCache holds.
    Rgb gatherRadiance(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng, RayCount& rays,
                       const Hit* firstHit = nullptr, Rgb* firstEmission = nullptr) const;

    /// gatherRadiance with the shadow rays of its NEE samples at surface vertices deferred:
    /// traces the path's continuation rays now (counting every ray, shadow rays included),
    /// appends the path to `out`; out.radiance() after out.trace() equals gatherRadiance's
    /// result bit for bit (same random numbers, same arithmetic in the same order). The
    /// first hit must be given. Punctual lights are evaluated at once (not deferred).
    void gatherRadianceDeferred(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng, RayCount& rays,
                                const Hit& firstHit, DeferredPaths& out) const;

    /// sampleEmissiveTriangles without its shadow ray: fills `out` and the shadow ray to
    /// trace and returns true if the sample counts when that ray is not blocked; returns
    /// false (no ray to trace) where sampleEmissiveTriangles returns false before tracing.
    bool emissiveCandidate(const Vec3f& x, float u, float v, double w, LightSample& out, Ray& shadow,
                           const Vec3f* facing = nullptr) const;

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

    /// Ends gathered paths at their first surface hit with `cache` (SurfaceIrradianceCache);
    /// nullptr (the default) restores full path tracing. The cache must outlive its use.
    void setSurfaceCache(const SurfaceIrradianceCache* cache) { cache_ = cache; }
    const SurfaceIrradianceCache* surfaceCache() const { return cache_; }

    bool hasEmissiveTriangles() const { return !emitters_.empty(); }
    /// True if the bake leaves this sample at the receiver out (TransportOptions::skipAtReceiver).
    bool skipsAtReceiver(const LightSample& s) const {
        const ReceiverDirectFilter* f = options_.skipAtReceiver.get();
        return f && (s.punctual ? f->skipsPunctual(s.source) : f->skipsTriangle(uint32_t(s.source)));
    }
    const TransportOptions& options() const { return options_; }
    const Tracer& tracer() const { return tracer_; }

private:
    /// Irradiance at a surface point from one emitter sample, its value times `emitterScale`
    /// (1 / the samples taken there), plus every punctual light if `punctualToo`.
    Rgb directAtSurface(const Vec3f& p, const Vec3f& n, Rng& rng, RayCount& rays, float emitterScale = 1.0f,
                        bool punctualToo = true) const;
    /// The random numbers of one emitter sample at a surface vertex (directAtSurface).
    void drawEmitterSample(Rng& rng, float& u, float& v, double& w) const;
    /// The path walk shared by gatherRadiance (immediate NEE) and gatherRadianceDeferred.
    struct DeferredSink;
    template <typename Sink>
    void walkPath(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng, RayCount& rays,
                  const Hit* firstHit, Sink& sink) const;

    const Scene& scene_;
    const Tracer& tracer_;
    TransportOptions options_;
    const SurfaceIrradianceCache* cache_ = nullptr;
    std::vector<uint32_t> emitters_;   ///< emissive triangle ids
    std::vector<float> emitterCdf_;    ///< cumulative power, normalised to 1
    std::vector<float> emitterPmf_;    ///< per emitter, probability of choosing it
    std::vector<float> emitterArea_;
    std::vector<Vec3f> unitNormals_;   ///< per triangle, front-face orientation
    std::vector<int32_t> emitterOf_;   ///< per triangle, index into emitters_ or -1
    /// Per emitter, what emissiveCandidate reads (the same values as from the scene).
    struct EmitterData {
        Vec3f a, ab, ac;  ///< vertex 0 and the edges to vertices 1 and 2
        Vec3f normal;     ///< unit front normal
        Rgb emission;
        float area, pmf;
        bool twoSided;
    };
    std::vector<EmitterData> emitterData_;
    std::shared_ptr<const PunctualLightSampler> punctualSampler_;  ///< !orientedLightTree
    std::shared_ptr<const LightTree> punctualTree_;   ///< orientedLightTree; both null: lights exact
    std::shared_ptr<const LightTree> emitterTree_;    ///< null: the global power CDF
    /// Probability of choosing emitter e at x (tree or CDF).
    double emitterChoicePmf(std::size_t e, const Vec3f& x) const;
};

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The lights of a scene as a volume lists them (light/direct_light.h), each with what it is made of
// in the scene, and their visibility from a point by shadow rays (issue 15, `bake --direct`).
//
// Emissive triangles are grouped into polygon lights: triangles with one material that lie in
// one plane, face the same way and share edges form one light (the two triangles of a quad
// luminaire, the emitting face of a closed fixture box, a fan of a disk). Its boundary loops
// are the edges used by one triangle only; where they do not chain into closed loops (a
// T-junction), the light keeps its triangles as loops, which Lambert's formula sums exactly.

namespace vdblight {

struct Scene;
class Tracer;

/// A light of the scene and its parts.
struct SceneLight {
    DirectLight light;                ///< in the scene's local frame
    std::vector<uint32_t> triangles;  ///< polygon: its emissive triangles (ascending)
    std::vector<double> triangleCdf;  ///< polygon: cumulative area of `triangles`, last = 1
    /// Point / spot / directional: the index in the order points, spots, directionals
    /// (LightSample::source of the estimator's punctual samples); -1 for polygons.
    int32_t punctual = -1;
    /// Polygon / mesh not made of scene triangles (freeLight): its loops split into triangles,
    /// three vertices each, with the sign of each (-1: a triangle that cancels area, inside a
    /// hole or a concave corner). triangleCdf is then over these triangles' absolute areas.
    std::vector<Vec3f> ownTriangles;
    std::vector<float> ownSign;
    /// Polygon / mesh: the total (absolute) area the sample points are drawn over.
    double sampledArea = 0;
};

/// A light that is not part of the scene's triangles (one placed by a user, e.g. to relight a
/// PRT file): point, spot and directional lights as they are; a polygon's or mesh's loops
/// split into a fan of triangles each, whose signed areas sum to the light's region (holes and
/// non-convex loops included), so that lightVisibility and samplePolygonLight draw points on
/// the light itself. Its shadow rays stop short of the light as for a scene light.
SceneLight freeLight(const DirectLight& light);

/// A polygon light of one loop of four vertices (a quad) as `pieces` x `pieces` quads that tile
/// it (bilinear in the quad's corners, each loop in the quad's orientation), each a DirectLight
/// of the same radiance, normal and sides: their exact irradiance sums to the whole light's.
/// Any other light, or pieces < 2, comes back whole (one element). `bake --split-lights`
/// (bake/each_pass.h: DirectOptions::splitLights) lists the pieces instead of the light, so
/// that each gets its own visibility.
std::vector<DirectLight> splitQuadLight(const DirectLight& light, int pieces);

/// A point on a polygon or mesh light for the unit-square point (u, v), as lightVisibility
/// draws them: u picks a triangle by area and is rescaled to [0, 1) inside it (a stratified
/// set of (u, v) stays stratified over the whole light), then (u, v) is a uniform point of
/// that triangle. `normal`: the light's front normal there; `sign`: -1 on a triangle of a free
/// light that cancels area, else 1. `scene` is read only for a light made of scene triangles.
struct PolygonLightPoint {
    Vec3f position;
    Vec3f normal;
    float sign = 1;
};
PolygonLightPoint samplePolygonLight(const SceneLight& light, const Scene* scene, float u, float v);

/// Every light of the scene, in a fixed order: polygons (by smallest triangle index), then
/// point, spot and directional lights in scene order. The sky is not a light here: it stays
/// in the volume's basis in every mode.
std::vector<SceneLight> sceneLights(const Scene& scene);

/// Fraction of `light`'s contribution at x that is not blocked: 0 or 1 for point, spot and
/// directional lights (one shadow ray); for a polygon the weighted mean over `samples`
/// stratified points on its area, each weighted by its share of the light's solid angle
/// (|cos at the light| / d^2) and, if `normal` is given, by the receiver's cosine. This is
/// the ratio of shadowed to unshadowed irradiance that a lookup multiplies exactIrradiance by.
/// The points depend only on `stream` (determinism). Returns 1 when no sample carries weight.
double lightVisibility(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, uint32_t samples,
                       uint64_t stream, RayCount& rays, const Vec3f* normal = nullptr);

/// Direct irradiance at x for the unit normal n from one light with its shadows:
/// exactIrradiance times lightVisibility with the receiver's cosine (`samples` shadow rays for
/// a polygon light, one for a point, spot or directional light; none where the light does not
/// reach the normal's side). `onSurface`: x lies on a surface facing n, so the shadow rays
/// start just off it (offsetRayOrigin) rather than at x. x and n in the scene's local frame.
Rgb shadowedIrradiance(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, const Vec3f& n,
                       uint32_t samples, uint64_t stream, RayCount& rays, bool onSurface = false);

/// Direct irradiance at x for the unit normal n from `lights` with their shadows, as a run
/// time adds it to a `--direct runtime` volume: shadowedIrradiance summed over the lights
/// (light i with stream hashCombine(stream, i)). x and n in the scene's local frame.
Rgb runtimeDirectIrradiance(const Scene& scene, const Tracer& tracer, const std::vector<SceneLight>& lights,
                            const Vec3f& x, const Vec3f& n, uint32_t samples, uint64_t stream, RayCount& rays);

/// The filter that leaves the direct light of `lights` at the receiver out of a bake
/// (TransportOptions::skipAtReceiver): their triangles and punctual indices.
std::shared_ptr<const ReceiverDirectFilter> receiverFilter(const Scene& scene, const std::vector<SceneLight>& lights);

}  // namespace vdblight
