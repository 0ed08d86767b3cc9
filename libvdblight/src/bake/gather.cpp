// The point-gather pass: SH order-2 radiance at every node of a uniform grid.

#include <atomic>
#include <chrono>
#include <vector>

#include "parallel_nodes.h"
#include "vdblight/bake.h"
#include "vdblight/errors.h"
#include "vdblight/interrupter.h"
#include "vdblight/scene.h"
#include "vdblight/sh.h"
#include "vdblight/trace.h"
#include "node_sampler.h"

namespace vdblight {

void projectIncidentRadiance(const RadianceEstimator& estimator, const Vec3f& x, uint32_t rays, uint64_t seed,
                             uint64_t streamIndex, Rgbd out[9], RayCount& count, const Tracer* tracer,
                             uint32_t* backFaceHits) {
    detail::NodeSampler sampler(estimator, x, seed, streamIndex, rays);
    sampler.addSamples(0, rays, count, tracer, backFaceHits);
    sampler.coefficients(out, count);
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

    std::vector<std::size_t> selected;  // a tile's nodes (tiles.h); empty = all
    if (options.only) {
        if (options.only->size() != 1 || (*options.only)[0].size() != nodes) throw ValueError("the node mask does not match the grid");
        for (std::size_t n = 0; n < nodes; ++n)
            if ((*options.only)[0][n]) selected.push_back(n);
    }
    const RadianceEstimator estimator(scene, tracer, options.transport);
    const bake_detail::ParallelRun run = bake_detail::forEachItemInParallel(
        options.only ? selected.size() : nodes, options.threads, interrupter, [&](std::size_t item, RayCount& count) {
            const std::size_t n = options.only ? selected[item] : item;
            Rgbd coeffs[sh::kCoeffs];
            projectIncidentRadiance(estimator, Vec3f(grid.node(n)), options.raysPerNode, options.seed, n, coeffs, count);
            float* dst = level.data.data() + n * sh::kCoeffs * 3;
            for (int j = 0; j < sh::kCoeffs; ++j) {
                dst[3 * j + 0] = float(coeffs[j].x);
                dst[3 * j + 1] = float(coeffs[j].y);
                dst[3 * j + 2] = float(coeffs[j].z);
            }
        });

    Metadata& m = volume.meta;
    bake_detail::addCommonBakeMetadata(m, scene, options.transport, options.seed, nodes, run);
    m["method"] = std::string("gather");
    m["sampling"] = std::string("point");
    m["rays_per_node"] = int64_t(options.raysPerNode);
    m["direction_sampling"] = std::string("scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact");

    if (stats) {
        stats->nodes = nodes;
        stats->rays = run.rays;
        stats->seconds = run.seconds;
    }
    return volume;
}

}  // namespace vdblight
