// Multi-level layouts: the exact triangle-box test against brute-force clipping, which
// cells get refined, which nodes exist, seams that make the lookup continuous (with a
// control that shows jumps without them), the fast lookup against the simple one, and the
// structure checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "refinement_box.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "query/query_levels.h"
#include "basis/sh.h"

using namespace vdblight;

namespace {

Bounds boxOf(Vec3d lo, Vec3d hi) {
    Bounds b;
    b.lo = lo;
    b.hi = hi;
    return b;
}

/// Brute force: clip the triangle by the six planes of the box (Sutherland-Hodgman); it
/// overlaps iff something remains.
bool clipOverlap(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Bounds& box) {
    std::vector<Vec3d> poly = {a, b, c};
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const double bound = side ? box.hi[axis] : box.lo[axis];
            auto inside = [&](const Vec3d& p) { return side ? p[axis] <= bound : p[axis] >= bound; };
            std::vector<Vec3d> out;
            for (std::size_t i = 0; i < poly.size(); ++i) {
                const Vec3d& p = poly[i];
                const Vec3d& q = poly[(i + 1) % poly.size()];
                if (inside(p)) out.push_back(p);
                if (inside(p) != inside(q)) {
                    const double t = (bound - p[axis]) / (q[axis] - p[axis]);
                    out.push_back(p + (q - p) * t);
                }
            }
            poly = out;
            if (poly.empty()) return false;
        }
    return true;
}

/// A small scene for layouts: a floor, a tilted triangle and a thin sliver.
struct Soup {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    void add(Vec3f a, Vec3f b, Vec3f c) {
        const uint32_t base = uint32_t(positions.size());
        positions.insert(positions.end(), {a, b, c});
        indices.insert(indices.end(), {base, base + 1, base + 2});
    }
};

Soup testSoup() {
    Soup s;
    s.add({0.0f, 0.0f, 0.02f}, {1.0f, 0.0f, 0.02f}, {1.0f, 0.97f, 0.02f});  // no exact touching
    s.add({0.3f, 0.2f, 0.5f}, {0.7f, 0.4f, 0.8f}, {0.4f, 0.8f, 0.6f});
    s.add({0.81f, 0.1f, 0.3f}, {0.83f, 0.9f, 0.35f}, {0.82f, 0.5f, 0.9f});
    return s;
}

GridSpec unitGrid(int n) {
    GridSpec g;
    g.origin = Vec3d(0.05, 0.05, 0.05);
    g.spacing = 0.9 / (n - 1);
    g.nx = g.ny = g.nz = n;
    return g;
}

/// testSoup() placed on unitGrid(n) for SH order 2 (108 bytes a node); `refine` and `levels`
/// default to LevelsPlacement's.
LevelLayout placeTestSoup(int n, LayoutKind kind, int refine = LevelsPlacement{}.refine,
                          int levels = LevelsPlacement{}.levels) {
    const Soup s = testSoup();
    LevelsPlacement p;
    p.kind = kind;
    p.refine = refine;
    p.levels = levels;
    return placeLevels(unitGrid(n), s.positions, s.indices, p, 108);
}

Volume layoutVolume(const LevelLayout& layout, uint32_t seed) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels = volumeLevels(layout.levels);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (VolumeLevel& l : v.levels) {
        l.data.resize(l.storedNodes() * 27);
        for (float& f : l.data) f = u(rng);
    }
    return v;
}

Vec3f unitNormal(std::mt19937& rng) {
    std::normal_distribution<float> g;
    return normalize(Vec3f(g(rng), g(rng), g(rng)));
}

/// Largest jump of E(x, n) (max over RGB, relative to max |E|) across the level changes met
/// on `segments` random segments, after subtracting the slope measured on either side.
double maxSeamJump(const Volume& volume, int segments, int* crossings) {
    const ShLevelsLookup lookup(volume, OutsidePolicy::Clamp);
    const Bounds b = lookup.bounds();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    auto randomPoint = [&] {
        return Vec3d(b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y),
                     b.lo.z + u(rng) * (b.hi.z - b.lo.z));
    };
    double worst = 0;
    *crossings = 0;
    for (int s = 0; s < segments; ++s) {
        const Vec3d p = randomPoint(), q = randomPoint();
        const Vec3f n = unitNormal(rng);
        auto at = [&](double t) { return Vec3f(p + (q - p) * t); };
        const int steps = 64;
        for (int i = 0; i < steps; ++i) {
            double t0 = double(i) / steps, t1 = double(i + 1) / steps;
            if (lookup.levelAt(at(t0)) == lookup.levelAt(at(t1))) continue;
            const int l0 = lookup.levelAt(at(t0));
            for (int it = 0; it < 60 && t1 - t0 > 1e-12; ++it) {
                const double tm = 0.5 * (t0 + t1);
                (lookup.levelAt(at(tm)) == l0 ? t0 : t1) = tm;
            }
            // Points d/2 either side of the crossing (far above float resolution), and the
            // change over the same distance just before and just after, to remove the slope.
            const double d = 1e-5, tc = 0.5 * (t0 + t1);
            const Rgb ea = lookup.irradiance(at(tc - d / 2), n), eb = lookup.irradiance(at(tc + d / 2), n);
            const Rgb ea2 = lookup.irradiance(at(tc - 3 * d / 2), n), eb2 = lookup.irradiance(at(tc + 3 * d / 2), n);
            for (int c = 0; c < 3; ++c) {
                const double scale = std::max({std::abs(ea[c]), std::abs(eb[c]), 1e-3f});
                const double slope = std::max(std::abs(ea[c] - ea2[c]), std::abs(eb2[c] - eb[c]));
                worst = std::max(worst, (std::abs(eb[c] - ea[c]) - 2 * slope) / scale);
            }
            ++*crossings;
        }
    }
    return worst;
}

}  // namespace

TEST(TriangleBox, MatchesClippingOnRandomCases) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int overlaps = 0;
    const int cases = 100000;
    for (int i = 0; i < cases; ++i) {
        const Vec3d c(u(rng), u(rng), u(rng));
        const Vec3d h(0.05 + 0.5 * std::abs(u(rng)), 0.05 + 0.5 * std::abs(u(rng)), 0.05 + 0.5 * std::abs(u(rng)));
        const Bounds box = boxOf(c - h, c + h);
        const Vec3d a(u(rng), u(rng), u(rng));
        const Vec3d b = a + Vec3d(u(rng), u(rng), u(rng)) * 0.8, d = a + Vec3d(u(rng), u(rng), u(rng)) * 0.8;
        const bool sat = triangleOverlapsBox(a, b, d, box);
        ASSERT_EQ(sat, clipOverlap(a, b, d, box)) << "case " << i;
        overlaps += sat;
    }
    // Both answers occur often (a test that always said "yes" would fail).
    EXPECT_GT(overlaps, cases / 20);
    EXPECT_LT(overlaps, cases * 9 / 10);
}

TEST(TriangleBox, BoundingBoxesOverlapButTriangleDoesNot) {
    // A diagonal triangle whose bounding box contains the box corner region, but which
    // passes beside the box: a bounding-box test would say yes.
    const Bounds box = boxOf({0, 0, 0}, {0.2, 0.2, 0.2});
    EXPECT_FALSE(triangleOverlapsBox({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, box));
    EXPECT_TRUE(triangleOverlapsBox({0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}, box));
    EXPECT_TRUE(triangleOverlapsBox({0.2, 0.3, 0.1}, {0.4, 0.4, 0.1}, {0.2, 0.5, 0.1}, boxOf({0.2, 0.3, 0}, {1, 1, 1})));
}

TEST(Levels, RefinedCellsAreExactlyTheCellsThatContainGeometry) {
    const Soup s = testSoup();
    const LevelLayout layout = placeTestSoup(6, LayoutKind::Adaptive, 3, 3);
    ASSERT_EQ(layout.levels.size(), 3u);
    EXPECT_EQ(layout.refine, 3);
    const double margin = 0.5 * layout.levels[0].grid.spacing;
    for (std::size_t l = 0; l + 1 < layout.levels.size(); ++l) {
        const GridSpec& g = layout.levels[l].grid;
        std::size_t expected = 0;
        for (int k = 0; k + 1 < g.nz; ++k)
            for (int j = 0; j + 1 < g.ny; ++j)
                for (int i = 0; i + 1 < g.nx; ++i) {
                    // Exists at this level: the parent chain is refined.
                    bool exists = true;
                    for (std::size_t up = 1; up <= l; ++up) {
                        int f = 1;
                        for (std::size_t e = 0; e < up; ++e) f *= 3;
                        exists = exists && isRefined(layout.levels[l - up],
                                                     layout.levels[l - up].grid.index(i / f, j / f, k / f));
                    }
                    Bounds box = boxOf(g.node(i, j, k), g.node(i + 1, j + 1, k + 1));
                    test::extendOnNodeBoxBorder(box, g, i, j, k, margin);
                    bool geometry = false;
                    for (std::size_t t = 0; t < s.indices.size(); t += 3)
                        geometry = geometry || clipOverlap(Vec3d(s.positions[s.indices[t]]), Vec3d(s.positions[s.indices[t + 1]]),
                                                           Vec3d(s.positions[s.indices[t + 2]]), box);
                    const bool want = exists && geometry;
                    EXPECT_EQ(isRefined(layout.levels[l], g.index(i, j, k)), want) << "level " << l << " cell " << i << "," << j << "," << k;
                    expected += want;
                }
        EXPECT_EQ(layout.levels[l].refinedCells.size(), expected);
        EXPECT_GT(expected, 0u);
    }
    // Sparse: far fewer nodes than a dense grid at the finest spacing.
    EXPECT_LT(double(layout.totalNodes()), 0.5 * layout.denseEquivalentNodes());
    // The structure is what the volume checks expect.
    Volume v = layoutVolume(layout, 1);
    EXPECT_NO_THROW(v.validate());
}

TEST(Levels, BilevelHasTwoLevelsAndUniformOne) {
    const Soup s = testSoup();
    LevelsPlacement p;
    p.kind = LayoutKind::Bilevel;
    p.levels = 7;  // ignored by bilevel
    EXPECT_EQ(placeLevels(unitGrid(5), s.positions, s.indices, p, 1).levels.size(), 2u);
    p.kind = LayoutKind::Uniform;
    EXPECT_EQ(placeLevels(unitGrid(5), s.positions, s.indices, p, 1).levels.size(), 1u);
}

TEST(Levels, RefusesBadParametersBeforeAllocating) {
    const Soup s = testSoup();
    LevelsPlacement p;
    p.kind = LayoutKind::Adaptive;
    p.refine = 1;
    EXPECT_THROW(placeLevels(unitGrid(5), s.positions, s.indices, p, 1), ValueError);
    p.refine = 3;
    p.levels = 0;
    EXPECT_THROW(placeLevels(unitGrid(5), s.positions, s.indices, p, 1), ValueError);
    p.levels = 40;  // 3^39 positions per axis: refused by the index-range estimate
    try {
        placeLevels(unitGrid(5), s.positions, s.indices, p, 1);
        FAIL() << "expected ValueError";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("index range"), std::string::npos) << e.what();
    }
    p.levels = 6;
    p.maxNodes = 20000;  // the memory estimate refuses before the level's nodes exist
    try {
        placeLevels(unitGrid(5), s.positions, s.indices, p, 216);
        FAIL() << "expected ValueError";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos) << e.what();
    }
}

TEST(Levels, ANextLevelOverTheLimitIsRefusedWhileItsCellsAreFound) {
    // A refine distance larger than the scene refines every cell, next to every triangle: the
    // third level's cells are refused as soon as their count is over the limit, not after all of
    // them are classified (minutes at --refine 8 on 24^3 nodes), and the decision is the
    // estimate's own, to the node.
    const Soup s = testSoup();
    LevelsPlacement p;
    p.kind = LayoutKind::Adaptive;
    p.levels = 3;
    p.refine = 4;
    p.refineDistance = 100.0;
    const LevelLayout all = placeLevels(unitGrid(5), s.positions, s.indices, p, 1);
    ASSERT_EQ(all.levels.size(), 3u);
    const double perCell = 125.0;  // (4 + 1)^3
    const double estimate = double(all.levels[0].storedNodes() + all.levels[1].storedNodes()) +
                            double(all.levels[1].refinedCells.size()) * perCell;
    EXPECT_EQ(all.levels[1].refinedCells.size(), 16u * 16u * 16u);
    p.maxNodes = uint64_t(estimate);
    EXPECT_EQ(placeLevels(unitGrid(5), s.positions, s.indices, p, 1).levels.size(), 3u);
    p.maxNodes = uint64_t(estimate) - 1;
    EXPECT_THROW(placeLevels(unitGrid(5), s.positions, s.indices, p, 1), ValueError);
    p.maxNodes = 100000;  // level 1 (8 125 at most) fits; level 2 is refused after ~760 cells
    try {
        placeLevels(unitGrid(5), s.positions, s.indices, p, 1);
        FAIL() << "expected ValueError";
    } catch (const ValueError& e) {
        const std::string what = e.what();
        const std::size_t at = what.find("would have more than ");
        ASSERT_NE(at, std::string::npos) << what;
        const double counted = std::stod(what.substr(at + 21));
        EXPECT_GT(counted, 100000.0) << what;
        EXPECT_LE(counted - perCell, 100000.0) << what;  // the first count over the limit
    }
}

TEST(Seams, LookupIsContinuousAcrossLevelBoundaries) {
    const LevelLayout layout = placeTestSoup(6, LayoutKind::Adaptive, 3, 3);
    Volume v = layoutVolume(layout, 11);
    applySeamConstraints(v);
    int crossings = 0;
    const double jump = maxSeamJump(v, 300, &crossings);
    EXPECT_GT(crossings, 200);
    EXPECT_LT(jump, 2e-5) << "over " << crossings << " crossings";
    std::printf("largest relative jump of E over %d level crossings: %.3g\n", crossings, jump);

    // Control: the same random volume without seam constraints jumps at the boundaries.
    Volume raw = layoutVolume(layout, 11);
    int rawCrossings = 0;
    const double rawJump = maxSeamJump(raw, 300, &rawCrossings);
    EXPECT_GT(rawJump, 0.05);
    std::printf("without seam constraints: %.3g\n", rawJump);
}

TEST(Seams, SeamNodesTouchAnUnrefinedCoarseCellAndOthersDoNot) {
    const LevelLayout layout = placeTestSoup(6, LayoutKind::Bilevel);
    const std::vector<std::size_t> seams = seamNodes(layout.levels, 1, 3);
    const LevelTopology& fine = layout.levels[1];
    EXPECT_GT(seams.size(), 0u);
    EXPECT_LT(seams.size(), fine.activeNodes.size());
    // A node strictly inside a refined coarse cell is never a seam node.
    for (std::size_t n : seams) {
        const uint64_t lin = fine.activeNodes[n];
        const int i = int(lin % fine.grid.nx), j = int(lin / fine.grid.nx % fine.grid.ny), k = int(lin / (uint64_t(fine.grid.nx) * fine.grid.ny));
        EXPECT_TRUE(i % 3 == 0 || j % 3 == 0 || k % 3 == 0) << "seam node inside a cell";
    }
}

TEST(LevelsLookup, MatchesReferenceAndNeverReadsAnUnbakedNode) {
    const LevelLayout layout = placeTestSoup(5, LayoutKind::Adaptive, 2, 4);
    ASSERT_EQ(layout.levels.size(), 4u);
    Volume v = layoutVolume(layout, 5);
    applySeamConstraints(v);
    const IrradianceQuery query(v);
    EXPECT_STREQ(query.kind(), "sh2-levels");
    const ShLevelsLookup lookup(v, OutsidePolicy::Clamp);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.05, 1.05);  // also outside (clamped)
    int perLevel[4] = {};
    for (int i = 0; i < 20000; ++i) {
        Vec3d x(u(rng), u(rng), u(rng));
        if (i % 4 == 0) x = v.levels[3].grid.node(v.levels[3].activeNodes[std::size_t(i) % v.levels[3].activeNodes.size()]);
        const Vec3f n = unitNormal(rng);
        int level = -1;
        Rgbd ref;
        ASSERT_NO_THROW(ref = referenceLevelsLookup(v, x, Vec3d(n), &level)) << "point " << i;
        const Rgb e = query.irradiance(Vec3f(x), n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], ref[c], 2e-5 * std::max(1.0, std::abs(ref[c]))) << "point " << i;
        perLevel[std::min(level, 3)]++;
    }
    for (int l = 0; l < 4; ++l) EXPECT_GT(perLevel[l], 100) << "level " << l << " never used";
}

TEST(LevelsStructure, InconsistentStructuresAreRefusedWithTheProblemNamed) {
    const LevelLayout layout = placeTestSoup(6, LayoutKind::Adaptive);
    const Volume good = layoutVolume(layout, 2);
    auto expectRefused = [](Volume v, const std::string& text) {
        try {
            v.validate();
            ADD_FAILURE() << "accepted; expected '" << text << "'";
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    Volume v = good;
    v.levels[0].refinedCells.clear();  // missing mask
    expectRefused(v, "missing mask");
    v = good;
    v.levels[1].grid.origin.x += 0.01;
    expectRefused(v, "origin");
    v = good;
    v.levels[2].grid.spacing *= 1.5;
    expectRefused(v, "spacing");
    v = good;
    v.levels[1].activeNodes.pop_back();
    v.levels[1].data.resize(v.levels[1].activeNodes.size() * 27);
    expectRefused(v, "active nodes");
    v = good;
    v.levels[1].refinedCells.push_back(v.levels[1].grid.index(0, 0, 0) + 0);  // out of order
    expectRefused(v, "refined cells");
    v = good;
    v.levels[2].refinedCells.push_back(0);
    expectRefused(v, "finest level");
}
