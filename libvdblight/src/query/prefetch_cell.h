// Asking the memory system early for the nodes a lookup will read (issue 33, part 4). A lookup
// of a large volume reads eight scattered corners (the default volume: 272 B of coefficients
// and depth per corner, then the lights' visibility and shadow edges), and its arithmetic
// (depth weights, SH terms, the lights' exact irradiance) waits for them: the default lookup
// spent about 110 of its 270 ns on memory at random points of a 32^3 volume. A prefetch
// retires at once, so the loads of all the corners' cache lines overlap each other and the
// arithmetic that does not need them. A prefetch of the wrong lines costs only bandwidth: the
// cell here is located in float without the lookups' checks (which stay where they are).
// (Internal to the query module.)
#pragma once

#include <cstddef>

#include "lattice_locate.h"
#include "vdblight/layout/layout.h"

namespace vdblight::query_detail {

/// The lower corner node of the cell around lattice coordinate g (clamped, as the lookups
/// locate it) and the node strides to the other corners (0 along an axis with one node).
struct CellNodes {
    std::size_t lower = 0, sx = 0, sy = 0, sz = 0;
};

inline CellNodes cellNodes(const GridSpec& grid, const float g[3]) {
    int idx[3] = {0, 0, 0};
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    for (int a = 0; a < 3; ++a) {
        float f = 0;
        if (dims[a] >= 2) splitCell(g[a], dims[a], idx[a], f);
    }
    CellNodes c;
    c.lower = grid.index(idx[0], idx[1], idx[2]);
    c.sx = dims[0] > 1;
    c.sy = dims[1] > 1 ? std::size_t(dims[0]) : 0;
    c.sz = dims[2] > 1 ? std::size_t(dims[0]) * dims[1] : 0;
    return c;
}

/// Prefetches (for reading) every cache line of the cell's corner nodes in a node-major array
/// of `floatsPerNode` floats per node: the x-neighbours are adjacent, so each of the four
/// rows is one stretch of two nodes.
inline void prefetchCell(const CellNodes& cell, const float* data, std::size_t floatsPerNode) {
    constexpr std::size_t kLine = 64;
    const std::size_t rows[4] = {cell.lower, cell.lower + cell.sy, cell.lower + cell.sz, cell.lower + cell.sy + cell.sz};
    for (const std::size_t row : rows) {
        const char* begin = reinterpret_cast<const char*>(data + row * floatsPerNode);
        const char* end = reinterpret_cast<const char*>(data + (row + cell.sx + 1) * floatsPerNode);
        for (const char* p = begin; p < end; p += kLine) __builtin_prefetch(p);
        __builtin_prefetch(end - 1);  // the last line, where the stretch does not start on a line
    }
}

}  // namespace vdblight::query_detail
