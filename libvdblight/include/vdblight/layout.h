// Spatial layout: where the nodes of a volume sit.
//
// A uniform grid of nodes with cubic cells. Node (i, j, k) sits at
// origin + spacing * (i, j, k); it is voxel (i, j, k) of the level's grids in the .vdb.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "vdblight/math.h"

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
