// Grid placement: nodes inset from the scene walls, explicit bounds honoured, absurd
// requests refused before allocating anything.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

using namespace vdblight;

namespace {
Bounds box(double x0, double y0, double z0, double x1, double y1, double z1) {
    Bounds b;
    b.lo = {x0, y0, z0};
    b.hi = {x1, y1, z1};
    return b;
}
}  // namespace

TEST(Layout, ResolutionPlacesCellCentredNodesInsideSceneBounds) {
    GridPlacement p;
    p.resolution = 10;
    const GridSpec g = placeUniformGrid(box(0, 0, 0, 2, 1, 0.6), p, 1);
    EXPECT_EQ(g.nx, 10);
    EXPECT_EQ(g.ny, 5);
    EXPECT_EQ(g.nz, 3);
    EXPECT_DOUBLE_EQ(g.spacing, 0.2);
    // Inset by half a spacing along the resolved axis: no node on a wall.
    EXPECT_NEAR(g.origin.x, 0.1, 1e-12);
    EXPECT_NEAR(g.node(g.nx - 1, 0, 0).x, 1.9, 1e-12);
    const Bounds nb = g.nodeBounds();
    EXPECT_GT(nb.lo.y, 0.0);
    EXPECT_LT(nb.hi.y, 1.0);
    EXPECT_NEAR(nb.center().z, 0.3, 1e-12);
}

TEST(Layout, ExplicitBoundsPutOuterNodesOnTheBox) {
    GridPlacement p;
    p.resolution = 5;
    p.bounds = box(-1, -1, -1, 1, 1, 1);
    const GridSpec g = placeUniformGrid(box(0, 0, 0, 1, 1, 1), p, 1);
    EXPECT_EQ(g.nx, 5);
    EXPECT_DOUBLE_EQ(g.spacing, 0.5);
    EXPECT_NEAR(g.origin.x, -1.0, 1e-12);
    EXPECT_NEAR(g.node(4, 4, 4).z, 1.0, 1e-12);
}

TEST(Layout, NodeIndexRoundTrips) {
    GridPlacement p;
    p.spacing = 0.25;
    const GridSpec g = placeUniformGrid(box(0, 0, 0, 1, 0.75, 0.5), p, 1);
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const Vec3d a = g.node(i, j, k), b = g.node(g.index(i, j, k));
                ASSERT_EQ(a, b);
            }
}

TEST(Layout, RefusesBadValuesWithAClearMessage) {
    GridPlacement p;
    EXPECT_THROW(placeUniformGrid(box(0, 0, 0, 1, 1, 1), p, 1), ValueError);  // neither
    p.spacing = -1;
    EXPECT_THROW(placeUniformGrid(box(0, 0, 0, 1, 1, 1), p, 1), ValueError);
    p.spacing = 0;
    p.resolution = -3;
    EXPECT_THROW(placeUniformGrid(box(0, 0, 0, 1, 1, 1), p, 1), ValueError);
    GridPlacement spacingOnly;
    spacingOnly.spacing = 0.1;
    EXPECT_THROW(placeUniformGrid(Bounds{}, spacingOnly, 1), ValueError);  // empty box
}

TEST(Layout, RefusesAbsurdGridsWithTheMemoryFigure) {
    GridPlacement p;
    p.spacing = 1e-6;  // 1e18 nodes in a unit cube
    try {
        placeUniformGrid(box(0, 0, 0, 1, 1, 1), p, 216);
        FAIL() << "expected ValueError";
    } catch (const ValueError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("nodes would need"), std::string::npos) << msg;
        EXPECT_NE(msg.find("PiB"), std::string::npos) << msg;
    }
}

// The default bake's grid (node_budget.h, issue 15): about the budget in a box of any shape,
// the same spacing on every axis, 16..64 nodes on the longest axis.
TEST(NodeBudget, GivesAboutTheBudgetWhateverTheShape) {
    const Vec3d boxes[] = {{1, 1, 1}, {8, 2.62, 4.02}, {6, 3, 5}, {16, 4.31, 16}};
    for (const Vec3d& size : boxes) {
        Bounds b;
        b.lo = Vec3d(-1, 2, 3);
        b.hi = b.lo + size;
        GridPlacement p;
        p.spacing = spacingForNodeBudget(b, 16384);
        const GridSpec g = placeUniformGrid(b, p, 1);
        EXPECT_NEAR(double(g.nodeCount()), 16384.0, 0.2 * 16384.0) << size.x << " x " << size.y << " x " << size.z;
        const int longest = std::max(g.nx, std::max(g.ny, g.nz));
        EXPECT_GE(longest, 16);
        EXPECT_LE(longest, 64);
    }
}

TEST(NodeBudget, FlatAndNeedleBoxesStayBetween16And64OnTheLongestAxis) {
    Bounds flat;  // a floor with nothing on it: zero height
    flat.lo = Vec3d(0, 0, 0);
    flat.hi = Vec3d(10, 0, 10);
    EXPECT_NEAR(spacingForNodeBudget(flat, 4096), std::cbrt(10.0 * 10.0 * (10.0 / 16) / 4096), 1e-12);  // height 10/16
    Bounds needle;
    needle.lo = Vec3d(0, 0, 0);
    needle.hi = Vec3d(100, 0.01, 0.01);
    EXPECT_DOUBLE_EQ(spacingForNodeBudget(needle, 16384), 100.0 / 64);  // capped: 64 on the long axis
    EXPECT_DOUBLE_EQ(spacingForNodeBudget(needle, 1), 100.0 / 16);      // never coarser than 16
    EXPECT_THROW(spacingForNodeBudget(needle, 0), ValueError);
    EXPECT_THROW(spacingForNodeBudget(Bounds(), 16384), ValueError);
}
