// Node grids for tests: an explicit lattice, or the usual placement over a box.
#pragma once

#include "vdblight/layout/layout.h"

namespace vdblight::test {

/// nx x ny x nz nodes `spacing` apart, the first at `origin`.
inline GridSpec makeGrid(const Vec3d& origin, double spacing, int nx, int ny, int nz) {
    GridSpec g;
    g.origin = origin;
    g.spacing = spacing;
    g.nx = nx, g.ny = ny, g.nz = nz;
    return g;
}

/// placeUniformGrid over `box` (scene bounds, default inset) with `resolution` nodes along
/// its longest axis.
inline GridSpec gridIn(const Bounds& box, int resolution) {
    GridPlacement p;
    p.resolution = resolution;
    return placeUniformGrid(box, p, 1);
}

}  // namespace vdblight::test
