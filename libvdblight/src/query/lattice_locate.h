// Locating a point among the nodes of one uniform level, in double precision. (Internal to
// the query module.) The export hooks use it: a point at a node's position must return
// exactly that node, so positions within 1e-9 of a node are snapped onto it.
#pragma once

#include <cmath>
#include <sstream>

#include "vdblight/errors.h"
#include "vdblight/layout.h"
#include "vdblight/query.h"

namespace vdblight {
namespace query_detail {

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

inline TrilinearCorners trilinearCorners(const GridSpec& grid, const Vec3d& x, OutsidePolicy outside) {
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    int lo[3];
    double frac[3];
    locateExact(grid, x, outside, lo, frac);
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

}  // namespace query_detail
}  // namespace vdblight
