// `bake --probe-cache surface`'s bins (bake/surface_bins.h) as exact integer sums, which a
// probe stage volume carries from stage 0 through the merge to stage 1 (tiles.h, "Staged
// bakes"): integers add exactly in any order, so the merge of the tiles' sums is the whole
// bake's.
//
// Sparse: only the cells that hold samples are listed. The samples lie on surfaces, so a bake
// touches a thin shell of its cells, and a tile only the cells its own nodes' paths reached;
// a dense array would cost every tile the whole grid's bins (issue 15, tile memory).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "vdblight/layout.h"

namespace vdblight {

/// Cells of the node grid: cell (i, j, k) spans nodes i..i+1, j..j+1, k..k+1, linear index
/// (k * cy + j) * cx + i. Per cell kBinsPerCell bins (the normal's signed axis: 2a for +a,
/// 2a + 1 for -a), per bin kValuesPerBin values: the irradiance sums r, g, b in units of
/// `unit`, the sample count, the position sums x, y, z (SurfaceBins' fixed point).
struct SurfaceBinSums {
    static constexpr int kValuesPerBin = 7;
    static constexpr int kBinsPerCell = 6;
    static constexpr int kValuesPerCell = kValuesPerBin * kBinsPerCell;
    /// Irradiance per integer step.
    double unit = 0;
    /// The listed cells' linear indices, strictly ascending.
    std::vector<uint64_t> cellIndices;
    /// kValuesPerCell values per listed cell, in cellIndices' order: bin `face`'s values start
    /// at face * kValuesPerBin.
    std::vector<uint64_t> values;

    /// The cells of `grid` along each axis (at least one).
    static std::array<int, 3> cells(const GridSpec& grid) {
        return {std::max(1, grid.nx - 1), std::max(1, grid.ny - 1), std::max(1, grid.nz - 1)};
    }
    static uint64_t cellCount(const std::array<int, 3>& cells) {
        return uint64_t(cells[0]) * uint64_t(cells[1]) * uint64_t(cells[2]);
    }
    /// The linear index of cell (i, j, k), which must lie inside `cells`.
    static uint64_t cellIndex(const std::array<int, 3>& cells, int i, int j, int k) {
        return (uint64_t(k) * uint64_t(cells[1]) + uint64_t(j)) * uint64_t(cells[0]) + uint64_t(i);
    }
    /// Cell (i, j, k) of linear index `index`.
    static std::array<int, 3> cellCoord(const std::array<int, 3>& cells, uint64_t index) {
        const uint64_t cx = uint64_t(cells[0]), cy = uint64_t(cells[1]);
        return {int(index % cx), int(index / cx % cy), int(index / (cx * cy))};
    }

    /// Adds `other`'s sums (exact; the union of the listed cells). ValueError if the units
    /// differ.
    void add(const SurfaceBinSums& other);
    /// ValueError unless the unit is positive and finite, the indices ascend strictly and lie
    /// inside `cells`, and `values` has kValuesPerCell per listed cell.
    void validate(const std::array<int, 3>& cells) const;
};

}  // namespace vdblight
