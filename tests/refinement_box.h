// The refinement test box of a cell (docs/format.md, "Levels"): cells on the border of the
// node box are tested extended outwards by half a level-0 spacing.
#pragma once

#include "vdblight/layout/layout.h"

namespace vdblight::test {

/// Pushes `box`, the box of cell (i, j, k) of grid `g`, out by `margin` on each side where
/// the cell lies on the border of the node box.
inline void extendOnNodeBoxBorder(Bounds& box, const GridSpec& g, int i, int j, int k, double margin) {
    const int idx[3] = {i, j, k}, dims[3] = {g.nx, g.ny, g.nz};
    for (int a = 0; a < 3; ++a) {
        if (idx[a] == 0) box.lo[a] -= margin;
        if (idx[a] == dims[a] - 2) box.hi[a] += margin;
    }
}

}  // namespace vdblight::test
