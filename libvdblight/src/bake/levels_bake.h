// What the node-by-node passes over a LevelLayout (uniform, bilevel, adaptive; the SH, bins and
// generic basis gathers) share: the volume they fill, the node a work item names, and how such a
// bake ends. (Internal to the bake module.)
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "parallel_nodes.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/layout/layout.h"
#include "vdblight/core/math.h"

namespace vdblight::bake_detail {

/// The checks every levels bake starts with (ValueError): at least one sample per node
/// (`what` names the count: "rays per node"), a thread count >= 0 (0 = all cores), a layout
/// with levels.
void checkLevelsBake(uint64_t samples, const char* what, int threads, const LevelLayout& layout);

/// A volume of `basis` on the levels of `layout`, `floatsPerNode` zeros per node; with `only`
/// (a tile), only the window of nodes the tile spans is held (setTileWindows, tiles.h).
Volume emptyLevelsVolume(const LevelLayout& layout, const BasisDesc& basis, std::size_t floatsPerNode,
                         const NodeMask* only);

/// The node that a work item of nodesToBake names.
struct LevelNode {
    VolumeLevel& level;
    std::size_t n;    ///< among the level's stored nodes
    uint64_t linear;  ///< index in the level's grid
    /// (level << 56) | linear: the node's sample stream, the same in a tile as in the whole bake,
    /// so that merged tiles give the single bake's bits.
    uint64_t stream;

    Vec3f position() const { return Vec3f(level.grid.node(std::size_t(linear))); }
    /// Where the node's `floatsPerNode` values go in the level's data (a tile holds its window only).
    float* values(std::size_t floatsPerNode) const { return level.data.data() + level.held(n) * floatsPerNode; }
};
LevelNode levelNode(Volume& volume, const std::pair<int, std::size_t>& item);

/// Runs fn(const LevelNode&, RayCount&) in parallel for every node a levels bake samples
/// (nodesToBake: seam nodes left out and counted in `seams`; with `only`, a tile's nodes).
template <typename Fn>
ParallelRun forEachLevelNode(Volume& volume, const NodeMask* only, int threads, Interrupter* interrupter, uint64_t& seams,
                             Fn&& fn) {
    const std::vector<std::pair<int, std::size_t>> work = nodesToBake(volume, seams, only);
    return forEachItemInParallel(work.size(), threads, interrupter,
                                 [&](std::size_t w, RayCount& count) { fn(levelNode(volume, work[w]), count); });
}

/// The end of a levels bake: the seam nodes set from the coarser level, except in a tile (their
/// coarse nodes may lie in other tiles: the merge sets them, tiles.h); the layout, refine and
/// nodes_seam metadata; and `stats` (may be null) from the parallel run.
void finishLevelsBake(Volume& volume, const LevelLayout& layout, uint64_t seams, const ParallelRun& run,
                      const NodeMask* only, LevelsBakeStats* stats);

}  // namespace vdblight::bake_detail
