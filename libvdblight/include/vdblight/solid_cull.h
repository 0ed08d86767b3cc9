// Solid culling for multi-level layouts (issue 4, "sparse"): nodes that a query in open
// space can never read are left out (inactive: not baked, not stored).
//
// The rule (conservative, docs/format.md "Levels"):
//  1. Leaf cells are the cells a query interpolates in: level-0 cells and the children of
//     refined cells, that are not refined themselves. A leaf cell is *geometry-free* when no
//     triangle overlaps it (the exact test that drives refinement, with the same half-spacing
//     extension at the node-box border; for the finest level LevelsPlacement::keepFinestGeometry).
//  2. Geometry-free leaf cells are joined into connected regions through shared faces (a
//     point just outside each face centre is located in the layout). A region is one piece of
//     space that no surface crosses, so it lies wholly inside or wholly outside any solid.
//  3. A region is *solid* when rays from the centres of (up to `maxCellsPerComponent`, evenly
//     chosen) of its cells in `raysPerCell` fixed directions never escape the scene and at
//     least `backfaceFraction` of them first hit a triangle from behind (ray . geometric
//     normal > 0). Majority back faces rather than all back faces, because closed solids are
//     often modelled without the face they stand on (the Cornell blocks have no bottom: from
//     inside, the downward rays see the floor's front); a parity test needs watertight,
//     non-overlapping solids, which scenes rarely are. An escape (hole to the outside) always
//     keeps the region.
//  4. A node of level l is culled when every cell of level l that has it as a corner and
//     exists (inside the box; for l >= 1 a child of a refined cell) is a solid leaf. Corners of
//     refined cells and of non-solid leaves are therefore always kept, so a query in a
//     non-solid cell, and the seam constraints, only read kept nodes.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/layout_levels.h"

namespace vdblight {

class Tracer;

struct SolidCullOptions {
    int raysPerCell = 16;            ///< fixed spherical Fibonacci directions
    int maxCellsPerComponent = 256;  ///< cells of a region whose rays vote
    double backfaceFraction = 0.5;   ///< a region is solid at or above this fraction of back-face hits
};

struct SolidCullStats {
    uint64_t leafCells = 0;          ///< leaf cells of all levels
    uint64_t freeLeafCells = 0;      ///< of which geometry-free
    uint64_t regions = 0;            ///< connected regions of geometry-free leaf cells
    uint64_t solidRegions = 0;
    uint64_t solidCells = 0;
    uint64_t nodesBefore = 0;        ///< nodes of the layout before culling
    uint64_t nodesCulled = 0;
    std::vector<uint64_t> culledPerLevel;
};

/// Solid leaf cells of every level (lower-corner linear indices, ascending), by the rule
/// above. Requires layout.hasFinestGeometry for multi-level layouts (ValueError otherwise).
std::vector<std::vector<uint64_t>> classifySolidCells(const LevelLayout& layout, const Tracer& tracer,
                                                      const SolidCullOptions& options = {},
                                                      SolidCullStats* stats = nullptr);

/// Linear indices (ascending) of the nodes of level `level` that rule 4 culls, given the
/// solid cells of every level. Level 0 considers every node of its box.
std::vector<uint64_t> culledNodes(const LevelLayout& layout, const std::vector<std::vector<uint64_t>>& solid,
                                  std::size_t level);

/// Classifies and removes the culled nodes from the layout's levels (level 0 becomes sparse
/// if any of its nodes is culled). A single-level layout is left unchanged. Returns the
/// number of nodes removed.
uint64_t cullSolidNodes(LevelLayout& layout, const Tracer& tracer, const SolidCullOptions& options = {},
                        SolidCullStats* stats = nullptr);

}  // namespace vdblight
