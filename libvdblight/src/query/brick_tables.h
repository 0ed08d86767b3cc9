// The refined cells of a multi-level volume as the multi-level lookups index them (internal to
// the query module): level l >= 1 is a list of bricks, one per refined cell of level l - 1 (in
// the order of its refinedCells), each of (K + 1)^3 nodes, u fastest.
#pragma once

#include <cstdint>
#include <vector>

#include "core/grid_index.h"
#include "lattice_locate.h"
#include "vdblight/layout/layout.h"

namespace vdblight::query_detail {

struct BrickTable {
    /// Per brick and node of the brick: the node's position in the fine level's storage
    /// (findNode), or -1 where the level holds no such node (culled inside solids).
    std::vector<int64_t> nodeAt;
    /// Per brick and sub-cell (K^3, u fastest): the brick of the next level that refines it
    /// (its position in the fine level's refinedCells), or -1; empty unless asked for.
    std::vector<int32_t> child;
};

/// The bricks of level `fine` below level `parent`, refined K times; `children`: fill
/// BrickTable::child (every level but the finest, where it would be all -1).
inline BrickTable brickTable(const LevelTopology& parent, const LevelTopology& fine, int K, bool children) {
    const int side = K + 1;
    const std::size_t bricks = parent.refinedCells.size(), nodes = std::size_t(side) * side * side,
                      cells = std::size_t(K) * K * K;
    BrickTable t;
    t.nodeAt.resize(bricks * nodes);
    if (children) t.child.resize(bricks * cells);
    for (std::size_t b = 0; b < bricks; ++b) {
        const core::Index3 p = core::unflatten(parent.refinedCells[b], uint64_t(parent.grid.nx), uint64_t(parent.grid.ny));
        for (int w = 0; w < side; ++w)
            for (int v = 0; v < side; ++v)
                for (int u = 0; u < side; ++u) {
                    const uint64_t linear = fine.grid.index(p.i * K + u, p.j * K + v, p.k * K + w);
                    t.nodeAt[b * nodes + u + side * (v + side * std::size_t(w))] = findNode(fine, linear);
                    if (children && u < K && v < K && w < K)
                        t.child[b * cells + u + K * (v + K * std::size_t(w))] = int32_t(positionIn(fine.refinedCells, linear));
                }
    }
    return t;
}

}  // namespace vdblight::query_detail
