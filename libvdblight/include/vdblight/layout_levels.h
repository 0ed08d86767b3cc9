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
// level interpolates there (applySeamConstraints in volume.h, with the stencils of
// level_topology.h), which makes the reconstruction C0
// across level boundaries: trilinear interpolation reproduces the coarse (bi)linear
// function exactly on the shared face.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/level_topology.h"
#include "vdblight/math.h"

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
    /// Nodes removed by solid culling (solid_cull.h); > 0 makes a bake mark its volume culled.
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
