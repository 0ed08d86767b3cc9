// The loop every node-by-node bake pass shares: core::parallelFor (core/parallel_for.h) with
// ray counts summed per thread and the wall time measured. (Internal to the bake module.)
//
// Determinism is the caller's: `work(item, rays)` must depend only on the item (its sample
// streams derive from the seed and the item index) and write only that item's output.
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <chrono>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/parallel_for.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/light/light.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

class Basis;
class Tracer;

namespace bake_detail {

struct ParallelRun {
    RayCount rays;       ///< summed over threads (integer sums: order does not matter)
    int threads = 0;     ///< size of the arena actually used
    double seconds = 0;  ///< wall time of the loop
};

/// Calls work(item, rays) for every item in [0, count), `threads` workers (0 = all cores),
/// as steps of `progress` (a task that runs several loops). Throws Cancelled if it is cancelled.
template <typename Work>
ParallelRun forEachItemInParallel(std::size_t count, int threads, core::TaskProgress& progress, Work&& work) {
    tbb::enumerable_thread_specific<RayCount> rayCounts;
    ParallelRun run;
    run.threads = core::threadCount(threads);
    const auto start = std::chrono::steady_clock::now();
    core::parallelFor(count, threads, [&](std::size_t item) { work(item, rayCounts.local()); }, &progress);
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const RayCount& c : rayCounts) run.rays += c;
    return run;
}

/// The same as one task "baking" of `count` items reported to `interrupter` (may be null).
template <typename Work>
ParallelRun forEachItemInParallel(std::size_t count, int threads, Interrupter* interrupter, Work&& work) {
    core::TaskProgress progress(interrupter, "baking", count, "bake cancelled");
    return forEachItemInParallel(count, threads, progress, std::forward<Work>(work));
}

/// What every pass on a uniform grid checks first: ValueError for threads < 0 or a grid
/// without nodes. Returns the node count.
std::size_t checkThreadsAndGrid(int threads, const GridSpec& grid);
/// A volume of one SH order-2 level (or, with `basis`, of that basis) on `grid`, every value
/// 0; with `only` (a tile), only the window of nodes the tile spans (setTileWindows, tiles.h).
Volume emptyShVolume(const GridSpec& grid, const NodeMask* only = nullptr, const Basis* basis = nullptr);

/// Depth moments (nodeDepthMoments, bake_depth.h) of the (level, position) items of `work`, in
/// parallel: each node's rays seeded by (level << 56) | its linear index, written into the
/// level's depth array (allocated by the caller).
ParallelRun depthMomentsOfNodes(const Tracer& tracer, Volume& volume, const std::vector<std::pair<int, std::size_t>>& work,
                                uint64_t seed, uint32_t rays, int threads, Interrupter* interrupter);

/// (level, position in the level's data) of every node a multi-level bake must sample, in a
/// fixed order: seam nodes (set afterwards from the coarser level) are left out and counted;
/// with `only` (a tile, tiles.h), so are the nodes outside it (not counted).
std::vector<std::pair<int, std::size_t>> nodesToBake(const Volume& volume, uint64_t& seams,
                                                     const NodeMask* only = nullptr);

}  // namespace bake_detail
}  // namespace vdblight
