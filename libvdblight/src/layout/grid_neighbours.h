// The nodes of a uniform grid around a node: one loop for every pass that reads a node's
// neighbourhood (dilation, the node filter, the probe-direction guide's pooling, the pass blend).
#pragma once

#include <vector>

#include "vdblight/layout/layout.h"

namespace vdblight {

/// Calls visit(a, b, c, di, dj, dk) for every node (a, b, c) = (i + di, j + dj, k + dk) of `grid`
/// with |di|, |dj|, |dk| <= radius (the node itself included), skipping offsets outside the grid.
/// Always k outermost, then j, then i: sums over a neighbourhood keep one order, so their bits.
template <typename Visit>
void forEachNodeAround(const GridSpec& grid, int i, int j, int k, int radius, Visit&& visit) {
    for (int dk = -radius; dk <= radius; ++dk) {
        const int c = k + dk;
        if (c < 0 || c >= grid.nz) continue;
        for (int dj = -radius; dj <= radius; ++dj) {
            const int b = j + dj;
            if (b < 0 || b >= grid.ny) continue;
            for (int di = -radius; di <= radius; ++di) {
                const int a = i + di;
                if (a < 0 || a >= grid.nx) continue;
                visit(a, b, c, di, dj, dk);
            }
        }
    }
}

/// Mean of values[grid.index(a, b, c)]^2 over the nodes forEachNodeAround visits that
/// `keep(value)` accepts, summed in double in its order; `ifNone` where it accepts none. The
/// bake's error-driven choices pool a node's noisy error estimate with its neighbours' this way.
template <typename Keep>
double meanSquareAround(const GridSpec& grid, const std::vector<float>& values, int i, int j, int k, int radius,
                        Keep&& keep, double ifNone) {
    double sum = 0;
    int count = 0;
    forEachNodeAround(grid, i, j, k, radius, [&](int a, int b, int c, int, int, int) {
        const float v = values[grid.index(a, b, c)];
        if (!keep(v)) return;
        sum += double(v) * double(v);
        ++count;
    });
    return count ? sum / count : ifNone;
}

}  // namespace vdblight
