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

/// Mean over the nodes of `g` on one side of the thin wall (x > 2.2: behind it, lit only through
/// the door; x < 1.8: the lit room) of `perNode(n)`.
template <typename PerNode>
double meanOnSide(const GridSpec& g, bool behind, PerNode perNode) {
    double sum = 0;
    int count = 0;
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const double x = g.node(i, j, k).x;
                if (behind ? x < 2.2 : x > 1.8) continue;
                sum += perNode(g.index(i, j, k));
                ++count;
            }
    return sum / count;
}

}  // namespace vdblight::test
