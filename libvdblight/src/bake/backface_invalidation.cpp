// Point sampling with the engines' leak heuristic: nodes whose rays see too many back-faces
// are invalid and get their valid neighbours' values by dilation.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "vdblight/bake_antialiased.h"
#include "vdblight/errors.h"
#include "vdblight/interrupter.h"
#include "vdblight/scene.h"
#include "vdblight/sh.h"
#include "vdblight/trace.h"

namespace vdblight {

Volume bakeShGatherInvalidated(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                               const GatherOptions& options, double maxBackfaceFraction, Interrupter* interrupter,
                               BakeStats* stats) {
    if (!(maxBackfaceFraction >= 0.0 && maxBackfaceFraction <= 1.0))
        throw ValueError("the back-face fraction must be in [0, 1], got " + std::to_string(maxBackfaceFraction));
    if (options.raysPerNode == 0) throw ValueError("rays per node must be at least 1");
    if (options.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    const std::size_t nodes = grid.nodeCount();
    if (nodes == 0) throw ValueError("the grid has no nodes");
    constexpr int kValues = sh::kCoeffs * 3;

    Volume volume;
    volume.basis = BasisDesc::sh2();
    volume.levels.resize(1);
    VolumeLevel& level = volume.levels[0];
    level.grid = grid;
    level.data.assign(nodes * kValues, 0.0f);
    std::vector<uint32_t> backFaces(nodes, 0);

    const RadianceEstimator estimator(scene, tracer, options.transport);
    tbb::enumerable_thread_specific<RayCount> rayCounts;
    std::atomic<uint64_t> done{0};
    std::atomic<bool> cancelled{false};
    if (interrupter) interrupter->start("baking (point, back-face invalidation)", nodes);
    const auto start = std::chrono::steady_clock::now();
    const int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            RayCount& count = rayCounts.local();
            for (std::size_t n = r.begin(); n != r.end(); ++n) {
                if (cancelled.load(std::memory_order_relaxed)) return;
                Rgbd coeffs[sh::kCoeffs];
                projectIncidentRadiance(estimator, Vec3f(grid.node(n)), options.raysPerNode, options.seed, n, coeffs,
                                        count, &tracer, &backFaces[n]);
                float* dst = level.data.data() + n * kValues;
                for (int j = 0; j < sh::kCoeffs; ++j)
                    for (int c = 0; c < 3; ++c) dst[3 * j + c] = float(coeffs[j][c]);
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

    level.validity.assign(nodes, 0.0f);
    std::vector<uint8_t> valid(nodes, 0);
    std::vector<double> weight(nodes, 0.0);
    std::size_t invalid = 0;
    for (std::size_t n = 0; n < nodes; ++n) {
        const double fraction = double(backFaces[n]) / options.raysPerNode;
        valid[n] = fraction <= maxBackfaceFraction;
        weight[n] = valid[n] ? 1.0 : 0.0;
        level.validity[n] = valid[n] ? 1.0f : 0.0f;
        invalid += valid[n] ? 0 : 1;
    }
    if (invalid == nodes) {
        throw SceneError("every node sees back-faces in more than " + std::to_string(maxBackfaceFraction) +
                         " of its rays (do the normals look reversed? check the faces' winding)");
    }
    const int passes = invalid ? dilateUnfilledNodes(level, sh::kCoeffs, valid, weight) : 0;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    RayCount total;
    for (const RayCount& c : rayCounts) total += c;
    Metadata& m = volume.meta;
    m["scene_name"] = scene.name;
    m["scene_hash"] = scene.contentHash();
    m["scene_triangles"] = int64_t(scene.triangleCount());
    m["method"] = std::string("gather");
    m["sampling"] = std::string("point");
    m["invalidate_backface"] = maxBackfaceFraction;
    m["rays_per_node"] = int64_t(options.raysPerNode);
    m["seed"] = int64_t(options.seed);
    m["bounces"] = int64_t(options.transport.maxBounces);
    m["roulette_start"] = int64_t(options.transport.rouletteStart);
    m["direction_sampling"] = std::string("scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact");
    m["nodes"] = int64_t(nodes);
    m["nodes_dilated"] = int64_t(invalid);
    m["dilation_passes"] = int64_t(passes);
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
