// LevelsPlacement::refineDistance (bake --refine-distance): a cell is refined when a
// triangle lies within D of it (its test box grown by D overlaps the triangle). Checked
// against a brute-force test of every cell against every triangle on two levels; D = 0 is
// Greger's rule; the refined set grows with D; bad distances are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "refinement_box.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;

namespace {

const Scene& cornell() {
    static const Scene s = loadScene(defaultScenePath());
    return s;
}

GridSpec level0(int resolution) {
    GridPlacement gp;
    gp.resolution = resolution;
    return placeUniformGrid(cornell().bounds(), gp, 1);
}

LevelLayout place(int resolution, double distance, int levels = 3) {
    LevelsPlacement p;
    p.kind = LayoutKind::Adaptive;
    p.refine = 3;
    p.levels = levels;
    p.refineDistance = distance;
    return placeLevels(level0(resolution), cornell().positions, cornell().indices, p, 1);
}

/// Brute force: cells of level l (level 0: all; below: children of refined cells) whose box,
/// pushed out by half a level-0 spacing on the node-box border and grown by D, overlaps a triangle.
std::vector<uint64_t> bruteRefined(const LevelLayout& layout, std::size_t l, double D) {
    const Scene& s = cornell();
    const GridSpec& g = layout.levels[l].grid;
    const int K = layout.refine;
    const double margin = 0.5 * layout.levels[0].grid.spacing;
    std::vector<uint64_t> out;
    for (int k = 0; k + 1 < g.nz; ++k)
        for (int j = 0; j + 1 < g.ny; ++j)
            for (int i = 0; i + 1 < g.nx; ++i) {
                if (l > 0) {
                    const LevelTopology& parent = layout.levels[l - 1];
                    if (!isRefined(parent, parent.grid.index(i / K, j / K, k / K))) continue;
                }
                const auto testBox = [&](const GridSpec& gg, int ii, int jj, int kk) {
                    Bounds box;
                    box.lo = gg.node(ii, jj, kk);
                    box.hi = box.lo + Vec3d(gg.spacing, gg.spacing, gg.spacing);
                    test::extendOnNodeBoxBorder(box, gg, ii, jj, kk, margin);
                    for (int a = 0; a < 3; ++a) box.lo[a] -= D, box.hi[a] += D;
                    return box;
                };
                const Bounds box = testBox(g, i, j, k);
                // The hierarchy only tests a child against triangles that touched its parent: a
                // wall exactly on a border cell's extended face may touch the child's box and
                // miss the parent's by one rounding step (8 h0 + h0 vs 27 h0 / 3).
                const Bounds parentBox = l > 0 ? testBox(layout.levels[l - 1].grid, i / K, j / K, k / K) : box;
                for (std::size_t t = 0; t < s.triangleCount(); ++t)
                    if (triangleOverlapsBox(Vec3d(s.vertex(t, 0)), Vec3d(s.vertex(t, 1)), Vec3d(s.vertex(t, 2)), box) &&
                        triangleOverlapsBox(Vec3d(s.vertex(t, 0)), Vec3d(s.vertex(t, 1)), Vec3d(s.vertex(t, 2)), parentBox)) {
                        out.push_back(g.index(i, j, k));
                        break;
                    }
            }
    return out;
}

}  // namespace

TEST(RefineDistance, RefinedCellsMatchBruteForce) {
    for (double D : {0.0, 0.02, 0.05}) {
        const LevelLayout layout = place(10, D);
        ASSERT_EQ(layout.levels.size(), 3u);
        for (std::size_t l = 0; l < 2; ++l) {
            const std::vector<uint64_t> brute = bruteRefined(layout, l, D);
            std::vector<uint64_t> onlyPlaced, onlyBrute;
            const auto& placed = layout.levels[l].refinedCells;
            std::set_difference(placed.begin(), placed.end(), brute.begin(), brute.end(), std::back_inserter(onlyPlaced));
            std::set_difference(brute.begin(), brute.end(), placed.begin(), placed.end(), std::back_inserter(onlyBrute));
            EXPECT_TRUE(onlyPlaced.empty() && onlyBrute.empty())
                << "D = " << D << ", level " << l << ": " << onlyPlaced.size() << " cells only placed (first "
                << (onlyPlaced.empty() ? -1 : int64_t(onlyPlaced[0])) << "), " << onlyBrute.size()
                << " only brute force (first " << (onlyBrute.empty() ? -1 : int64_t(onlyBrute[0])) << ")";
        }
    }
}

TEST(RefineDistance, ZeroIsGregersRuleAndTheSetGrowsWithDistance) {
    LevelsPlacement p;
    p.kind = LayoutKind::Adaptive;
    p.refine = 3;
    p.levels = 3;
    const LevelLayout plain = placeLevels(level0(10), cornell().positions, cornell().indices, p, 1);
    const LevelLayout zero = place(10, 0.0);
    for (std::size_t l = 0; l < plain.levels.size(); ++l) {
        EXPECT_EQ(plain.levels[l].refinedCells, zero.levels[l].refinedCells);
        EXPECT_EQ(plain.levels[l].activeNodes, zero.levels[l].activeNodes);
    }
    const LevelLayout wide = place(10, 0.04);
    for (std::size_t l = 0; l < 2; ++l) {
        const auto& a = zero.levels[l].refinedCells;
        const auto& b = wide.levels[l].refinedCells;
        EXPECT_TRUE(std::includes(b.begin(), b.end(), a.begin(), a.end())) << "level " << l;
        EXPECT_GT(b.size(), a.size()) << "level " << l;
    }
    EXPECT_GT(wide.totalNodes(), zero.totalNodes());
}

TEST(RefineDistance, BadDistancesAreRefused) {
    EXPECT_THROW(place(6, -0.01), ValueError);
    EXPECT_THROW(place(6, std::numeric_limits<double>::quiet_NaN()), ValueError);
    EXPECT_THROW(place(6, std::numeric_limits<double>::infinity()), ValueError);
    LevelsPlacement p;
    p.kind = LayoutKind::Adaptive;
    p.levels = 4;
    p.refineDistance = 10.0;  // everything refined: caught by the node estimate before allocating
    p.maxNodes = 1'000'000;
    EXPECT_THROW(placeLevels(level0(16), cornell().positions, cornell().indices, p, 1), ValueError);
}
