// The packet form of intersect (coherent 16-ray packets, used for a bake node's first hits)
// returns exactly the hits of one ray at a time: same triangle, and the same bits of t, u, v
// and the geometric normal. Checked for the bake's own rays (Sobol directions from points
// inside the scene) on the default scene and on the office scene (tens of thousands of
// triangles, a deep BVH), with counts that are not multiples of 16 and finite extents.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

#include "support/office_scene.h"

using namespace vdblight;

namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

void expectPacketHitsEqualSingleRays(const Scene& s, int origins, uint32_t raysPerOrigin, uint64_t seed) {
    const Tracer tracer(s);
    const Bounds b = s.bounds();
    const Vec3f lo(b.lo), size(b.size());
    Rng rng(seed, 0x7061636b);
    std::size_t hits = 0, total = 0;
    std::vector<Ray> rays(raysPerOrigin);
    std::vector<Hit> packet(raysPerOrigin + 1);
    for (int o = 0; o < origins; ++o) {
        const Vec3f x = lo + size * Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
        const uint32_t n = raysPerOrigin - uint32_t(o % 5);  // not always a multiple of 16
        for (uint32_t i = 0; i < n; ++i) {
            float u, v;
            sobol02(i, uint64_t(o) * 977 + seed, u, v);
            rays[i] = Ray{x, uniformSphere(u, v)};
            if (o % 4 == 3) rays[i].tfar = 0.25f * length(size);  // some rays end short of a wall
        }
        packet[n].triangle = 12345;  // past the end: must not be written
        tracer.intersect(rays.data(), n, packet.data());
        EXPECT_EQ(packet[n].triangle, 12345u);
        for (uint32_t i = 0; i < n; ++i) {
            const Hit single = tracer.intersect(rays[i]);
            const Hit& p = packet[i];
            ASSERT_EQ(p.triangle, single.triangle) << "origin " << o << " ray " << i;
            ASSERT_TRUE(sameBits(p.t, single.t) && sameBits(p.u, single.u) && sameBits(p.v, single.v))
                << "origin " << o << " ray " << i << ": t " << p.t << " vs " << single.t;
            ASSERT_TRUE(sameBits(p.geometricNormal.x, single.geometricNormal.x) &&
                        sameBits(p.geometricNormal.y, single.geometricNormal.y) &&
                        sameBits(p.geometricNormal.z, single.geometricNormal.z))
                << "origin " << o << " ray " << i;
            hits += p.hit();
            ++total;
        }
    }
    // Both hits and misses occur (the short rays miss), so the comparison means something.
    EXPECT_GT(hits, total / 2);
    EXPECT_LT(hits, total);
}

}  // namespace

TEST(TracerPacket, IntersectEqualsSingleRaysOnTheDefaultScene) {
    expectPacketHitsEqualSingleRays(loadScene(defaultScenePath()), 200, 578, 1);
}

TEST(TracerPacket, IntersectEqualsSingleRaysOnTheOfficeScene) {
    expectPacketHitsEqualSingleRays(makeOfficeScene(1), 60, 578, 2);
}

TEST(TracerPacket, EmptyAndSingleRayCounts) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    const Bounds b = s.bounds();
    const Vec3f c(b.lo + b.size() * 0.5);
    Hit h[2];
    h[0].triangle = 7;
    tracer.intersect(nullptr, 0, h);  // nothing traced, nothing written
    EXPECT_EQ(h[0].triangle, 7u);
    const Ray r{c, Vec3f(0, -1, 0)};
    tracer.intersect(&r, 1, h);
    EXPECT_EQ(h[0].triangle, tracer.intersect(r).triangle);
    EXPECT_TRUE(h[0].hit());
}
