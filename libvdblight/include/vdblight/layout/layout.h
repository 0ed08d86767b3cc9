// The layout module's API, where the nodes go, in four parts: the uniform grid (below), the
// default bake's node budget, the topology of a level, and bilevel / adaptive levels.
//
// Spatial layout: where the nodes of a volume sit.
//
// A uniform grid of nodes with cubic cells. Node (i, j, k) sits at
// origin + spacing * (i, j, k); it is voxel (i, j, k) of the level's grids in the .vdb.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct GridSpec {
    Vec3d origin;          ///< world position of node (0, 0, 0)
    double spacing = 1.0;  ///< distance between neighbouring nodes
    int nx = 0, ny = 0, nz = 0;

    std::size_t nodeCount() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
    }
    Vec3d node(int i, int j, int k) const { return origin + Vec3d(i, j, k) * spacing; }
    Vec3d node(std::size_t index) const;
    /// Box spanned by the nodes (not the cells around them).
    Bounds nodeBounds() const;
};

/// How a user asked for the grid to be placed. Exactly one of spacing / resolution > 0.
struct GridPlacement {
    double spacing = 0.0;             ///< distance between nodes, scene units
    int resolution = 0;               ///< nodes along the longest axis
    std::optional<Bounds> bounds;     ///< explicit node box; default: inset scene bounds
    uint64_t maxNodes = 50'000'000;   ///< refuse larger grids (memory estimate in the error)
};

/// Places a uniform grid. Over scene bounds, nodes sit at the centres of cells that tile
/// the bounds (inset by half a spacing from the walls, as Greger et al. inset theirs);
/// over explicit bounds, the outermost nodes lie on the given box.
/// Throws ValueError for non-positive or absurd values, with the memory it would need.
GridSpec placeUniformGrid(const Bounds& sceneBounds, const GridPlacement& placement,
                          std::size_t bytesPerNode);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The default bake's grid rule (issue 15): a node budget instead of a fixed count on the
// longest axis, so that an elongated scene (two rooms side by side, a corridor) gets the
// same spacing on every axis and as many nodes as a cube of the same volume.

namespace vdblight {

/// The nodes on the longest axis that a node budget's grid stays between.
constexpr int kBudgetMinNodesOnLongestAxis = 16;
constexpr int kBudgetMaxNodesOnLongestAxis = 64;
/// The grid of a bake without a node budget, resolution or spacing: nodes on the longest axis.
constexpr int kDefaultResolution = 16;

/// The spacing that puts about `nodes` nodes in `box` (placeUniformGrid, layout/layout.h):
/// (volume / nodes)^(1/3), each extent counted as at least 1/16 of the longest (a flat scene
/// is not given a vanishing spacing), then kept between longest / 64 and longest / 16, so the
/// grid has 16..64 nodes on its longest axis whatever the shape. Throws ValueError for an
/// empty or non-finite box or nodes = 0.
double spacingForNodeBudget(const Bounds& box, uint64_t nodes);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Which nodes of a level exist: the topology that a layout places (layout/layout.h) and that
// a volume stores its channels on (VolumeLevel in volume/volume.h derives from LevelTopology).
//
// Kept apart from the data so that the layout module knows nothing of volumes: the layout
// owns the nodes, the volume owns what is stored at them.

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
/// in fine.activeNodes, ascending (layout/layout.h explains seams).
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
/// coarse cell. The values are applied by applySeamConstraints (volume/volume.h).
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

// ---------------------------------------------------------------------------------------------
// Multi-level layouts (Greger et al. section 3.1, grown to n levels): a uniform first
// level, and cells that contain geometry subdivided K x K x K into the next level.
//
// Level l has spacing h0 / K^l, the same origin as level 0 and dims (n_{l-1} - 1) K + 1, so
// node (i, j, k) of level l-1 is node (K i, K j, K k) of level l. A cell is named by its
// lower corner node. Level 0 is dense; a finer level holds only the corners of the children
// of refined cells (LevelTopology::activeNodes), so a query never needs any other node.
//
// Seams: a fine node that touches a coarser cell which is not refined (on a shared face,
// edge or corner) is a "seam node". Its value is not baked but set to what the coarser
// level interpolates there (applySeamConstraints in volume/volume.h, with the stencils of
// layout/layout.h), which makes the reconstruction C0
// across level boundaries: trilinear interpolation reproduces the coarse (bi)linear
// function exactly on the shared face.

namespace vdblight {

/// Exact triangle / axis-aligned box overlap (Akenine-Moeller's separating-axis test, in
/// double). Touching counts as overlapping.
bool triangleOverlapsBox(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Bounds& box);

enum class LayoutKind { Uniform, Bilevel, Adaptive };
/// "uniform" | "bilevel" | "adaptive" (ValueError otherwise).
LayoutKind parseLayoutKind(const std::string& name);
const char* layoutName(LayoutKind kind);

struct LevelsPlacement {
    LayoutKind kind = LayoutKind::Bilevel;
    int refine = 3;                  ///< K: cells split K x K x K (>= 2)
    int levels = 3;                  ///< adaptive: number of levels including level 0 (>= 1)
    uint64_t maxNodes = 50'000'000;  ///< refuse layouts with more nodes in total
    /// Also list the finest level's cells that contain geometry (LevelLayout::finestGeometryCells,
    /// one more level of exact triangle-box tests); solid culling needs them.
    bool keepFinestGeometry = false;
    /// Refine a cell when a triangle lies within this distance of it (>= 0, scene units; the
    /// max-norm distance: the cell's test box grown by D on every side overlaps the triangle).
    /// 0 = Greger's rule (the cell contains geometry). A band of refined cells around the
    /// surfaces, so that points near (not only on) geometry get the finer levels.
    double refineDistance = 0.0;
};

/// A placed layout: the levels' grids, active nodes and refined cells (no data yet).
struct LevelLayout {
    LayoutKind kind = LayoutKind::Uniform;
    int refine = 1;
    std::vector<LevelTopology> levels;  ///< which nodes exist (a bake adds the data: VolumeLevel)
    /// With LevelsPlacement::keepFinestGeometry: cells of the finest level (that exist, i.e.
    /// children of refined cells) overlapped by a triangle (same test as refinement), ascending.
    std::vector<uint64_t> finestGeometryCells;
    bool hasFinestGeometry = false;  ///< finestGeometryCells was computed
    /// Nodes removed by solid culling (bake/each_pass.h); > 0 makes a bake mark its volume culled.
    uint64_t culledNodes = 0;

    uint64_t totalNodes() const;
    /// Nodes a dense grid at the finest spacing over the same box would have.
    double denseEquivalentNodes() const;
};

/// Builds the levels over `level0` (a uniform grid, e.g. from placeUniformGrid) for the
/// triangles (positions, 3 indices each). A level-l cell is refined when a triangle
/// overlaps it (grown by refineDistance); cells on the border of the node box are tested extended outwards by half a
/// level-0 spacing (the inset of the node box from the scene walls), so walls refine them.
/// Refinement stops early if no cell of a level contains geometry.
/// Throws ValueError for refine < 2, levels < 1, a negative or non-finite refine distance, a level-0 grid with fewer than two nodes
/// along an axis (multi-level only), or a layout beyond maxNodes / index range (the error
/// states the estimated memory with `bytesPerNode`); the estimate is checked before each
/// level's nodes are allocated.
LevelLayout placeLevels(const GridSpec& level0, const std::vector<Vec3f>& positions,
                        const std::vector<uint32_t>& indices, const LevelsPlacement& placement,
                        std::size_t bytesPerNode);

}  // namespace vdblight
