// The point-gather pass: SH order-2 radiance at every node of a uniform grid.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <vector>

#include "parallel_nodes.h"
#include "vdblight/bake.h"
#include "vdblight/errors.h"
#include "vdblight/interrupter.h"
#include "vdblight/scene.h"
#include "vdblight/sh.h"
#include "vdblight/trace.h"
#include "node_sampler.h"
#include "surface_cache.h"

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
    if (options.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    const std::size_t nodes = grid.nodeCount();
    if (nodes == 0) throw ValueError("the grid has no nodes");

    Volume volume;
    volume.basis = BasisDesc::sh2();
    volume.levels.resize(1);
    VolumeLevel& level = volume.levels[0];
    level.grid = grid;
    level.data.assign(nodes * sh::kCoeffs * 3, 0.0f);
    if (options.depthMoments) level.depth.assign(nodes * depth::kFloatsPerNode, 0.0f);

    std::vector<std::size_t> selected;  // a tile's nodes (tiles.h); empty = all
    if (options.only) {
        if (options.only->size() != 1 || (*options.only)[0].size() != nodes) throw ValueError("the node mask does not match the grid");
        if (options.probePasses > 0 && options.stage < 0)  // a probe pass reads every node of the pass before
            throw ValueError("a tile of a bake with probe-to-probe passes is baked in stages (GatherOptions::stage; tiles.h)");
        for (std::size_t n = 0; n < nodes; ++n)
            if ((*options.only)[0][n]) selected.push_back(n);
    }
    std::vector<float> error(nodes, 0.0f);
    std::vector<Rgb> reflected;  // per node, nine coefficients: the next pass's cache
    if (options.probePasses > 0) reflected.assign(nodes * sh::kCoeffs, Rgb(0, 0, 0));
    RadianceEstimator estimator(scene, tracer, options.transport);
    std::unique_ptr<bake_detail::VolumeSurfaceCache> cache;
    bake_detail::ParallelRun run;
    // One stage of a staged bake (tiles.h) runs one pass, from the stage before's reflected light.
    const bake_detail::PassRange range =
        bake_detail::stagePasses(options.probePasses, options.stage, options.stageInput, grid, options.depthMoments);
    if (range.first > 0) {
        cache = std::make_unique<bake_detail::VolumeSurfaceCache>(tracer, grid, bake_detail::stageReflected(*options.stageInput));
        estimator.setSurfaceCache(cache.get());
        if (options.depthMoments) level.depth = options.stageInput->levels[0].depth;  // pass 0's
    }
    // Pass 0 traces full paths; pass k > 0 ends them at their first hit with pass k - 1's
    // reflected light (probe-to-probe bounces, surface_cache.h), with its own seed.
    for (int pass = range.first; pass <= range.last; ++pass) {
        const uint64_t seed = pass == 0 ? options.seed : hashCombine(options.seed, uint64_t(pass));
        const bool keepReflected = pass < options.probePasses;
        const bake_detail::ParallelRun passRun =
            bake_detail::forEachItemInParallel(options.only ? selected.size() : nodes, options.threads, interrupter,
                                               [&](std::size_t item, RayCount& count) {
                const std::size_t n = options.only ? selected[item] : item;
                Rgbd coeffs[sh::kCoeffs];
                // projectIncidentRadiance's sampling, keeping the sampler for its error estimate.
                detail::NodeSampler sampler(estimator, Vec3f(grid.node(n)), seed, n, options.raysPerNode);
                // Depth moments come from the first pass's own first hits (no extra rays).
                depth::Accumulator depthAcc;
                const bool recordDepth = options.depthMoments && pass == 0;
                if (recordDepth) sampler.recordDepth(&depthAcc, grid.spacing);
                sampler.addSamples(0, options.raysPerNode, count);
                sampler.coefficients(coeffs, count);
                if (recordDepth) depthAcc.finish(level.depth.data() + n * depth::kFloatsPerNode);
                error[n] = float(std::min(sampler.relativeStandardError(count), 1e30));
                float* dst = level.data.data() + n * sh::kCoeffs * 3;
                for (int j = 0; j < sh::kCoeffs; ++j) {
                    dst[3 * j + 0] = float(coeffs[j].x);
                    dst[3 * j + 1] = float(coeffs[j].y);
                    dst[3 * j + 2] = float(coeffs[j].z);
                }
                if (keepReflected) {
                    sampler.reflectedCoefficients(coeffs);
                    for (int j = 0; j < sh::kCoeffs; ++j) reflected[n * sh::kCoeffs + j] = Rgb(coeffs[j]);
                }
            });
        run.rays += passRun.rays;
        run.seconds += passRun.seconds;
        run.threads = passRun.threads;
        if (keepReflected && pass < range.last) {
            estimator.setSurfaceCache(nullptr);
            cache = std::make_unique<bake_detail::VolumeSurfaceCache>(tracer, grid, reflected);
            estimator.setSurfaceCache(cache.get());
        }
    }

    Metadata& m = volume.meta;
    bake_detail::addCommonBakeMetadata(m, scene, options.transport, options.seed, nodes, run);
    if (options.stageInput) addEarlierStageSums(m, options.stageInput->meta);
    if (options.depthMoments) bake_detail::addDepthMetadata(m, options.raysPerNode);
    if (range.last < options.probePasses) {  // a stage before the last: its reflected light
        volume = bake_detail::stageVolume(grid, reflected, std::move(level.depth), std::move(m), range.last,
                                          options.probePasses);
        if (stats) {
            stats->nodes = nodes;
            stats->rays = run.rays;
            stats->seconds = run.seconds;
            stats->estimatedError.clear();
        }
        return volume;
    }
    m["method"] = std::string("gather");
    m["sampling"] = std::string("point");
    m["rays_per_node"] = int64_t(options.raysPerNode);
    m["direction_sampling"] = std::string("scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact");
    bake_detail::addErrorSummary(m, error, grid);
    if (options.probePasses > 0) {
        m["probe_passes"] = int64_t(options.probePasses);
        m["probe_bounces"] = std::string(
            "passes after the first end gathered paths at their first hit with the previous pass's reflected light "
            "(trilinear over the visible nodes in front of the surface; DDGI-style); error_estimate excludes the "
            "previous passes' noise");
    }

    if (stats) {
        stats->nodes = nodes;
        stats->rays = run.rays;
        stats->seconds = run.seconds;
        stats->estimatedError = std::move(error);
    }
    return volume;
}

}  // namespace vdblight
