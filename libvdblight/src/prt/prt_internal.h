// Pieces shared by the PRT bake and relight files.
#pragma once

#include "../core/parallel_for.h"  // relative: tests include this header too

#include "vdblight/prt/prt.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight::prt_detail {

/// f(i) for i in [0, n) on `threads` threads, each i writing only its own outputs (core/parallel_for.h).
using core::parallelFor;
using core::threadCount;

/// True if the segment between two surface points (each offset along its normal) is free.
inline bool visibleBetween(const Tracer& tracer, const Vec3f& p, const Vec3f& np, const Vec3f& q, const Vec3f& nq) {
    const Vec3f a = offsetRayOrigin(p, np, q - p);
    const Vec3f b = offsetRayOrigin(q, nq, p - q);
    Ray ray{a, b - a, 0.0f, 0.9999f};
    return !tracer.occluded(ray);
}

/// Direct irradiance per unit intensity from a point at l (cos / d^2, no visibility), or 0
/// behind the surface, as the compressed path evaluates it (float). Also the distance if asked.
inline float unshadowedUnit(const Vec3f& p, const Vec3f& n, const Vec3f& l, float* dist = nullptr) {
    const Vec3f w = l - p;
    const float d2 = dot(w, w);
    if (d2 <= 0.0f) return 0.0f;
    const float d = std::sqrt(d2);
    const float c = dot(n, w) / d;
    if (dist) *dist = d;
    return c > 0.0f ? c / d2 : 0.0f;
}

/// Sender j as seen from the volume node x: omega = its solid angle, sh[m] = the integral of
/// Y_m over it (solid angle times Y of the direction), visibility by one ray to its centre.
/// A sender closer than 4 disk radii is split into 4 x 4 equal-area sub-disks (concentric
/// map) so that nodes near a surface see its true directions. False if it is hidden.
inline bool senderShFromNode(const SurfaceSamples& s, const Tracer& tracer, const Vec3f& x, std::size_t j,
                             float sh[sh::kCoeffs], float& omega) {
    const Vec3f& p = s.position[j];
    const Vec3f& m = s.normal[j];
    omega = diskSolidAngle(x, p, m, s.area[j]);
    if (omega <= 0.0f) return false;
    const Vec3f q = offsetRayOrigin(p, m, x - p);
    if (tracer.occluded(Ray{x, q - x, 0.0f, 0.9999f})) return false;
    const float radius = std::sqrt(s.area[j] * float(kInvPi));
    const Vec3f w = q - x;
    if (dot(w, w) >= 16.0f * radius * radius) {
        sh::evalUnrolled(normalize(w), sh);
        for (int k = 0; k < sh::kCoeffs; ++k) sh[k] *= omega;
        return true;
    }
    constexpr int kSub = 4;
    Vec3f t1, t2;
    orthonormalBasis(m, t1, t2);
    float y[sh::kCoeffs];
    for (int k = 0; k < sh::kCoeffs; ++k) sh[k] = 0.0f;
    omega = 0.0f;
    for (int a = 0; a < kSub * kSub; ++a) {
        float dx, dy;
        concentricSquareToDisk((float(a % kSub) + 0.5f) / kSub, (float(a / kSub) + 0.5f) / kSub, dx, dy);
        const Vec3f c = q + (t1 * dx + t2 * dy) * radius;
        const float o = diskSolidAngle(x, c, m, s.area[j] / float(kSub * kSub));
        if (o <= 0.0f) continue;
        sh::evalUnrolled(normalize(c - x), y);
        for (int k = 0; k < sh::kCoeffs; ++k) sh[k] += o * y[k];
        omega += o;
    }
    return omega > 0.0f;
}

/// Rows of a sparse matrix: row r holds, for columns column[begin[r] .. begin[r+1]) in
/// ascending order, `width` weights each (weight[k * width ...]).
struct SparseRows {
    int width = 1;
    std::vector<std::size_t> begin{0};
    std::vector<uint32_t> column;
    std::vector<float> weight;
    std::size_t rows() const { return begin.size() - 1; }
};

/// Sample-to-sample form factors from `rays` stratified cosine-distributed rays per sample
/// (rounded up to a square), each hit assigned to the sample standing for the hit point
/// (sampled_form_factors.cpp). Width 1: the irradiance at r per unit radiance leaving j.
SparseRows sampledSampleFormFactors(const SurfaceSamples& s, const Tracer& tracer, uint32_t rays, bool normalise,
                                    uint64_t seed, int threads, Interrupter* in);

/// Node-to-sample SH gather from `rays` stratified uniform rays per node. Width 9: the SH
/// order-2 projection, at node r, of unit radiance leaving sender j.
SparseRows sampledNodeGather(const SurfaceSamples& s, const Tracer& tracer, const std::vector<Vec3f>& nodes,
                             uint32_t rays, bool normalise, uint64_t seed, int threads, Interrupter* in);

}  // namespace vdblight::prt_detail

namespace vdblight {
/// One point emitter of the PRT's relighting: a light as the compressed visibility sees it.
/// Intensity towards a receiver in unit direction w (light -> receiver) per unit light value:
/// weight, times dot(normal, w) for a cosine emitter (|.| if twoSided; 0 behind a one-sided
/// one), times spotFalloff for a spot.
struct PrtPointLight {
    Vec3f position;
    Vec3f normal{0, 0, 0};   ///< cosine emitter's front; zero: isotropic
    float weight = 1.0f;     ///< point, spot: 1; polygon point: its signed share of the area
    bool twoSided = false;
    const DirectLight* spot = nullptr;  ///< a spot light: its falloff (outlives this point)
    /// The intensity factor towards w (unit, from the light); 0: none.
    float emission(const Vec3f& w) const;
};

/// The PRT discretisation of a light, in one place: a point or spot light is one point; a
/// polygon or mesh areaSamples^2 cosine emitters (twoSided as the light), each weighted by
/// its share of the area: the cell centres of an areaSamples x areaSamples grid on a
/// parallelogram (a square panel: squareLight), else stratified points of the light's
/// triangles (samplePolygonLight of scene_lights.h with the grid's cell centres; a free
/// light's cancelling triangles weigh negatively). Throws ValueError for a directional light.
std::vector<PrtPointLight> pointEmitters(const DirectLight& light, int areaSamples);

/// The compressed direct unit irradiance (prtDirectLight) of the lights, summed per light
/// colour (DirectLight::value, in order of first appearance): lights of one colour share one
/// projection and transfer (relight.cpp).
std::vector<std::pair<Rgb, std::vector<float>>> directByColour(const PrtData& prt, const std::vector<DirectLight>& lights,
                                                                 int areaSamples);

/// The example lights of the direct-light basis: trainingLightPositions(count + extra) with
/// extra = round(count * orientedFraction); the first `count` are isotropic points (the
/// paper's), the rest one-sided cosine emitters (unit intensity along the normal) facing away
/// from the nearest surface hit by the six axis rays from the position (a lamp on a wall or a
/// ceiling), or along the Halton (bases 7, 11) sphere direction if no axis ray hits.
std::vector<PrtPointLight> trainingLights(const Scene& scene, const Tracer& tracer, uint32_t count,
                                          float orientedFraction);

/// The light-basis coefficients of every cluster for a direct unit irradiance (stride values
/// per cluster, [0] = 1 for the mean vector, 0 if the mean is zero) (relight.cpp).
void projectLightBases(const PrtData& prt, const std::vector<float>& direct, std::vector<float>& coeffs);

/// Fills prt.transfer (and prt.volumeTransfer for prt.volumeGrid if `volume`) with
/// `bounces` diffuse bounces from the light bases (multi_bounce.cpp).
/// `formFactorRays` = 0: every sample pair with one visibility ray (sampleFormFactors);
/// otherwise sampled form factors with that many rays per receiver (seeded by `seed`).
void bakeMultiBounceTransfer(PrtData& prt, const Tracer& tracer, int bounces, bool volume, bool normalise,
                             uint32_t formFactorRays, uint64_t seed, int threads, Interrupter* interrupter);
}  // namespace vdblight
