// Locating a point among the nodes of the lookups' levels, shared by every lookup of the
// query module (internal to it):
// - in float for the fast paths: the outside check, the cell and fraction along an axis, the
//   descent through refined cells of a multi-level volume;
// - in double for the export hooks (a point at a node's position must return exactly that
//   node, so positions within 1e-9 of a node are snapped onto it) and the reference lookups.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

#include "float4.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"

namespace vdblight {
namespace query_detail {

/// ValueError "point (x, y, z) is outside the volume" with OutsidePolicy::Throw if the lattice
/// coordinate g of x lies outside the node box by more than 1e-4 of a cell.
inline void checkInside(const Vec3f& g, const GridSpec& grid, const Vec3f& x, OutsidePolicy outside) {
    if (outside != OutsidePolicy::Throw) return;
    const float tol = 1e-4f;
    if (!(g.x >= -tol && g.y >= -tol && g.z >= -tol && g.x <= grid.nx - 1 + tol && g.y <= grid.ny - 1 + tol &&
          g.z <= grid.nz - 1 + tol)) {
        std::ostringstream s;
        s << "point (" << x.x << ", " << x.y << ", " << x.z << ") is outside the volume";
        throw ValueError(s.str());
    }
}

/// Lattice coordinate g along an axis of n nodes, clamped into [0, n - 1] (NaN to 0), split
/// into the lower node index i of its cell and the fraction f towards the next node.
template <class T>
inline void splitCell(T g, int n, int& i, T& f) {
    if (!(g >= T(0))) g = T(0);
    if (g > T(n - 1)) g = T(n - 1);
    i = std::min(int(g), n - 2);
    if (i < 0) i = 0;
    f = g - T(i);
}

/// Trilinear weights of the fractions fx, fy, fz (corner c = x bit 0, y bit 1, z bit 2):
/// weights[c] = wx * wy * wz, multiplied in that order, the x-y products made once for both z.
inline void trilinearWeights(float fx, float fy, float fz, float weights[8]) {
    const float gx = 1 - fx, gy = 1 - fy;
    const Float4 xy = Float4{gx, fx, gx, fx} * Float4{gy, gy, fy, fy};
    const Float4 lower = xy * (1 - fz), upper = xy * fz;
    std::memcpy(weights, &lower, sizeof lower);
    std::memcpy(weights + 4, &upper, sizeof upper);
}

/// A fraction f of a refined cell split into K sub-cells: the sub-cell i and the fraction in it.
template <class T>
inline void splitLocal(T& f, int K, int& i) {
    const T g = f * T(K);
    i = std::min(int(g), K - 1);
    f = g - T(i);
}

/// Position of `value` in a sorted list, -1 if absent (a refined cell's brick).
inline int64_t positionIn(const std::vector<uint64_t>& sorted, uint64_t value) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), value);
    return it != sorted.end() && *it == value ? int64_t(it - sorted.begin()) : -1;
}

/// Level 0's child table of a multi-level lookup: per cell of `grid` (x fastest), the position
/// of the cell in `refinedCells` (its brick of level 1), or -1.
inline std::vector<int32_t> levelZeroChildren(const GridSpec& grid, const std::vector<uint64_t>& refinedCells) {
    std::vector<int32_t> child(std::size_t(grid.nx - 1) * (grid.ny - 1) * (grid.nz - 1));
    for (int k = 0; k < grid.nz - 1; ++k)
        for (int j = 0; j < grid.ny - 1; ++j)
            for (int i = 0; i < grid.nx - 1; ++i)
                child[i + std::size_t(grid.nx - 1) * (j + std::size_t(grid.ny - 1) * k)] =
                    int32_t(positionIn(refinedCells, grid.index(i, j, k)));
    return child;
}

/// Where a descent through refined cells ends: the level, the brick of that level holding the
/// leaf cell (-1 at level 0) and the child value that stopped it (-1, or a lookup's marker
/// such as ShLevelsLookup::kCulled).
struct LeafCell {
    std::size_t level = 0;
    int32_t brick = -1;
    int32_t stop = -1;
};

/// From the level-0 cell (i, j, k) with fractions f, follows refined cells down the levels
/// (Level::child: per level-0 cell, then per sub-cell of a brick, the child brick or < 0): at
/// each level (i, j, k) become the sub-cell in the brick and f the fractions in it.
template <class Level, class T>
inline LeafCell descendLevels(const std::vector<Level>& levels, const GridSpec& grid, int K, int& i, int& j, int& k,
                              T f[3]) {
    int32_t brick =
        levels[0].child.empty() ? -1 : levels[0].child[i + std::size_t(grid.nx - 1) * (j + std::size_t(grid.ny - 1) * k)];
    if (brick < 0) return {0, -1, brick};
    for (std::size_t l = 1;; ++l) {
        splitLocal(f[0], K, i);
        splitLocal(f[1], K, j);
        splitLocal(f[2], K, k);
        const Level& level = levels[l];
        const int32_t next = level.child.empty() ? -1 : level.child[std::size_t(brick) * K * K * K + i + K * (j + K * k)];
        if (next < 0) return {l, brick, next};
        brick = next;
    }
}

/// The cell of x among the nodes of `grid`, located in double as the visibility lookups do
/// (OcclusionLookup and its streamed twin: the same operations, so the same bits): per axis the
/// lower node base[a] (x clamped into the node box; NaN and below: the first node) and the
/// fraction f[a] towards the next node (0 along an axis of one node).
inline void visibilityCell(const GridSpec& grid, const Vec3d& x, int base[3], double f[3]) {
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    for (int a = 0; a < 3; ++a) {
        double u = (x[a] - grid.origin[a]) / grid.spacing;
        if (!(u > 0)) u = 0;
        u = std::min(u, double(dims[a] - 1));
        base[a] = std::min(int(u), std::max(0, dims[a] - 2));
        f[a] = dims[a] > 1 ? u - base[a] : 0.0;
    }
}

/// Per axis, the lower node index lo[a] of the cell containing x and the fraction frac[a]
/// towards the next node. Outside the node box: clamped, or ValueError with Throw.
inline void locateExact(const GridSpec& grid, const Vec3d& x, OutsidePolicy outside, int lo[3], double frac[3]) {
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    for (int a = 0; a < 3; ++a) {
        double g = (x[a] - grid.origin[a]) / grid.spacing;
        if (std::fabs(g - std::round(g)) < 1e-9) g = std::round(g);
        if (outside == OutsidePolicy::Throw && !(g >= -1e-4 && g <= dims[a] - 1 + 1e-4)) {
            std::ostringstream s;
            s << "point (" << x.x << ", " << x.y << ", " << x.z << ") is outside the volume";
            throw ValueError(s.str());
        }
        if (!(g >= 0.0)) g = 0.0;  // also maps NaN to the boundary
        g = std::min(g, double(dims[a] - 1));
        lo[a] = std::min(int(g), std::max(dims[a] - 2, 0));
        frac[a] = g - lo[a];
    }
}

/// The eight nodes around x and their trilinear weights (double), from locateExact.
/// Along an axis with a single node both corners are that node.
struct TrilinearCorners {
    std::size_t node[8];  ///< grid.index of each corner
    double weight[8];
};

/// The corners of the cell with lower node lo and fractions frac (along an axis with a single
/// node both corners are that node).
inline TrilinearCorners cornersOf(const GridSpec& grid, const int lo[3], const double frac[3]) {
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    TrilinearCorners t;
    for (int corner = 0; corner < 8; ++corner) {
        double w = 1.0;
        int idx[3];
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            idx[a] = std::min(lo[a] + bit, dims[a] - 1);
            w *= bit ? frac[a] : 1.0 - frac[a];
        }
        t.node[corner] = grid.index(idx[0], idx[1], idx[2]);
        t.weight[corner] = w;
    }
    return t;
}

inline TrilinearCorners trilinearCorners(const GridSpec& grid, const Vec3d& x, OutsidePolicy outside) {
    int lo[3];
    double frac[3];
    locateExact(grid, x, outside, lo, frac);
    return cornersOf(grid, lo, frac);
}

/// The simple reference lookups' corners (referenceLookup, referenceVectorLookup): x clamped
/// into the node box, no snapping; along an axis with a single node both corners are that node.
inline TrilinearCorners referenceCorners(const GridSpec& grid, const Vec3d& x) {
    const Vec3d lattice = (x - grid.origin) / grid.spacing;
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    int lo[3];
    double frac[3];
    for (int a = 0; a < 3; ++a) {
        const double c = std::min(std::max(lattice[a], 0.0), double(dims[a] - 1));
        lo[a] = std::min(int(std::floor(c)), std::max(dims[a] - 2, 0));
        frac[a] = c - lo[a];
    }
    return cornersOf(grid, lo, frac);
}

}  // namespace query_detail
}  // namespace vdblight
