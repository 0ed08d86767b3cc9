// The error-targeted point gather (bake_adaptive.h).

#include <algorithm>
#include <cmath>

#include "pass_metadata.h"
#include "probe_passes.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

namespace {
// Factor by which a standard error estimated from n samples can be too small with 10 %
// probability (for normal samples): sqrt(k / q), q = the 10 % quantile of chi-square with
// k = n - 1 degrees of freedom (Wilson-Hilferty). 1.33 for n = 16, 1.13 for n = 64,
// 1.03 for n = 1024: small rounds must beat the target by a margin before a node stops.
double varianceUncertainty(uint32_t n) {
    const double k = std::max(1.0, double(n) - 1.0);
    const double c = 2.0 / (9.0 * k);
    const double q = k * std::pow(std::max(1e-3, 1.0 - c - 1.2815515655446004 * std::sqrt(c)), 3.0);
    return std::sqrt(k / q);
}
}  // namespace

Volume bakeShGatherAdaptive(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                            const AdaptiveOptions& o, Interrupter* interrupter, AdaptiveStats* stats) {
    if (!(o.targetError > 0 && o.targetError <= 1))
        throw ValueError("target error must be in (0, 1] (a relative standard error), got " + std::to_string(o.targetError));
    if (o.minRays < 2) throw ValueError("the first round needs at least 2 rays per node to estimate a variance");
    if (o.maxRays < o.minRays) throw ValueError("max rays (" + std::to_string(o.maxRays) + ") is below the first round (" +
                                                std::to_string(o.minRays) + ")");
    const std::size_t nodes = bake_detail::checkThreadsAndGrid(o.threads, grid);

    // A tile holds only the window of nodes it spans (tiles.h): per-node arrays by level.held(n).
    Volume volume = bake_detail::emptyShVolume(grid, o.only);
    VolumeLevel& level = volume.levels[0];
    const std::size_t held = level.heldNodes();
    std::vector<uint32_t> raysUsed(held, 0);
    std::vector<float> achieved(held, 0.0f);
    std::vector<std::size_t> selected;  // a tile's nodes (tiles.h); empty = all
    if (o.only) {
        if (o.only->size() != 1 || (*o.only)[0].size() != nodes) throw ValueError("the node mask does not match the grid");
        if (o.probePasses > 0 && o.stage < 0)
            throw ValueError("a tile of a bake with probe-to-probe passes is baked in stages (AdaptiveOptions::stage; tiles.h)");
        for (std::size_t n = 0; n < nodes; ++n)
            if ((*o.only)[0][n]) selected.push_back(n);
    }

    std::vector<Rgb> reflected;  // per node, nine coefficients: the next pass's cache
    if (o.probePasses > 0) reflected.assign(held * sh::kCoeffs, Rgb(0, 0, 0));
    RadianceEstimator estimator(scene, tracer, o.transport);
    uint64_t samplesBefore = 0;  // samples of the passes before the last
    // One stage of a staged bake (tiles.h) runs one pass, from the stage before's reflected light.
    const bake_detail::PassRange range = bake_detail::stagePasses(o.probePasses, o.stage, o.stageInput, grid, false);
    if (range.first > 0) samplesBefore = uint64_t(metaNumber(o.stageInput->meta, "probe_stage_samples", 0));
    // As bakeShGather (bake.h, probePasses), each pass to the target.
    const bake_detail::ParallelRun run = bake_detail::runProbePasses(
        estimator, tracer, grid, o.seed, o.probePasses, range,
        range.first > 0 ? o.stageInput->levels[0].data.data() : nullptr, reflected,
        [&](const bake_detail::ProbePass& pass) {
            for (uint32_t r : raysUsed) samplesBefore += r;
            return bake_detail::forEachItemInParallel(
                o.only ? selected.size() : nodes, o.threads, interrupter, [&](std::size_t item, RayCount& count) {
                const std::size_t n = o.only ? selected[item] : item;
                const std::size_t h = level.held(n);
                detail::NodeSampler sampler(estimator, Vec3f(grid.node(n)), pass.seed, n, o.maxRays);
                uint32_t taken = 0, next = o.minRays;
                double err = 0;
                bool previousMet = false;
                for (;;) {
                    sampler.addSamples(taken, next, count);
                    taken = next;
                    err = sampler.relativeStandardError(count);
                    // Zero variance (below what a double variance resolves) stops at once; otherwise the rule must hold at the end of
                    // two consecutive rounds (a rare large sample missing from a small round
                    // makes a variance look small by chance).
                    const bool met = err * varianceUncertainty(taken) <= o.targetError;
                    if (err <= 1e-7 || (met && previousMet) || taken >= o.maxRays) break;
                    previousMet = met;
                    next = uint32_t(std::min<uint64_t>(uint64_t(taken) * 2, o.maxRays));
                }
                Rgbd coeffs[sh::kCoeffs];
                sampler.coefficients(coeffs, count);
                bake_detail::storeNode(sampler, coeffs, level.data.data() + h * sh::kCoeffs * 3,
                                       pass.keepReflected ? &reflected[h * sh::kCoeffs] : nullptr);
                raysUsed[h] = taken;
                achieved[h] = float(std::min(err, 1e30));
            });
        });
    AdaptiveStats local;
    AdaptiveStats& s = stats ? *stats : local;
    s.nodes = nodes;
    s.rays = run.rays;
    s.seconds = run.seconds;
    s.samples = 0;
    s.nodesAtMax = 0;
    for (std::size_t n = 0; n < held; ++n) {
        s.samples += raysUsed[n];
        if (raysUsed[n] >= o.maxRays && achieved[n] * varianceUncertainty(raysUsed[n]) > o.targetError) ++s.nodesAtMax;
    }
    s.raysPerNode = std::move(raysUsed);
    s.estimatedError = std::move(achieved);

    bake_detail::PassMetadata m(volume.meta);
    m.common(scene, o.transport, o.seed, nodes, run);
    if (o.stageInput) addEarlierStageSums(volume.meta, o.stageInput->meta);
    if (range.last < o.probePasses) {  // a stage before the last: its reflected light
        m.count("probe_stage_samples", int64_t(s.samples));
        volume = bake_detail::stageVolume(level, reflected, {}, std::move(volume.meta), range.last, o.probePasses);
        s.estimatedError.clear();
        return volume;
    }
    m.method("gather", "point, error-targeted")
        .number("target_error", o.targetError)
        .count("min_rays", o.minRays)
        .count("max_rays", o.maxRays);
    if (o.probePasses > 0) m.count("probe_passes", o.probePasses).count("samples_earlier_passes", int64_t(samplesBefore));
    m.count("samples_total", int64_t(s.samples))
        .sampleSummary();
    if (!o.only) m.errorSummary(s.estimatedError, grid);  // a tile's: the merge's, from every tile's errors
    m.count("nodes_at_max_rays", int64_t(s.nodesAtMax))
        .text("direction_sampling", "scrambled Sobol (0,2) uniform sphere in doubling rounds + NEE on emissive triangles; "
                                    "punctual lights exact or one sampled per ray");
    return volume;
}

}  // namespace vdblight
