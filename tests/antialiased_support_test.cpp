// The experimental visible-support option of the anti-aliased pass (AntialiasedOptions::
// visibleSupport): a node's support does not reach across a wall thinner than a cell.
#include <gtest/gtest.h>

#include "bake/bake_antialiased.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

#include "support/scene_generators.h"

using namespace vdblight;

namespace {
/// Room [0,4]x[0,2]x[0,2] closed by a solid wall x in [1.95, 2.05] (no door), a point light
/// on the x < 2 side only: the x > 2.05 side receives exactly no light.
Scene dividedRoom() {
    Scene s;
    s.name = "divided_room";
    Material m;
    m.albedo = {0.6f, 0.6f, 0.6f};
    addMaterial(s, m);
    appendBox(s, {0, 0, 0}, {4, 2, 2}, /*inward=*/true, 0);
    appendBox(s, {1.95f, -0.01f, -0.01f}, {2.05f, 2.01f, 2.01f}, /*inward=*/false, 0);
    s.pointLights.push_back({{1, 1, 1}, {5, 5, 5}});
    return s;
}

/// Nodes at x = 0.125 + 0.25 i: the wall lies inside the cells [1.875, 2.125].
GridSpec shiftedGrid() {
    GridSpec g;
    g.origin = {0.125, 0.25, 0.25};
    g.spacing = 0.25;
    g.nx = 16, g.ny = 7, g.nz = 7;
    return g;
}

double maxAbsOnDarkSide(const Volume& v, double* litNode) {
    const GridSpec& g = v.levels[0].grid;
    double m = 0;
    *litNode = 0;
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const std::size_t n = g.index(i, j, k);
                const float* c = &v.levels[0].data[n * sh::kCoeffs * 3];
                if (g.node(i, j, k).x > 2.05)
                    for (int q = 0; q < sh::kCoeffs * 3; ++q) m = std::max(m, double(std::abs(c[q])));
                if (i == 7) *litNode = std::max(*litNode, double(c[0]));  // x = 1.875
            }
    return m;
}
}  // namespace

TEST(AntialiasedSupport, VisibleSupportKeepsLightFromCrossingAThinWall) {
    const Scene s = dividedRoom();
    const Tracer tracer(s);
    AntialiasedOptions o;
    o.raysPerCell = 32;
    o.transport.maxBounces = 1;
    o.domain = DomainMode::Interior;
    double lit = 0;
    // Plain eq. 6: the node at x = 2.125 averages origins from both sides of the wall.
    const Volume plain = bakeShAntialiased(s, tracer, shiftedGrid(), o);
    EXPECT_GT(maxAbsOnDarkSide(plain, &lit), 0.0);
    o.visibleSupport = true;
    const Volume visible = bakeShAntialiased(s, tracer, shiftedGrid(), o);
    EXPECT_EQ(maxAbsOnDarkSide(visible, &lit), 0.0);  // exactly black, as the reference
    EXPECT_GT(lit, 0.0);                                // and the lit side next to the wall is lit
    EXPECT_EQ(metaString(visible.meta, "support", ""), "visible (origin-to-node occlusion test)");
}
