// The point-gather pass: SH order-2 radiance at every node of a uniform grid.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <vector>

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

    const RadianceEstimator estimator(scene, tracer, options.transport);
    tbb::enumerable_thread_specific<RayCount> rayCounts;
    std::atomic<uint64_t> done{0};
    std::atomic<bool> cancelled{false};
    if (interrupter) interrupter->start("baking", nodes);

    const auto start = std::chrono::steady_clock::now();
    const int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            RayCount& count = rayCounts.local();
            for (std::size_t n = r.begin(); n != r.end(); ++n) {
                if (cancelled.load(std::memory_order_relaxed)) return;
                Rgbd coeffs[sh::kCoeffs];
                projectIncidentRadiance(estimator, Vec3f(grid.node(n)), options.raysPerNode, options.seed, n,
                                        coeffs, count);
                float* dst = level.data.data() + n * sh::kCoeffs * 3;
                for (int j = 0; j < sh::kCoeffs; ++j) {
                    dst[3 * j + 0] = float(coeffs[j].x);
                    dst[3 * j + 1] = float(coeffs[j].y);
                    dst[3 * j + 2] = float(coeffs[j].z);
                }
                const uint64_t finished = done.fetch_add(1, std::memory_order_relaxed) + 1;
                if (interrupter) {
                    interrupter->progress(finished);
                    if (interrupter->wasInterrupted()) cancelled = true;
                }
            }
        });
    });
    if (interrupter) interrupter->end();
    if (cancelled) throw Cancelled("bake cancelled");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    RayCount total;
    for (const RayCount& c : rayCounts) total += c;  // integer sums: order does not matter

    Metadata& m = volume.meta;
    m["scene_name"] = scene.name;
    m["scene_hash"] = scene.contentHash();
    m["scene_triangles"] = int64_t(scene.triangleCount());
    m["method"] = std::string("gather");
    m["sampling"] = std::string("point");
    m["rays_per_node"] = int64_t(options.raysPerNode);
    m["seed"] = int64_t(options.seed);
    m["bounces"] = int64_t(options.transport.maxBounces);
    m["roulette_start"] = int64_t(options.transport.rouletteStart);
    m["direction_sampling"] = std::string("scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact");
    m["nodes"] = int64_t(nodes);
    m["rays_intersect"] = int64_t(total.intersect);
    m["rays_occluded"] = int64_t(total.occluded);
    m["bake_seconds"] = seconds;
    m["threads"] = int64_t(threads);

    if (stats) {
        stats->nodes = nodes;
        stats->rays = total;
        stats->seconds = seconds;
    }
    return volume;
}

}  // namespace vdblight
