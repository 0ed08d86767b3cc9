// The depth-moment pass (bake_depth.h): first-hit rays from every node, binned by face.
#include "vdblight/bake/each_pass.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

void nodeDepthMoments(const Tracer& tracer, const Vec3f& x, double spacing, uint64_t seed, uint64_t stream,
                      uint32_t rays, float* out, RayCount& count) {
    constexpr uint64_t kDirection = 1;  // NodeSampler::kDirection: the gather's direction scramble
    constexpr uint32_t kBatch = 256;
    const uint64_t scramble = mix64(hashCombine(hashCombine(seed, stream), kDirection));
    thread_local std::vector<Ray> batch;
    thread_local std::vector<Hit> hits;
    batch.resize(kBatch);
    hits.resize(kBatch);
    depth::Accumulator acc;
    for (uint32_t first = 0; first < rays; first += kBatch) {
        const uint32_t m = std::min(kBatch, rays - first);
        for (uint32_t k = 0; k < m; ++k) {
            float u, v;
            sobol02Mixed(first + k, scramble, u, v);
            batch[k] = Ray{x, uniformSphere(u, v)};
        }
        tracer.intersect(batch.data(), m, hits.data());
        count.intersect += m;
        for (uint32_t k = 0; k < m; ++k)
            acc.add(batch[k].direction, hits[k].hit() ? hits[k].t : std::numeric_limits<float>::infinity(), spacing);
    }
    acc.finish(out);
}

bake_detail::ParallelRun bake_detail::depthMomentsOfNodes(const Tracer& tracer, Volume& volume,
                                                         const std::vector<std::pair<int, std::size_t>>& work,
                                                         uint64_t seed, uint32_t rays, int threads,
                                                         Interrupter* interrupter) {
    return forEachItemInParallel(work.size(), threads, interrupter, [&](std::size_t w, RayCount& count) {
        VolumeLevel& level = volume.levels[std::size_t(work[w].first)];
        const std::size_t n = work[w].second;
        const uint64_t linear = level.sparse() ? level.activeNodes[n] : n;
        nodeDepthMoments(tracer, Vec3f(level.grid.node(std::size_t(linear))), level.grid.spacing, seed,
                         (uint64_t(work[w].first) << 56) | linear, rays, level.depth.data() + level.held(n) * depth::kFloatsPerNode,
                         count);
    });
}

void bakeDepthMoments(const Tracer& tracer, Volume& volume, const DepthOptions& options, Interrupter* interrupter,
                      DepthStats* stats) {
    if (options.raysPerNode == 0) throw ValueError("depth rays per node must be at least 1");
    if (options.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    std::vector<std::pair<int, std::size_t>> work;
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        VolumeLevel& level = volume.levels[l];
        if (options.only && (options.only->size() != volume.levels.size() || (*options.only)[l].size() != level.storedNodes()))
            throw ValueError("the node mask does not match the levels");
        // A tile's volume holds its window of nodes (tiles.h): depth for the same positions.
        level.depth.assign(level.heldNodes() * depth::kFloatsPerNode, 0.0f);
        for (std::size_t n = 0; n < level.storedNodes(); ++n)
            if (!options.only || (*options.only)[l][n]) work.emplace_back(int(l), n);
    }
    const bake_detail::ParallelRun run = bake_detail::depthMomentsOfNodes(tracer, volume, work, options.seed,
                                                                          options.raysPerNode, options.threads, interrupter);
    bake_detail::PassMetadata(volume.meta).depthMoments(options.raysPerNode);
    if (stats) {
        stats->rays = run.rays.total();
        stats->seconds = run.seconds;
    }
}

}  // namespace vdblight
