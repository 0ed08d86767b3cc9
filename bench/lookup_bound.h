// The memory-bandwidth bound of a dense lookup's access pattern, for vdblight_bench's query rows.
//
// A lookup of a uniform volume reads, at the eight corners of the cell around x, a fixed number
// of bytes per node from each of its node arrays (coefficients, depth moments, visibility). The
// bound does exactly that for the same points and nothing else: it finds the lower corner node
// of x's cell (the same clamped split as the lookups), and sums the floats of the eight corners
// of every array in a loop the compiler vectorises. No basis, no weights, no normal: what is
// left is the time to bring those bytes in, which no lookup of that layout can beat. The
// arrays are the lookup's own layout (node-major, `floatsPerNode` floats per node), filled with
// arbitrary values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "bench_util.h"
#include "vdblight/layout/layout.h"

namespace vdblight::bench {

/// One node array a lookup reads: `floatsPerNode` contiguous floats per node of the grid.
struct GatheredArray {
    int floatsPerNode = 0;
    std::vector<float> data;
};

/// Arrays of the given sizes for `grid` (values i % 7, so that nothing is zero or constant).
inline std::vector<GatheredArray> gatheredArrays(const GridSpec& grid, const std::vector<int>& floatsPerNode) {
    std::vector<GatheredArray> arrays;
    for (const int f : floatsPerNode) {
        GatheredArray a;
        a.floatsPerNode = f;
        a.data.resize(grid.nodeCount() * std::size_t(f));
        for (std::size_t i = 0; i < a.data.size(); ++i) a.data[i] = float(i % 7);
        arrays.push_back(std::move(a));
    }
    return arrays;
}

namespace bound_detail {
/// Lattice coordinate g along an axis of n >= 2 nodes, clamped, to the cell's lower node.
inline int lowerNode(float g, int n) {
    if (!(g >= 0.0f)) g = 0.0f;
    return std::min(int(g), n - 2);
}

/// acc[f] += the sum over the eight corners of floats f of `base`'s node plus the strides.
inline void addCorners(const float* base, std::size_t sx, std::size_t sy, std::size_t sz, int count, float* acc) {
    const float* p[8] = {base, base + sx, base + sy, base + sx + sy, base + sz, base + sx + sz, base + sy + sz,
                         base + sx + sy + sz};
    for (int f = 0; f < count; ++f)
        acc[f] += ((p[0][f] + p[1][f]) + (p[2][f] + p[3][f])) + ((p[4][f] + p[5][f]) + (p[6][f] + p[7][f]));
}
}  // namespace bound_detail

/// Lookups per second (of the thread's CPU time, the best stretch of `repeats` passes, as
/// bench::lookupRate) of the gather-and-sum over `arrays` at the points of `in` (grid of at
/// least 2 nodes per axis). The sum goes to `sink` (print it).
inline double gatherBoundRate(const GridSpec& grid, const std::vector<GatheredArray>& arrays, const LookupInputs& in,
                              int repeats, float& sink) {
    const Vec3f origin(grid.origin);
    const float inv = float(1.0 / grid.spacing);
    constexpr int kMaxFloats = 128;
    float acc[kMaxFloats] = {};
    double best = 0;
    for (int r = 0; r < repeats; ++r)
        for (std::size_t begin = 0; begin < in.points.size(); begin += kTimedStretch) {  // as lookupRate
            const std::size_t stop = std::min(in.points.size(), begin + kTimedStretch);
            const double t0 = threadSeconds();
            for (std::size_t i = begin; i < stop; ++i) {
                const Vec3f g = (in.points[i] - origin) * inv;
                const std::size_t node = grid.index(bound_detail::lowerNode(g.x, grid.nx), bound_detail::lowerNode(g.y, grid.ny),
                                                    bound_detail::lowerNode(g.z, grid.nz));
                for (const GatheredArray& a : arrays) {
                    const std::size_t f = std::size_t(a.floatsPerNode);
                    bound_detail::addCorners(a.data.data() + node * f, f, f * grid.nx, f * grid.nx * grid.ny,
                                             std::min(a.floatsPerNode, kMaxFloats), acc);
                }
            }
            best = std::max(best, double(stop - begin) / (threadSeconds() - t0));
        }
    for (const float a : acc) sink += a;
    return best;
}

}  // namespace vdblight::bench
