// Which nodes of a level exist: the topology that a layout places (layout_levels.h) and that
// a volume stores its channels on (VolumeLevel in volume.h derives from LevelTopology).
//
// Kept apart from the data so that the layout module knows nothing of volumes: the layout
// owns the nodes, the volume owns what is stored at them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/math.h"

namespace vdblight {

struct LevelTopology {
    GridSpec grid;
    /// Sparse levels (refined levels of a bilevel / n-level volume): the linear indices
    /// grid.index(i, j, k) of the nodes that exist, strictly ascending; a volume's data then
    /// holds these nodes in this order (its "node" is a position in this list). Empty = dense:
    /// every node of the box exists and data is in node order.
    std::vector<uint64_t> activeNodes;
    /// Cells of this level refined into the next level, each named by the linear index
    /// grid.index(i, j, k) of its lower corner node, strictly ascending. Empty on the
    /// finest level (and on a single-level volume).
    std::vector<uint64_t> refinedCells;

    bool sparse() const { return !activeNodes.empty(); }
    /// Nodes stored (the positions a volume's data holds).
    std::size_t storedNodes() const { return sparse() ? activeNodes.size() : grid.nodeCount(); }
};

/// Position in the level's stored nodes of the node with linear index `linear`, or -1 if it
/// is not active.
int64_t findNode(const LevelTopology& level, uint64_t linear);
/// True if the cell with lower-corner linear index `cell` is refined.
bool isRefined(const LevelTopology& level, uint64_t cell);

/// The descent every simple multi-level lookup does: x is clamped into level 0's node box,
/// then followed down through refined cells. Returns the finest level whose cell contains x,
/// with that cell's lower node indices and the fractions towards the next nodes (an axis
/// with a single node has cell 0, fraction 0). `refine` is the volume's refinement factor.
/// `Level` is LevelTopology or a type derived from it (VolumeLevel): a template so that a
/// layout's and a volume's levels take the same code.
template <class Level>
std::size_t finestCellAt(const std::vector<Level>& levels, int refine, const Vec3d& x, int cell[3], double frac[3]);

/// Seam nodes of `fine`, the level below `coarse` (refinement factor `refine`): positions
/// in fine.activeNodes, ascending (layout_levels.h explains seams).
std::vector<std::size_t> seamNodes(const LevelTopology& coarse, const LevelTopology& fine, int refine);
/// The same for levels[level] (>= 1) below levels[level - 1].
template <class Level>
std::vector<std::size_t> seamNodes(const std::vector<Level>& levels, int level, int refine) {
    return seamNodes(levels.at(std::size_t(level - 1)), levels.at(std::size_t(level)), refine);
}

/// Where the coarser level interpolates a seam node: a refined cell of the coarse level that
/// contains it (lower corner node indices; all eight corners exist on the coarse level) and
/// the node's fractions within that cell.
struct SeamStencil {
    std::size_t node;  ///< position in fine.activeNodes
    int cell[3];
    double t[3];
};
/// The stencils of every seam node of `fine` (as seamNodes, same order). `level` (fine's
/// index) only names the level in the FormatError thrown for a node outside every refined
/// coarse cell. The values are applied by applySeamConstraints (volume.h).
std::vector<SeamStencil> seamStencils(const LevelTopology& coarse, const LevelTopology& fine, int refine, int level);

// ---------------------------------------------------------------------------------------
// Definitions

template <class Level>
std::size_t finestCellAt(const std::vector<Level>& levels, int refine, const Vec3d& x, int cell[3], double frac[3]) {
    const GridSpec& g0 = levels.at(0).grid;
    const int dims[3] = {g0.nx, g0.ny, g0.nz};
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 2) {
            cell[a] = 0, frac[a] = 0;
            continue;
        }
        const double u = std::min(std::max((x[a] - g0.origin[a]) / g0.spacing, 0.0), double(dims[a] - 1));
        cell[a] = std::min(int(std::floor(u)), dims[a] - 2);
        frac[a] = u - cell[a];
    }
    std::size_t l = 0;
    while (l + 1 < levels.size() && isRefined(levels[l], levels[l].grid.index(cell[0], cell[1], cell[2]))) {
        for (int a = 0; a < 3; ++a) {
            const double u = frac[a] * refine;
            const int c = std::min(int(std::floor(u)), refine - 1);
            frac[a] = u - c;
            cell[a] = cell[a] * refine + c;
        }
        ++l;
    }
    return l;
}

}  // namespace vdblight
