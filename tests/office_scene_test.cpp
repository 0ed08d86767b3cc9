// The generated office (office_scene.h): size, validity, lights, closed room and lighting
// that reaches the desks.
#include <gtest/gtest.h>

#include "vdblight/core/errors.h"
#include "vdblight/reference/reference.h"
#include "vdblight/trace/trace.h"

#include "support/office_scene.h"

using namespace vdblight;

TEST(OfficeScene, TensOfThousandsOfValidTrianglesInAClosedLitRoom) {
    const Scene s = makeOfficeScene(1);
    validateScene(s);
    EXPECT_GE(s.triangleCount(), 20000u);
    EXPECT_LE(s.triangleCount(), 100000u);
    EXPECT_EQ(s.stats.degenerateTrianglesSkipped, 0u);
    EXPECT_TRUE(s.hasEmissiveTriangles());
    const Bounds b = s.bounds();
    EXPECT_NEAR(b.lo.x, 0, 1e-6);
    EXPECT_NEAR(b.hi.x, 6, 1e-6);
    EXPECT_NEAR(b.hi.y, 3, 1e-6);
    EXPECT_NEAR(b.hi.z, 5, 1e-6);
    EXPECT_GT(makeOfficeScene(2).triangleCount(), 3 * s.triangleCount());
    EXPECT_EQ(makeOfficeScene(1).contentHash(), s.contentHash());  // deterministic
    EXPECT_THROW(makeOfficeScene(0), ValueError);

    // Closed room: rays from inside in many directions all hit a front face.
    const Tracer tracer(s);
    int escaped = 0, backFaces = 0;
    for (int i = 0; i < 2000; ++i) {
        float u, v;
        sobol02(uint32_t(i), 5, u, v);
        const Ray r{Vec3f(3.0f, 2.0f, 1.9f), uniformSphere(u, v)};
        const Hit h = tracer.intersect(r);
        if (!h.hit()) ++escaped;
        else if (dot(h.geometricNormal, r.direction) > 0) ++backFaces;
    }
    EXPECT_EQ(escaped, 0);
    EXPECT_EQ(backFaces, 0);

    // Light reaches a desk top from above; under a desk it is darker.
    ReferenceOptions ro;
    ro.samples = 2048;
    ro.transport.maxBounces = 2;
    const auto e = referenceIrradiance(s, tracer, {{{1.4f, 0.8f, 0.9f}, {0, 1, 0}}, {{1.4f, 0.3f, 0.9f}, {0, 1, 0}}}, ro);
    EXPECT_GT(e[0].irradiance.x, 0.2);  // about 0.44 directly from the ceiling panel (2.2 m up, 2 m aside)
    EXPECT_LT(e[1].irradiance.x, 0.5 * e[0].irradiance.x);
}
