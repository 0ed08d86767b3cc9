// The point-gather pass: SH order-2 radiance (or another basis's values) at every node of a
// uniform grid.

#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "direction_guide.h"
#include "extra_cache_paths.h"
#include "first_pass_by_error.h"
#include "volume/first_pass_blend.h"
#include "project_incident.h"
#include "pass_metadata.h"
#include "probe_passes.h"
#include "stage_carry.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/volume/volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "volume/node_filter.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

void projectIncidentRadiance(const RadianceEstimator& estimator, const Vec3f& x, uint32_t rays, uint64_t seed,
                             uint64_t streamIndex, Rgbd out[9], RayCount& count, const Tracer* tracer,
                             uint32_t* backFaceHits, float* depthOut, double spacing) {
    detail::NodeSampler sampler(estimator, x, seed, streamIndex, rays);
    depth::Accumulator depth;
    if (depthOut) sampler.recordDepth(&depth, spacing);
    sampler.addSamples(0, rays, count, tracer, backFaceHits);
    sampler.coefficients(out, count);
    if (depthOut) depth.finish(depthOut);
}

Volume bakeShGather(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const GatherOptions& options,
                    Interrupter* interrupter, BakeStats* stats) {
    if (options.raysPerNode == 0) throw ValueError("rays per node must be at least 1");
    const std::size_t nodes = bake_detail::checkThreadsAndGrid(options.threads, grid);

    const Basis* basis = options.basis.get();  // null: SH order 2
    std::vector<std::size_t> selected;  // a tile's nodes (tiles.h); empty = all
    if (options.only) {
        if (options.only->size() != 1 || (*options.only)[0].size() != nodes) throw ValueError("the node mask does not match the grid");
        if (options.probePasses > 0 && options.stage < 0)  // a probe pass reads every node of the pass before
            throw ValueError("a tile of a bake with probe-to-probe passes is baked in stages (GatherOptions::stage; tiles.h)");
        for (std::size_t n = 0; n < nodes; ++n)
            if ((*options.only)[0][n]) selected.push_back(n);
    }
    // A tile holds only the window of nodes it spans (tiles.h, setTileWindows): every per-node
    // array below is indexed by level.held(n).
    Volume volume = bake_detail::emptyShVolume(grid, options.only, basis);
    VolumeLevel& level = volume.levels[0];
    const std::size_t floats = volume.basis.channelCount() * std::size_t(3);
    const std::size_t held = level.heldNodes();
    if (options.depthMoments) level.depth.assign(held * depth::kFloatsPerNode, 0.0f);
    std::vector<float> error(held, 0.0f);
    // Nodes inside solids (error_summary.h): with depth weights no free-space lookup reads
    // them, so the error summary leaves them out. Classified from the first hits of the pass
    // whose error is kept (the last; every pass traces its first hits, so no extra rays and the
    // same bits), so that the last stage of a staged bake classifies as the single bake does.
    std::vector<uint8_t> insideSolid(options.depthMoments ? held : 0, 0);
    std::vector<Rgb> reflected;  // per node, nine coefficients: the next pass's cache
    if (options.probePasses > 0) reflected.assign(held * sh::kCoeffs, Rgb(0, 0, 0));
    RadianceEstimator estimator(scene, tracer, options.transport);
    // One stage of a staged bake (tiles.h) runs one pass, from the stage before's reflected light.
    const bake_detail::PassRange range =
        bake_detail::stagePasses(options.probePasses, options.stage, options.stageInput, grid, options.depthMoments);
    if (range.first > 0 && options.depthMoments) {  // pass 0's, of the window
        const VolumeLevel& stage = options.stageInput->levels[0];  // maybe a window of it (tiles.h)
        if (level.windowFirst < stage.windowFirst || stage.held(level.windowFirst) + held > stage.heldNodes())
            throw ValueError("the stage input read does not hold this tile's nodes");
        const std::vector<float>& in = stage.depth;
        const auto from = in.begin() + std::ptrdiff_t(stage.held(level.windowFirst) * depth::kFloatsPerNode);
        level.depth.assign(from, from + std::ptrdiff_t(held * depth::kFloatsPerNode));
    }
    // Guided probe directions (direction_guide.h): pass 0's luminance per direction cell.
    using bake_detail::DirectionGuide;
    const bool guided = options.guideProbeDirections && options.probePasses > 0;
    if (guided && options.probePasses > 1 && options.stage >= 0)
        throw ValueError("guided probe directions in a staged bake need exactly one probe pass");
    std::vector<float> guideSums(guided ? held * DirectionGuide::kCells : 0, 0.0f);
    std::vector<uint32_t> guideCounts(guideSums.size(), 0);
    const bool blend = options.blendFirstPass && options.probePasses == 1 && range.last == 1;
    // A staged bake's stage 0 carries pass 0's map, values and errors to stage 1 (stage_carry.h).
    bake_detail::StageCarry carry;
    carry.guide = guided;
    carry.firstPassFloats = options.blendFirstPass && options.probePasses == 1 ? floats : 0;
    if (options.firstPassByError && (options.stage >= 0 || options.only))
        throw ValueError("pass 0's rays by its error need every node's first pass in one bake (not tiled or staged)");
    if (options.probePassByError && (options.probePasses != 1 || options.stage >= 0 || options.only))
        throw ValueError("the probe pass's rays by its error need exactly one probe pass, every node in one bake (not tiled "
                         "or staged)");
    if (options.extraCachePaths && options.stage >= 0)
        throw ValueError("extra paths for the surface probe cache need every pass in one bake (not staged)");
    std::vector<float> firstValues, firstError;
    if (range.first > 0 && carry.any()) {  // stage 1: pass 0's, from the stage input
        const bake_detail::StageCarry in = bake_detail::StageCarry::of(options.stageInput->basis);
        if (in.guide != carry.guide || in.firstPassFloats != carry.firstPassFloats)
            throw ValueError("the stage input does not carry what this stage's guide or blend reads: its stage 0 was "
                             "baked with other options");
        // A guided probe pass does not classify the nodes (below): pass 0's classification stays.
        bake_detail::readCarriedFirstPass(*options.stageInput, in, level.windowFirst, held, blend ? &firstValues : nullptr,
                                          blend ? &firstError : nullptr,
                                          guided && options.depthMoments ? &insideSolid : nullptr);
        if (guided)
            bake_detail::poolCarriedGuide(*options.stageInput, in, grid, DirectionGuide::kPoolRadius, options.threads,
                                          level.windowFirst, held, guideSums, guideCounts);
    }
    std::unique_ptr<bake_detail::SurfaceBins> bins;
    if (options.surfaceProbeCache) {
        if (options.probePasses != 1) throw ValueError("the surface probe cache needs exactly one probe pass");
        if (range.first > 0) {  // stage 1: the bins of every tile's stage-0 paths, merged
            if (!options.stageInput->surfaceBins)
                throw ValueError("the stage input has no surface bins: its stage 0 was baked without --probe-cache surface");
            bins = std::make_unique<bake_detail::SurfaceBins>(tracer, grid, *options.stageInput->surfaceBins);
        } else {
            bins = std::make_unique<bake_detail::SurfaceBins>(tracer, grid, bake_detail::radianceScale(scene, grid.spacing));
        }
    }
    const bake_detail::ParallelRun run = bake_detail::runProbePasses(
        estimator, tracer, grid, options.seed, options.probePasses, range,
        range.first > 0 ? options.stageInput->levels[0].data.data() : nullptr, reflected,
        [&](const bake_detail::ProbePass& pass) {
            if (guided && pass.index == 1 && range.first == 0)
                bake_detail::poolGuideSums(grid, DirectionGuide::kPoolRadius, options.threads, guideSums, guideCounts);
            if (blend && pass.index == 1 && range.first == 0) {
                firstValues = level.data;
                firstError = error;
            }
            // projectIncidentRadiance's sampling, keeping the sampler for its error estimate.
            const auto startNode = [&](detail::NodeSampler& sampler, depth::Accumulator& depthAcc, std::size_t h) {
                sampler.projectAlsoInto(basis);
                // Depth moments come from the first pass's own first hits (no extra rays).
                if (options.depthMoments && pass.index == 0) sampler.recordDepth(&depthAcc, grid.spacing);
                if (bins && pass.index == 0) sampler.recordSurface(bins.get());
                if (guided && pass.index == 0)
                    sampler.recordGuide(&guideSums[h * DirectionGuide::kCells], &guideCounts[h * DirectionGuide::kCells]);
            };
            const auto finishNode = [&](detail::NodeSampler& sampler, const depth::Accumulator& depthAcc, std::size_t h,
                                        bool classify, uint32_t backFaces, RayCount& count) {
                Rgbd coeffs[sh::kCoeffs];
                sampler.coefficients(coeffs, count);
                if (options.depthMoments && pass.index == 0) depthAcc.finish(level.depth.data() + h * depth::kFloatsPerNode);
                if (classify) insideSolid[h] = insideSolidByBackFaces(backFaces, sampler.samples());
                error[h] = float(std::min(sampler.relativeStandardError(count), 1e30));
                float* values = level.data.data() + h * floats;
                bake_detail::storeNode(sampler, coeffs, basis ? nullptr : values,
                                       pass.keepReflected ? &reflected[h * sh::kCoeffs] : nullptr);
                if (basis) sampler.basisValues(values, count);
            };
            // A guided probe pass draws each node's directions from its density (direction_guide.h),
            // which lives as long as the node's sampler.
            const bool guidedPass = guided && pass.index > 0;
            const auto guideNode = [&](detail::NodeSampler& sampler, std::size_t h, float* density,
                                       std::optional<DirectionGuide>& guide) {
                DirectionGuide::build(&guideSums[h * DirectionGuide::kCells], &guideCounts[h * DirectionGuide::kCells],
                                      DirectionGuide::kUniformShare, density);
                guide.emplace(density);
                sampler.guideDirections(&*guide);
            };
            // A guided pass's back-face count is not a uniform fraction: pass 0's stays.
            const bool classify = options.depthMoments && !guidedPass;
            bake_detail::ParallelRun passRun;
            const bool byError = pass.index == 0 ? options.firstPassByError : options.probePassByError;
            if (byError) {
                // Two rounds (first_pass_by_error.h): the samplers wait between them, a guided
                // probe pass's with their guide (each node's density, built once).
                struct Pending {
                    std::unique_ptr<detail::NodeSampler> sampler;
                    depth::Accumulator depth;
                    uint32_t backFaces = 0;
                    std::optional<DirectionGuide> guide;
                };
                std::vector<Pending> pending(nodes);
                std::vector<float> pilotError(nodes, 0.0f);
                const uint32_t pilot = bake_detail::pilotRays(options.raysPerNode);
                std::vector<float> density(guidedPass ? nodes * DirectionGuide::kCells : 0);
                passRun = bake_detail::forEachItemInParallel(nodes, options.threads, interrupter, [&](std::size_t n, RayCount& count) {
                    Pending& p = pending[n];
                    p.sampler = std::make_unique<detail::NodeSampler>(estimator, Vec3f(grid.node(n)), pass.seed, n, options.raysPerNode);
                    startNode(*p.sampler, p.depth, n);
                    if (guidedPass) guideNode(*p.sampler, n, &density[n * DirectionGuide::kCells], p.guide);
                    p.sampler->addSamples(0, pilot, count, classify ? &tracer : nullptr, classify ? &p.backFaces : nullptr);
                    pilotError[n] = float(std::min(p.sampler->relativeStandardError(count), 1e30));
                    if (classify) insideSolid[n] = insideSolidByBackFaces(p.backFaces, pilot);
                });
                const std::vector<uint32_t> rays =
                    bake_detail::raysPerNodeByError(grid, pilotError, insideSolid, pilot, options.raysPerNode);
                const bake_detail::ParallelRun second = bake_detail::forEachItemInParallel(
                    nodes, options.threads, interrupter, [&](std::size_t n, RayCount& count) {
                        Pending& p = pending[n];
                        p.sampler->addSamples(pilot, rays[n], count, classify ? &tracer : nullptr, classify ? &p.backFaces : nullptr);
                        finishNode(*p.sampler, p.depth, n, classify, p.backFaces, count);
                        p.sampler.reset();
                    });
                passRun.rays += second.rays;
                passRun.seconds += second.seconds;
            } else {
                passRun = bake_detail::forEachItemInParallel(
                options.only ? selected.size() : nodes, options.threads, interrupter, [&](std::size_t item, RayCount& count) {
                    const std::size_t n = options.only ? selected[item] : item;
                    const std::size_t h = level.held(n);
                    detail::NodeSampler sampler(estimator, Vec3f(grid.node(n)), pass.seed, n, options.raysPerNode);
                    depth::Accumulator depthAcc;
                    startNode(sampler, depthAcc, h);
                    float density[DirectionGuide::kCells];
                    std::optional<DirectionGuide> guide;
                    if (guidedPass) guideNode(sampler, h, density, guide);
                    uint32_t backFaces = 0;
                    sampler.addSamples(0, options.raysPerNode, count, classify ? &tracer : nullptr,
                                       classify ? &backFaces : nullptr);
                    finishNode(sampler, depthAcc, h, classify, backFaces, count);
                });
            }
            // Pass 0's errors are known here, and the estimator has no cache yet (probe_passes.h).
            if (pass.index == 0 && bins && options.extraCachePaths && !options.only) {
                const bake_detail::ParallelRun extra = bake_detail::traceExtraCachePaths(
                    estimator, grid, options.seed, bake_detail::extraCachePaths(grid, error, insideSolid, options.extraCachePathsPerNode), *bins,
                    options.threads, interrupter);
                passRun.rays += extra.rays;
                passRun.seconds += extra.seconds;
            }
            return passRun;
        }, bins.get(), range.first > 0 ? std::size_t(options.stageInput->basis.channelCount()) * 3 : 27);

    bake_detail::PassMetadata m(volume.meta);
    m.common(scene, options.transport, options.seed, nodes, run);
    if (options.stageInput) addEarlierStageSums(volume.meta, options.stageInput->meta);
    if (options.depthMoments) m.depthMoments(options.raysPerNode);
    if (range.last < options.probePasses) {  // a stage before the last: its reflected light
        std::vector<float> passValues;  // pass 0's, for the next stage's blend
        if (carry.firstPassFloats) passValues = level.data;
        volume = bake_detail::stageVolume(level, reflected, std::move(level.depth), std::move(volume.meta), range.last,
                                          options.probePasses);
        // Unmarked errors and the solid flags apart: the single bake's blend and guide read these.
        bake_detail::carryIntoStage(volume, carry, passValues, error, insideSolid, guideSums, guideCounts);
        // A tile's bins hold its own nodes' samples; the merge adds every tile's (integers).
        if (bins) volume.surfaceBins = std::make_shared<SurfaceBinSums>(bins->sums());
        if (stats) {
            stats->nodes = nodes;
            stats->rays = run.rays;
            stats->seconds = run.seconds;
            stats->estimatedError.clear();
        }
        return volume;
    }
    for (std::size_t h = 0; h < insideSolid.size(); ++h)
        if (insideSolid[h]) error[h] = kNodeInsideSolid;
    // A tile's blend pools variances across its borders: the merge blends (tiles.h).
    if (blend && !options.only) blendWithFirstPass(grid, floats, firstValues, firstError, level.data, error);
    if (!options.only) {
        filterNodes(volume, options.nodeFilterPasses, options.nodeFilterByNoise ? &error : nullptr, options.threads);
    } else if (options.nodeFilterPasses > 0) {  // its kernel crosses tile borders: the merge filters (tiles.h)
        volume.meta["tile_node_filter_passes"] = int64_t(options.nodeFilterPasses);
        volume.meta["tile_node_filter_by_noise"] = int64_t(options.nodeFilterByNoise ? 1 : 0);
    }
    if (options.nodeFilterPasses > 0) m.count("node_filter_passes", options.nodeFilterPasses);
    if (options.probePasses > 0 && options.transport.cacheEndLightSamples > 1)
        m.count("probe_light_samples", options.transport.cacheEndLightSamples);
    if (blend)
        m.text("first_pass_blend", "pass 0's values blended into the probe pass's by pooled inverse variance (first_pass_blend.h)");
    if (options.extraCachePaths && bins)
        m.text("extra_cache_paths", std::to_string(options.extraCachePathsPerNode) +
                                        " more paths for the surface cache's bins from each node whose pass-0 error is above " +
                                        "twice the median (extra_cache_paths.h)");
    if (options.firstPassByError)
        m.text("first_pass_rays", std::to_string(bake_detail::pilotRays(options.raysPerNode)) +
                                      " rays at every node, then the rest of rays_per_node x nodes by the pooled error "
                                      "of those (first_pass_by_error.h)");
    if (options.probePassByError)
        m.text("probe_pass_rays", std::to_string(bake_detail::pilotRays(options.raysPerNode)) +
                                      " rays at every node, then the rest of the probe pass's rays x nodes by the "
                                      "pooled error of those (first_pass_by_error.h)");
    if (guided)
        m.text("probe_directions", "guided: drawn from pass 0's luminance per direction cell, pooled over the nodes within " +
                                       std::to_string(DirectionGuide::kPoolRadius) + " steps, half uniform (direction_guide.h)");
    m.method("gather", "point")
        .count("rays_per_node", options.raysPerNode)
        .text("direction_sampling", "scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact")
        ;
    if (basis) m.text("projection", "the point gather's samples through Basis::accumulate, Basis::finish per node (bake.h)");
    if (!options.only) m.errorSummary(error, grid);  // a tile's: the merge's, from every tile's errors
    if (options.probePasses > 0) {
        m.count("probe_passes", options.probePasses)
            .text("probe_bounces",
                  bins ? "the second pass ends gathered paths at their first hit with the surface probe cache "
                         "(probe_cache); error_estimate excludes the first pass's noise"
                       : "passes after the first end gathered paths at their first hit with the previous pass's "
                         "reflected light (trilinear over the visible nodes in front of the surface; DDGI-style); "
                         "error_estimate excludes the previous passes' noise")
            .text("probe_cache",
                  bins ? "surface: the first hit reads bins (node cells x 6 normal axes) of irradiance samples that pass "
                         "0's paths took at their first surface vertex, instead of the nodes (docs/methods.md)"
                       : "nodes: the previous pass's reflected light at the nodes around the first hit");
    }

    if (stats) {
        stats->nodes = nodes;
        stats->rays = run.rays;
        stats->seconds = run.seconds;
        stats->estimatedError = std::move(error);
        if (blend && options.only) {
            stats->firstPassValues = std::move(firstValues);
            stats->firstPassError = std::move(firstError);
        }
    }
    return volume;
}

}  // namespace vdblight
