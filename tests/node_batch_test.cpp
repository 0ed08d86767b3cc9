// Reference vs optimised: a gather node sampled with its rays in packets (first hits, and
// every NEE shadow ray deferred to the end of a batch of paths; TransportOptions::packetRays)
// gives the same bits as the one-ray-at-a-time reference path: the same SH coefficients,
// the same ray counts and the same back-face counts. Checked on the scenes that take each
// branch of the transport: emissive triangles only (the Cornell box: the paper
// configuration), a sky and punctual lights (evaluated at once, not deferred), many point
// lights (one sampled per vertex), the office scene (an emitter panel, tens of thousands of
// triangles), the probe pass's several light samples at its paths' end, and with sample
// counts that are not multiples of the batch. Whole bakes
// (multi-level, error-targeted) are compared too, at 1 and 2 threads.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

#include "support/office_scene.h"

using namespace vdblight;

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

/// Projects at `points` random free points with both paths; every coefficient must match.
/// With `cache`, both estimators end their paths at the first hit (the probe pass).
void expectSameProjections(const Scene& scene, TransportOptions transport, uint32_t rays, int points,
                           bool countBackFaces = false, const SurfaceIrradianceCache* cache = nullptr) {
    const Tracer tracer(scene);
    TransportOptions one = transport, packets = transport;
    one.packetRays = false;
    packets.packetRays = true;
    RadianceEstimator reference(scene, tracer, one), batched(scene, tracer, packets);
    reference.setSurfaceCache(cache);
    batched.setSurfaceCache(cache);
    const Bounds b = scene.bounds();
    Rng rng(17, 0x6e6f6465);
    double total = 0;
    for (int p = 0; p < points; ++p) {
        const Vec3f x(b.lo + b.size() * Vec3d(0.05 + 0.9 * rng.uniform(), 0.05 + 0.9 * rng.uniform(),
                                               0.05 + 0.9 * rng.uniform()));
        Rgbd a[9], c[9];
        RayCount ca, cc;
        uint32_t backA = 0, backC = 0;
        projectIncidentRadiance(reference, x, rays, 7, uint64_t(p), a, ca, countBackFaces ? &tracer : nullptr,
                                countBackFaces ? &backA : nullptr);
        projectIncidentRadiance(batched, x, rays, 7, uint64_t(p), c, cc, countBackFaces ? &tracer : nullptr,
                                countBackFaces ? &backC : nullptr);
        for (int j = 0; j < 9; ++j) {
            ASSERT_TRUE(sameBits(a[j].x, c[j].x) && sameBits(a[j].y, c[j].y) && sameBits(a[j].z, c[j].z))
                << "point " << p << " coefficient " << j << ": " << a[j].x << " vs " << c[j].x;
            total += a[j].x + a[j].y + a[j].z;
        }
        EXPECT_EQ(ca.intersect, cc.intersect) << "point " << p;
        EXPECT_EQ(ca.occluded, cc.occluded) << "point " << p;
        EXPECT_EQ(backA, backC) << "point " << p;
    }
    EXPECT_GT(total, 0.0);  // light arrives: the comparison is not between two zeros
}

uint64_t checksum(const Volume& v) {
    uint64_t h = 1469598103934665603ull;
    for (const VolumeLevel& l : v.levels)
        for (float f : l.data) {
            uint32_t bits;
            std::memcpy(&bits, &f, 4);
            h = (h ^ bits) * 1099511628211ull;
        }
    return h;
}

/// A cache that holds the same irradiance everywhere: the probe pass's path end, whatever
/// the cache's values.
class UniformCache : public SurfaceIrradianceCache {
public:
    bool irradiance(const Vec3f&, const Vec3f&, Rgb& out, RayCount&) const override {
        out = Rgb(0.3f, 0.2f, 0.1f);
        return true;
    }
};

}  // namespace

TEST(NodeBatch, EmissiveTrianglesOnlyMatchesOneByOne) {
    expectSameProjections(loadScene(defaultScenePath()), TransportOptions{}, 100, 40);
    // More samples than one batch (1024): a full batch and a partial one.
    expectSameProjections(loadScene(defaultScenePath()), TransportOptions{}, 1100, 3);
}

TEST(NodeBatch, BackFaceCountsMatchOneByOne) {
    expectSameProjections(loadScene(defaultScenePath()), TransportOptions{}, 70, 20, true);
}

TEST(NodeBatch, SkyAndPunctualLightsMatchOneByOne) {
    Scene s = loadScene(defaultScenePath());
    const Bounds b = s.bounds();
    const Vec3f c(b.lo + b.size() * 0.5);
    s.sky.constant = Rgb(0.2f, 0.3f, 0.4f);
    s.pointLights.push_back({c + Vec3f(0.1f, 0.2f, 0.0f), Rgb(0.5f, 0.4f, 0.3f)});
    s.directionalLights.push_back({normalize(Vec3f(0.3f, -1.0f, 0.2f)), Rgb(0.7f, 0.7f, 0.6f)});
    // Open the box to the sky: no front wall (rays escape), so the sky term is exercised.
    Scene open = s;
    open.indices.clear();
    open.materialIds.clear();
    for (std::size_t t = 0; t < s.triangleCount(); ++t) {
        const Vec3f n = cross(s.vertex(t, 1) - s.vertex(t, 0), s.vertex(t, 2) - s.vertex(t, 0));
        const Vec3f mid = (s.vertex(t, 0) + s.vertex(t, 1) + s.vertex(t, 2)) / 3.0f;
        if (std::abs(n.z) > 0.9f * length(n) && mid.z > float(b.hi.z) - 1e-3f) continue;
        for (int k = 0; k < 3; ++k) open.indices.push_back(s.indices[3 * t + k]);
        open.materialIds.push_back(s.materialIds[t]);
    }
    ASSERT_LT(open.triangleCount(), s.triangleCount());
    expectSameProjections(open, TransportOptions{}, 70, 20);
}

TEST(NodeBatch, ManySampledPointLightsMatchOneByOne) {
    Scene s = loadScene(defaultScenePath());
    const Bounds b = s.bounds();
    Rng rng(3);
    for (int l = 0; l < 40; ++l)
        s.pointLights.push_back({Vec3f(b.lo + b.size() * Vec3d(0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform(),
                                                               0.1 + 0.8 * rng.uniform())),
                                 Rgb(0.05f, 0.04f, 0.03f)});
    TransportOptions t;
    t.exactLightLimit = 4;  // one light sampled per vertex and per node sample
    expectSameProjections(s, t, 40, 16);
}

/// The probe pass's path end with several light samples (TransportOptions::cacheEndLightSamples):
/// emitter samples deferred (the Cornell box), and with punctual lights (evaluated at once,
/// with the first sample only).
TEST(NodeBatch, ProbePassLightSamplesMatchOneByOne) {
    const UniformCache cache;
    TransportOptions t;
    t.cacheEndLightSamples = 3;
    Scene s = loadScene(defaultScenePath());
    expectSameProjections(s, t, 90, 16, false, &cache);
    const Bounds b = s.bounds();
    s.pointLights.push_back({Vec3f(b.lo + b.size() * 0.5) + Vec3f(0.1f, 0.2f, 0.0f), Rgb(0.5f, 0.4f, 0.3f)});
    expectSameProjections(s, t, 90, 16, false, &cache);
}

TEST(NodeBatch, OfficeSceneMatchesOneByOne) {
    expectSameProjections(makeOfficeScene(1), TransportOptions{}, 80, 12);
}

TEST(NodeBatch, WholeBakesMatchOneByOneAtAnyThreadCount) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    GridPlacement p;
    p.resolution = 4;
    LevelsPlacement lp;
    lp.kind = LayoutKind::Bilevel;
    lp.refine = 2;
    lp.levels = 2;
    const LevelLayout layout = placeLevels(placeUniformGrid(scene.bounds(), p, 1), scene.positions, scene.indices, lp, 1);
    uint64_t first = 0;
    for (bool packets : {false, true})
        for (int threads : {1, 2}) {
            GatherOptions o;
            o.raysPerNode = 48;
            o.threads = threads;
            o.transport.packetRays = packets;
            LevelsBakeStats stats;
            const uint64_t sum = checksum(bakeShGatherLevels(scene, tracer, layout, o, nullptr, &stats));
            if (!packets && threads == 1) first = sum;
            EXPECT_EQ(sum, first) << (packets ? "packets" : "one by one") << ", " << threads << " threads";
            EXPECT_GT(stats.rays.occluded, 0u);
        }

    // The error-targeted bake samples nodes in rounds (consecutive sample ranges).
    AdaptiveOptions a;
    a.targetError = 0.05;
    a.minRays = 16;
    a.maxRays = 256;
    uint64_t adaptiveFirst = 0;
    for (bool packets : {false, true}) {
        a.transport.packetRays = packets;
        a.threads = packets ? 2 : 1;
        const uint64_t sum = checksum(bakeShGatherAdaptive(scene, tracer, layout.levels[0].grid, a));
        if (!packets) adaptiveFirst = sum;
        EXPECT_EQ(sum, adaptiveFirst);
    }
}
