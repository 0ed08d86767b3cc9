// Fixtures of the tests of the bake's error-driven choices (first_pass_by_error_test,
// extra_cache_paths_test, direction_guide_test): an error field of two rooms on a small grid, and
// the node grid on which those tests bake the thin-wall scene (support/leak_scenes.h).
#pragma once

#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"

namespace vdblight::test {

constexpr int kTwoRoomsN = 8;

/// kTwoRoomsN^3 nodes at unit spacing from the origin.
inline GridSpec twoRoomsGrid() {
    GridSpec g;
    g.nx = g.ny = g.nz = kTwoRoomsN;
    return g;
}

/// Pass 0's relative errors on twoRoomsGrid(): `dark` in the quarter x >= 6 (a room lit through
/// a door), 0.05 in the rest.
inline std::vector<float> twoRoomsErrors(float dark) {
    std::vector<float> e(std::size_t(kTwoRoomsN * kTwoRoomsN * kTwoRoomsN), 0.05f);
    const GridSpec g = twoRoomsGrid();
    for (int k = 0; k < kTwoRoomsN; ++k)
        for (int j = 0; j < kTwoRoomsN; ++j)
            for (int i = 6; i < kTwoRoomsN; ++i) e[g.index(i, j, k)] = dark;
    return e;
}

/// The thin-wall room's nodes at spacing 0.25, none on its outer walls: 15 x 7 x 7 from 0.25.
inline GridSpec thinWallNodes() {
    GridSpec g;
    g.origin = Vec3d(0.25, 0.25, 0.25);
    g.spacing = 0.25;
    g.nx = 15;
    g.ny = g.nz = 7;
    return g;
}

}  // namespace vdblight::test
