// The sparse, exact sums of the surface probe cache's bins (surface_bin_sums.h): the merge of
// stage-0 tiles adds them; stage 1 checks them before it reads them.
#include "vdblight/volume/volume.h"

#include <cmath>
#include <string>

#include "vdblight/core/errors.h"

namespace vdblight {

void SurfaceBinSums::add(const SurfaceBinSums& other) {
    if (other.cellIndices.empty()) return;
    if (cellIndices.empty()) {
        *this = other;
        return;
    }
    if (other.unit != unit) throw ValueError("the surface bins differ in their unit");
    // A merge of two ascending lists; a cell in both gets the sum of its values.
    constexpr std::size_t V = kValuesPerCell;
    std::vector<uint64_t> indices, sums;
    indices.reserve(cellIndices.size() + other.cellIndices.size());
    sums.reserve(indices.capacity() * V);
    std::size_t a = 0, b = 0;
    while (a < cellIndices.size() || b < other.cellIndices.size()) {
        const bool takeA = b == other.cellIndices.size() || (a < cellIndices.size() && cellIndices[a] <= other.cellIndices[b]);
        const bool takeB = a == cellIndices.size() || (b < other.cellIndices.size() && other.cellIndices[b] <= cellIndices[a]);
        indices.push_back(takeA ? cellIndices[a] : other.cellIndices[b]);
        const std::size_t at = sums.size();
        sums.resize(at + V, 0);
        if (takeA)
            for (std::size_t v = 0; v < V; ++v) sums[at + v] += values[a * V + v];
        if (takeB)
            for (std::size_t v = 0; v < V; ++v) sums[at + v] += other.values[b * V + v];
        a += takeA;
        b += takeB;
    }
    cellIndices = std::move(indices);
    values = std::move(sums);
}

void SurfaceBinSums::validate(const std::array<int, 3>& cells) const {
    if (!(unit > 0) || !std::isfinite(unit)) throw ValueError("the surface bins' unit is not a positive number");
    if (values.size() != cellIndices.size() * std::size_t(kValuesPerCell))
        throw ValueError("the surface bins have " + std::to_string(values.size()) + " values for " +
                         std::to_string(cellIndices.size()) + " cells");
    const uint64_t count = cellCount(cells);
    for (std::size_t c = 0; c < cellIndices.size(); ++c)
        if (cellIndices[c] >= count || (c > 0 && cellIndices[c] <= cellIndices[c - 1]))
            throw ValueError("the surface bins' cells do not fit this grid");
}

}  // namespace vdblight
