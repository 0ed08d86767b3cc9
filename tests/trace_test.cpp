// The tracer finds the closest triangle, respects ray extents and reports the triangle's
// own index, so materials can be looked up.
#include <gtest/gtest.h>

#include "test_util.h"
#include "vdblight/errors.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"

using namespace vdblight;

TEST(Tracer, HitsTheClosestWallOfABoxFromInside) {
    const Scene s = test::makeFurnaceBox({-1, -2, -3}, {1, 2, 3}, {1, 1, 1}, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(s);
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const float dist[6] = {1, 1, 2, 2, 3, 3};
    for (int d = 0; d < 6; ++d) {
        const Hit h = tracer.intersect(Ray{{0.1f, 0.2f, 0.3f}, dirs[d]});
        ASSERT_TRUE(h.hit());
        const float expected = dist[d] - dot(Vec3f(0.1f, 0.2f, 0.3f), dirs[d]);
        EXPECT_NEAR(h.t, expected, 1e-5f);
        ASSERT_LT(h.triangle, s.triangleCount());
        // The hit triangle lies in the plane that was hit.
        const Vec3f p = s.vertex(h.triangle, 0);
        EXPECT_NEAR(dot(p, dirs[d]), dist[d], 1e-5f);
    }
}

TEST(Tracer, RespectsRayExtentAndOcclusion) {
    const Scene s = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(s);
    EXPECT_FALSE(tracer.intersect(Ray{{0, 0, 0}, {1, 0, 0}, 0.0f, 0.5f}).hit());
    EXPECT_FALSE(tracer.occluded(Ray{{0, 0, 0}, {1, 0, 0}, 0.0f, 0.99f}));
    EXPECT_TRUE(tracer.occluded(Ray{{0, 0, 0}, {1, 0, 0}, 0.0f, 1.01f}));
    // Outside, looking away: nothing.
    EXPECT_FALSE(tracer.intersect(Ray{{3, 0, 0}, {1, 0, 0}}).hit());
}

TEST(Tracer, ClosedBoxDoesNotLeakRandomRays) {
    // Robust traversal: random rays from inside a closed box all hit it (no cracks at edges).
    const Scene s = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(s);
    Bounds inner;
    inner.lo = {-0.999, -0.999, -0.999};
    inner.hi = {0.999, 0.999, 0.999};
    EXPECT_EQ(tracer.traceRandomRays(inner, 100000, 7), 100000u);
}

TEST(Tracer, RefusesAnEmptyScene) {
    Scene empty;
    empty.name = "empty";
    EXPECT_THROW(Tracer{empty}, SceneError);
}
