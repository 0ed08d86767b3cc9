// The sampling of one point-gather node, split into ranges of samples so that a node can
// be sampled in rounds (the error-targeted bake, bake_adaptive.h) with exactly the samples
// and sums of the fixed-budget bake: after samples [0, N) the coefficients have the same
// bits as projectIncidentRadiance with N rays.
//
// Besides the SH sums it keeps the first two moments of each sample's estimate of the
// node's mean irradiance over all normals, Ebar = (1/4) * integral of L over the sphere
// (luminance). Ebar is exactly the SH DC term's irradiance (pi * Y00 * L00), so it has no
// SH truncation error, and its per-sample estimate is pi * lum(L_i) + lum(NEE_i) / 4
// (+ lum(punctual_i) / 4 when punctual lights are sampled).
//
// A sampler may also project the same samples into another basis (projectAlsoInto, e.g.
// sh:4 through the Basis interface): the SH order-2 sums stay, for the error estimate and
// the probe passes' reflected light, and the stored values come from the other basis.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "direction_guide.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/light/light.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight::detail {

class NodeSampler {
public:
    // Independent scrambles for the sample dimensions of one node.
    enum Dimension : uint64_t { kDirection = 1, kLightPoint = 2, kLightChoice = 3, kPath = 4, kPunctual = 5 };

    /// `plannedRays`: the most samples this node will take. At the node itself, point and
    /// spot lights are sampled (one per sample) only if the estimator samples them and there
    /// are more of them than planned samples; otherwise each costs one shadow ray, once.
    NodeSampler(const RadianceEstimator& estimator, const Vec3f& x, uint64_t seed, uint64_t streamIndex,
                uint32_t plannedRays)
        : estimator_(estimator), x_(x), stream_(hashCombine(seed, streamIndex)), rng_(stream_, kPath),
          sampledLights_(estimator.samplesPunctualLights() && estimator.pointAndSpotLightCount() > plannedRays),
          lightOffset_(toUnitDouble(hashCombine(stream_, kLightChoice))),
          punctualOffset_(toUnitDouble(hashCombine(stream_, kPunctual))) {}

    /// Also record every sample's first hit in `acc` (depth_moments.h; `spacing`: the node's
    /// level spacing). The rays are the ones traced anyway: no extra rays, the same bits.
    void recordDepth(depth::Accumulator* acc, double spacing) {
        depth_ = acc;
        depthSpacing_ = spacing;
    }

    /// Also give every path's first-vertex irradiance sample to `sink` (light.h; packeted
    /// sampling only). The rays are the ones traced anyway.
    void recordSurface(SurfaceSampleSink* sink) { surface_ = sink; }

    /// Only the surface samples are wanted, not the node's values (extra_cache_paths.h): the
    /// node's own light samples, their shadow rays and the sums are skipped. The paths, and so
    /// the surface samples, stay the same (their random numbers are not the light samples').
    void recordSurfaceOnly(SurfaceSampleSink* sink) {
        surface_ = sink;
        surfaceOnly_ = true;
    }

    /// Also add every sample's gathered luminance to its direction cell (DirectionGuide::kCells
    /// sums and counts, direction_guide.h): the map a later pass's guide is built from. The
    /// rays are the ones traced anyway.
    void recordGuide(float* luminanceSums, uint32_t* counts) {
        guideSums_ = luminanceSums;
        guideCounts_ = counts;
    }

    /// Draw the directions from `guide` instead of uniformly (direction_guide.h): each sample
    /// weighted by the inverse of the guide's density, and the emitters' MIS weights from the
    /// guided pdf. Null: uniform (the same bits as without the call).
    void guideDirections(const bake_detail::DirectionGuide* guide) { guide_ = guide; }

    /// Also accumulate every sample into `basis` (basis.h; kept for the node's lifetime), whose
    /// values basisValues() returns. Call before the first addSamples. The exact punctual
    /// lights' sums are allocated only by a light that reaches the node (exactEbar): a sampler
    /// kept between two rounds (first_pass_by_error.h) holds a fifth less memory.
    void projectAlsoInto(const Basis* basis) {
        basis_ = basis;
        if (!basis) return;
        for (std::vector<Rgbd>* acc : {&basisDir_, &basisLight_}) acc->assign(basis->accumulatorSize(), Rgbd(0, 0, 0));
    }

    /// Adds samples [first, last) (sample numbers of the node's stratified sequence; rounds
    /// must be consecutive starting at 0). Optional first-hit tracing as in bake.h.
    /// With TransportOptions::packetRays the rays go to Embree in packets (addSamplesPacketed),
    /// otherwise one at a time (addSamplesOneByOne, the reference); the same bits either way.
    void addSamples(uint32_t first, uint32_t last, RayCount& count, const Tracer* tracer = nullptr,
                    uint32_t* backFaceHits = nullptr) {
        if (estimator_.options().packetRays) {
            for (uint32_t b = first; b < last; b += kBatch)
                addSamplesPacketed(b, std::min(last, b + kBatch), count, backFaceHits);
        } else {
            addSamplesOneByOne(first, last, count, tracer, backFaceHits);
        }
        samples_ = last;
    }

    /// The reference: each sample's rays traced one at a time, as each is needed.
    void addSamplesOneByOne(uint32_t first, uint32_t last, RayCount& count, const Tracer* tracer,
                            uint32_t* backFaceHits) {
        float y[sh::kCoeffs];
        const bool nee = estimator_.hasEmissiveTriangles();
        constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
        for (uint32_t i = first; i < last; ++i) {
            // Reflected light and sky: stratified directions, uniform over the sphere.
            float u, v;
            sobol02(i, hashCombine(stream_, kDirection), u, v);
            const float density = guide_ ? guide_->warp(u, v) : 1.0f;
            const float dirPdf = kSpherePdf * density;
            const Vec3f dir = uniformSphere(u, v);
            Rgb l, emitted;
            if ((tracer && backFaceHits) || depth_) {
                ++count.intersect;
                const Hit hit = (tracer ? *tracer : estimator_.tracer()).intersect(Ray{x_, dir});
                if (backFaceHits && hit.hit() && dot(hit.geometricNormal, dir) > 0.0f) ++*backFaceHits;
                if (depth_) depth_->add(dir, hit.hit() ? hit.t : std::numeric_limits<float>::infinity(), depthSpacing_);
                l = estimator_.gatherRadiance(x_, dir, dirPdf, rng_, count, &hit, &emitted);
            } else {
                l = estimator_.gatherRadiance(x_, dir, dirPdf, rng_, count, nullptr, &emitted);
            }
            recordGuideSample(u, v, l);
            if (guide_) {  // the guided sample's weight (1 / density); unguided samples keep their bits
                l = l * (1.0f / density);
                emitted = emitted * (1.0f / density);
            }
            sh::evalUnrolled(dir, y);
            addGathered(dir, l, emitted, y);
            double ebar = kPi * double(luminance(l));
            // Emissive triangles: one NEE sample per ray, stratified on the light too.
            if (nee) {
                sobol02(i, hashCombine(stream_, kLightPoint), u, v);
                double w = radicalInverse(3, i) + lightOffset_;
                w -= std::floor(w);
                LightSample s;
                Ray shadow;  // a light the bake leaves out at the node costs no shadow ray
                if (estimator_.emissiveCandidate(x_, u, v, float(w), s, shadow) && !estimator_.skipsAtReceiver(s) &&
                    (++count.occluded, !estimator_.tracer().occluded(shadow))) {
                    sh::evalUnrolled(s.direction, y);
                    const Rgb weight = s.weight * misWeight(s.pdf, directionPdf(s.direction));
                    addLight(s.direction, weight, y);
                    ebar += 0.25 * double(luminance(weight));
                }
            }
            // Many punctual lights: one chosen per sample (light.h), stratified choice.
            if (sampledLights_) {
                double w = radicalInverse(5, i) + punctualOffset_;
                w -= std::floor(w);
                LightSample s;
                if (estimator_.samplePunctualLight(x_, w, s, count) && !estimator_.skipsAtReceiver(s)) {
                    sh::evalUnrolled(s.direction, y);
                    addLight(s.direction, s.weight, y);
                    ebar += 0.25 * double(luminance(s.weight));
                }
            }
            ebarSum_ += ebar;
            ebarSquares_ += ebar * ebar;
        }
    }

    /// The same samples with the rays batched: the first hits of up to kBatch samples in
    /// packets from the node; their paths walked in sample order (continuation rays one at a
    /// time: each depends on the last), every NEE shadow ray (the node's and the surface
    /// vertices') deferred and then traced in packets; then the sums in sample order with
    /// the arithmetic of addSamplesOneByOne. The first hits are always traced here (the same
    /// hits as gatherRadiance's own), so back faces can always be counted.
    void addSamplesPacketed(uint32_t first, uint32_t last, RayCount& count, uint32_t* backFaceHits) {
        const uint32_t n = last - first;
        const bool nee = estimator_.hasEmissiveTriangles() && !surfaceOnly_;
        constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
        const uint64_t dirScramble = mix64(hashCombine(stream_, kDirection));  // sobol02's, once
        const uint64_t lightScramble = mix64(hashCombine(stream_, kLightPoint));
        thread_local Scratch scratch;  // reused: no allocations per node
        scratch.resize(n);
        Vec3f* dirs = scratch.dirs.data();
        Ray* rays = scratch.rays.data();
        Hit* hits = scratch.hits.data();
        float* density = scratch.density.data();
        uint16_t* cell = scratch.cell.data();
        for (uint32_t k = 0; k < n; ++k) {
            float u, v;
            sobol02Mixed(first + k, dirScramble, u, v);
            density[k] = guide_ ? guide_->warp(u, v) : 1.0f;
            if (guideSums_) cell[k] = uint16_t(bake_detail::DirectionGuide::cellOf(u, v));
            dirs[k] = uniformSphere(u, v);
            rays[k] = Ray{x_, dirs[k]};
        }
        count.intersect += n;
        estimator_.tracer().intersect(rays, n, hits);
        if (backFaceHits)
            for (uint32_t k = 0; k < n; ++k)
                if (hits[k].hit() && dot(hits[k].geometricNormal, dirs[k]) > 0.0f) ++*backFaceHits;
        if (depth_)
            for (uint32_t k = 0; k < n; ++k)
                depth_->add(dirs[k], hits[k].hit() ? hits[k].t : std::numeric_limits<float>::infinity(), depthSpacing_);

        thread_local DeferredPaths paths_;  // reused: no allocations per node
        paths_.clear();
        paths_.recordFirstVertices(surface_ != nullptr);
        // The node's own NEE samples (no random numbers from rng_: any order is the same).
        LightSample* lights = scratch.lights.data();
        uint32_t* lightRay = scratch.lightRay.data();
        for (uint32_t k = 0; k < n; ++k) {
            lightRay[k] = DeferredPaths::kNoShadowRay;
            if (!nee) continue;
            float u, v;
            sobol02Mixed(first + k, lightScramble, u, v);
            double w = radicalInverseOf<3>(first + k) + lightOffset_;
            w -= std::floor(w);
            Ray shadow;
            if (estimator_.emissiveCandidate(x_, u, v, float(w), lights[k], shadow) &&
                !estimator_.skipsAtReceiver(lights[k])) {
                ++count.occluded;
                lightRay[k] = paths_.addShadowRay(shadow);
            }
        }
        // The paths, in sample order: they share rng_.
        for (uint32_t k = 0; k < n; ++k)
            estimator_.gatherRadianceDeferred(x_, dirs[k], kSpherePdf * density[k], rng_, count, hits[k], paths_);
        paths_.trace(estimator_.tracer());
        if (surface_) {
            Vec3f p, nrm;
            Rgb e;
            for (uint32_t k = 0; k < n; ++k)
                if (paths_.firstVertexIrradiance(k, p, nrm, e)) surface_->add(p, nrm, e);
        }
        if (surfaceOnly_) return;

        float y[sh::kCoeffs];
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t i = first + k;
            Rgb l = paths_.radiance(k), emitted = paths_.firstEmission(k);
            if (guideSums_) {
                guideSums_[cell[k]] += luminance(l);
                ++guideCounts_[cell[k]];
            }
            if (guide_) {  // the guided sample's weight (1 / density); unguided samples keep their bits
                l = l * (1.0f / density[k]);
                emitted = emitted * (1.0f / density[k]);
            }
            sh::evalUnrolled(dirs[k], y);
            addGathered(dirs[k], l, emitted, y);
            double ebar = kPi * double(luminance(l));
            if (lightRay[k] != DeferredPaths::kNoShadowRay && !paths_.blocked(lightRay[k])) {
                const LightSample& s = lights[k];
                sh::evalUnrolled(s.direction, y);
                const Rgb weight = s.weight * misWeight(s.pdf, directionPdf(s.direction));
                addLight(s.direction, weight, y);
                ebar += 0.25 * double(luminance(weight));
            }
            if (sampledLights_) {  // one punctual light per sample, traced at once
                double w = radicalInverseOf<5>(i) + punctualOffset_;
                w -= std::floor(w);
                LightSample s;
                if (estimator_.samplePunctualLight(x_, w, s, count) && !estimator_.skipsAtReceiver(s)) {
                    sh::evalUnrolled(s.direction, y);
                    addLight(s.direction, s.weight, y);
                    ebar += 0.25 * double(luminance(s.weight));
                }
            }
            ebarSum_ += ebar;
            ebarSquares_ += ebar * ebar;
        }
    }

    /// Evaluates the exactly computed punctual lights once (all of them, or only the
    /// directional ones when point/spot lights are sampled); returns their Ebar part.
    double exactEbar(RayCount& count) {
        if (!exactDone_) {
            thread_local std::vector<LightSample> punctual;
            punctual.clear();
            estimator_.punctualLights(x_, punctual, count, sampledLights_);
            float y[sh::kCoeffs];
            // Punctual lights are deltas: their projection is exact, one shadow ray each.
            for (const LightSample& s : punctual) {
                if (estimator_.skipsAtReceiver(s)) continue;
                sh::evalUnrolled(s.direction, y);
                for (int j = 0; j < sh::kCoeffs; ++j) exact_[j] += Rgbd(s.weight) * double(y[j]);
                if (basis_) {
                    if (basisExact_.empty()) basisExact_.assign(basis_->accumulatorSize(), Rgbd(0, 0, 0));
                    basis_->accumulate(s.direction, Rgbd(s.weight), 1.0, basisExact_.data());
                }
                exactEbar_ += 0.25 * double(luminance(s.weight));
            }
            exactDone_ = true;
        }
        return exactEbar_;
    }

    /// The SH coefficients from the samples so far plus the exact punctual part.
    void coefficients(Rgbd out[sh::kCoeffs], RayCount& count) {
        exactEbar(count);
        const double dirScale = directionScale(), lightScale = lightSampleScale();
        for (int j = 0; j < sh::kCoeffs; ++j)
            out[j] = Rgbd(acc_[j][0], acc_[j][1], acc_[j][2]) * dirScale +
                     Rgbd(lightAcc_[j][0], lightAcc_[j][1], lightAcc_[j][2]) * lightScale + exact_[j];
    }

    /// The node's values in the basis of projectAlsoInto (basis.floatsPerNode() floats), from
    /// the samples so far plus the exact punctual part, weighted as coefficients() weights them.
    void basisValues(float* out, RayCount& count) {
        exactEbar(count);
        const double dirScale = directionScale(), lightScale = lightSampleScale();
        thread_local std::vector<Rgbd> sum;
        sum.resize(basisDir_.size());
        const bool exact = !basisExact_.empty();  // else no punctual light: the same zeros as before
        for (std::size_t j = 0; j < sum.size(); ++j)
            sum[j] = basisDir_[j] * dirScale + basisLight_[j] * lightScale + (exact ? basisExact_[j] : Rgbd(0, 0, 0));
        basis_->finish(sum.data(), out);
    }

    /// The SH coefficients of the reflected light and sky alone (the gathered radiance less
    /// the emission of directly hit emitters; no NEE, no punctual lights): what a
    /// SurfaceIrradianceCache of this node holds (light.h, surface_cache.h).
    void reflectedCoefficients(Rgbd out[sh::kCoeffs]) const {
        const double dirScale = directionScale();
        for (int j = 0; j < sh::kCoeffs; ++j)
            out[j] = Rgbd(reflected_[j][0], reflected_[j][1], reflected_[j][2]) * dirScale;
    }

    uint32_t samples() const { return samples_; }
    /// Mean of the per-sample Ebar estimates and the standard error of that mean from the
    /// sample variance (an overestimate for the stratified direction part: conservative).
    double ebarMean() const { return samples_ ? ebarSum_ / samples_ : 0.0; }
    double ebarStandardError() const {
        if (samples_ < 2) return std::numeric_limits<double>::infinity();
        const double n = samples_, mean = ebarSum_ / n;
        const double var = std::max(0.0, ebarSquares_ / n - mean * mean) * n / (n - 1.0);
        return std::sqrt(var / n);
    }

    /// Relative standard error of the node's mean irradiance over normals: the standard
    /// error of the samples' Ebar over Ebar (exact punctual lights included, adding no
    /// variance). 0 for zero variance; infinity for a dark node with variance.
    double relativeStandardError(RayCount& count) {
        const double se = ebarStandardError();
        const double mean = ebarMean() + exactEbar(count);
        if (se == 0.0) return 0.0;
        return mean > 0 ? se / mean : std::numeric_limits<double>::infinity();
    }

private:
    /// Weights of the sums: a gathered direction 1 / (uniform-sphere pdf * N), an NEE or sampled
    /// punctual light 1 / N (its weight already divides by its pdf); 0 before any sample.
    double directionScale() const { return samples_ > 0 ? 4.0 * kPi / samples_ : 0.0; }
    double lightSampleScale() const { return samples_ > 0 ? 1.0 / samples_ : 0.0; }

    /// The pdf of the direction sampling at `dir` (per steradian): uniform, or the guide's.
    float directionPdf(const Vec3f& dir) const {
        constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
        return guide_ ? kSpherePdf * guide_->density(dir) : kSpherePdf;
    }
    /// recordGuide's sums for the one-by-one sampling (the packeted loop adds its own).
    void recordGuideSample(float u, float v, const Rgb& l) {
        if (!guideSums_) return;
        const int c = bake_detail::DirectionGuide::cellOf(u, v);
        guideSums_[c] += luminance(l);
        ++guideCounts_[c];
    }

    void addGathered(const Vec3f& dir, const Rgb& l, const Rgb& emitted, const float y[sh::kCoeffs]) {
        if (basis_) basis_->accumulate(dir, Rgbd(l), 1.0, basisDir_.data());
        const Rgb r = l - emitted;
        for (int j = 0; j < sh::kCoeffs; ++j) {
            acc_[j][0] += double(l.x) * y[j];
            acc_[j][1] += double(l.y) * y[j];
            acc_[j][2] += double(l.z) * y[j];
            reflected_[j][0] += double(r.x) * y[j];
            reflected_[j][1] += double(r.y) * y[j];
            reflected_[j][2] += double(r.z) * y[j];
        }
    }
    void addLight(const Vec3f& dir, const Rgb& weight, const float y[sh::kCoeffs]) {
        if (basis_) basis_->accumulate(dir, Rgbd(weight), 1.0, basisLight_.data());
        for (int j = 0; j < sh::kCoeffs; ++j) {
            lightAcc_[j][0] += double(weight.x) * y[j];
            lightAcc_[j][1] += double(weight.y) * y[j];
            lightAcc_[j][2] += double(weight.z) * y[j];
        }
    }

    /// Samples per batch of addSamplesPacketed: the paper configuration's 578 in one batch
    /// (fewer part-filled packets: 1024 took 0.95x the CPU time of batches of 64).
    static constexpr uint32_t kBatch = 1024;
    struct Scratch {
        std::vector<Vec3f> dirs;
        std::vector<Ray> rays;
        std::vector<Hit> hits;
        std::vector<LightSample> lights;
        std::vector<uint32_t> lightRay;
        std::vector<float> density;   ///< the guide's density at each direction (1: uniform)
        std::vector<uint16_t> cell;   ///< each direction's guide cell (recordGuide)
        void resize(std::size_t n) {
            if (dirs.size() >= n) return;
            density.resize(n);
            cell.resize(n);
            dirs.resize(n);
            rays.resize(n);
            hits.resize(n);
            lights.resize(n);
            lightRay.resize(n);
        }
    };
    const RadianceEstimator& estimator_;
    Vec3f x_;
    uint64_t stream_;
    Rng rng_;
    bool sampledLights_;
    double lightOffset_, punctualOffset_;
    double acc_[sh::kCoeffs][3] = {};
    double lightAcc_[sh::kCoeffs][3] = {};
    double reflected_[sh::kCoeffs][3] = {};
    SurfaceSampleSink* surface_ = nullptr;
    bool surfaceOnly_ = false;  ///< recordSurfaceOnly
    double ebarSum_ = 0, ebarSquares_ = 0;
    Rgbd exact_[sh::kCoeffs] = {};
    double exactEbar_ = 0;
    bool exactDone_ = false;
    uint32_t samples_ = 0;
    depth::Accumulator* depth_ = nullptr;
    double depthSpacing_ = 1.0;
    const Basis* basis_ = nullptr;  ///< projectAlsoInto's basis, or null
    const bake_detail::DirectionGuide* guide_ = nullptr;  ///< guideDirections's, or null (uniform)
    float* guideSums_ = nullptr;       ///< recordGuide's, or null
    uint32_t* guideCounts_ = nullptr;
    std::vector<Rgbd> basisDir_, basisLight_, basisExact_;  ///< its sums, weighted as acc_, lightAcc_, exact_ (empty: 0)
};

}  // namespace vdblight::detail
