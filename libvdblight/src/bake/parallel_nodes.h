// The loop every node-by-node bake pass shares: items processed in parallel on a TBB arena
// of the requested size, with progress and cancelling through an Interrupter, ray counts
// summed per thread, wall time measured. (Internal to the bake module.)
//
// Determinism is the caller's: `work(item, rays)` must depend only on the item (its sample
// streams derive from the seed and the item index) and write only that item's output.
#pragma once

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <utility>
#include <vector>

#include "vdblight/error_summary.h"
#include "vdblight/errors.h"
#include "vdblight/interrupter.h"
#include "vdblight/light.h"
#include "vdblight/tiles.h"
#include "vdblight/volume.h"

namespace vdblight {

struct Scene;

namespace bake_detail {

struct ParallelRun {
    RayCount rays;       ///< summed over threads (integer sums: order does not matter)
    int threads = 0;     ///< size of the arena actually used
    double seconds = 0;  ///< wall time of the loop
};

/// Calls work(item, rays) for every item in [0, count), `threads` workers (0 = all cores).
/// Throws Cancelled if the interrupter asks to stop.
template <typename Work>
ParallelRun forEachItemInParallel(std::size_t count, int threads, Interrupter* interrupter, Work&& work) {
    tbb::enumerable_thread_specific<RayCount> rayCounts;
    std::atomic<uint64_t> done{0};
    std::atomic<bool> cancelled{false};
    if (interrupter) interrupter->start("baking", count);
    ParallelRun run;
    run.threads = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
    const auto start = std::chrono::steady_clock::now();
    tbb::task_arena arena(run.threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            RayCount& rays = rayCounts.local();
            for (std::size_t item = r.begin(); item != r.end(); ++item) {
                if (cancelled.load(std::memory_order_relaxed)) return;
                work(item, rays);
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
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const RayCount& c : rayCounts) run.rays += c;
    return run;
}

/// (level, position in the level's data) of every node a multi-level bake must sample, in a
/// fixed order: seam nodes (set afterwards from the coarser level) are left out and counted;
/// with `only` (a tile, tiles.h), so are the nodes outside it (not counted).
std::vector<std::pair<int, std::size_t>> nodesToBake(const Volume& volume, uint64_t& seams,
                                                     const NodeMask* only = nullptr);

/// The metadata every gather-style pass writes: scene identity, transport, seed, counts, time.
void addCommonBakeMetadata(Metadata& m, const Scene& scene, const TransportOptions& transport, uint64_t seed,
                           uint64_t nodes, const ParallelRun& run);

/// The per-node error summary of the point gathers (error_summary.h).
inline void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid) {
    vdblight::addErrorSummary(m, estimatedError, grid);
}
/// The metadata of a volume with depth moments (depth_moments.h) from `rays` rays per node.
inline void addDepthMetadata(Metadata& m, uint32_t rays) {
    m["depth_moments"] = std::string("axial depth per cube face, mean and sigma, 8-bit (depth_moments.h)");
    m["depth_rays_per_node"] = int64_t(rays);
}

}  // namespace bake_detail
}  // namespace vdblight
