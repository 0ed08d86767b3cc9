// The facing shortcut of RadianceEstimator::sampleEmissiveTriangles (used by NEE at path
// vertices): with a receiver normal, a sample is accepted exactly when the plain sample is
// accepted and lies in front of the receiver, with the same direction, weight and pdf, and
// the shadow ray is saved for the rejected ones. So the surface NEE adds the same bits.
#include <gtest/gtest.h>

#include <cstring>

#include "test_util.h"
#include "vdblight/light/light.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

TEST(NeeFacing, SameSamplesInFrontAndNoShadowRayBehind) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const RadianceEstimator estimator(scene, tracer);
    Rng rng(11);
    int accepted = 0, behind = 0;
    uint64_t saved = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f x(0.02f + 0.51f * rng.uniform(), 0.02f + 0.51f * rng.uniform(), 0.02f + 0.51f * rng.uniform());
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const float u = rng.uniform(), v = rng.uniform(), w = rng.uniform();
        LightSample a, b;
        RayCount ca, cb;
        const bool plain = estimator.sampleEmissiveTriangles(x, u, v, w, a, ca);
        const bool facing = estimator.sampleEmissiveTriangles(x, u, v, w, b, cb, &n);
        const bool front = plain && dot(n, a.direction) > 0.0f;
        ASSERT_EQ(facing, front) << "sample " << i;
        if (facing) {
            ++accepted;
            EXPECT_EQ(std::memcmp(&a.direction, &b.direction, sizeof(Vec3f)), 0);
            EXPECT_EQ(std::memcmp(&a.weight, &b.weight, sizeof(Rgb)), 0);
            EXPECT_EQ(a.pdf, b.pdf);
        }
        behind += plain && !front;
        EXPECT_LE(cb.occluded, ca.occluded);
        saved += ca.occluded - cb.occluded;
    }
    EXPECT_GT(accepted, 1000);
    EXPECT_GT(behind, 1000);
    EXPECT_GT(saved, uint64_t(behind));  // also the occluded samples behind the receiver
}
