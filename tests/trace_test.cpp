// The tracer finds the closest triangle, respects ray extents and reports the triangle's
// own index, so materials can be looked up.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <vector>

#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/trace/random_rays.h"  // internal: traceRandomRays

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
    EXPECT_EQ(traceRandomRays(tracer, inner, 100000, 7), 100000u);
}

TEST(Tracer, RefusesAnEmptyScene) {
    Scene empty;
    empty.name = "empty";
    EXPECT_THROW(Tracer{empty}, SceneError);
}

// The packet form (coherent 16-ray packets) answers exactly as one ray at a time: rays from a
// grid of points inside the default scene to one light, with a count that is not a multiple
// of 16, finite and infinite extents, and some rays ending short of the blockers.
TEST(Tracer, PacketOcclusionEqualsSingleRays) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    const Bounds b = s.bounds();
    const Vec3f lo(b.lo), size(b.size());
    Rng rng(5, 0x7061636b);
    const Vec3f light = lo + size * Vec3f(0.31f, 0.42f, 0.27f);
    std::vector<Ray> rays;
    for (int i = 0; i < 1000; ++i) {
        const Vec3f x = lo + size * Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
        const float end = i % 3 == 0 ? 0.5f : i % 3 == 1 ? 0.9999f : std::numeric_limits<float>::infinity();
        rays.push_back(Ray{x, i % 7 == 0 ? uniformSphere(rng.uniform(), rng.uniform()) : light - x, 0.0f, end});
    }
    for (std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(16), std::size_t(17), rays.size()}) {
        std::unique_ptr<bool[]> blocked(new bool[count + 1]);
        tracer.occluded(rays.data(), count, blocked.get());
        std::size_t hits = 0;
        for (std::size_t i = 0; i < count; ++i) {
            EXPECT_EQ(blocked[i], tracer.occluded(rays[i])) << "ray " << i << " of " << count;
            hits += blocked[i];
        }
        if (count == rays.size()) {  // both answers occur, so the comparison means something
            EXPECT_GT(hits, count / 10);
            EXPECT_LT(hits, count - count / 10);
        }
    }
}
