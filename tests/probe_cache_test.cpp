// The probe pass (GatherOptions::probePasses) against closed forms and the reference
// (issue 15, fourth session).
//
// 1. Its estimator: with an exact cache (the reflected irradiance at the hit traced with full
//    paths) a path ended at its first hit must give the reference's irradiance: NEE at the
//    hit, the emitters' MIS share of one cosine ray, albedo / pi x the cache, and nothing
//    counted twice. (docs/measurements/default_bake.md, "The probe pass's bias, isolated": with the bake's cache
//    the bias comes from the nodes standing for the surface point, not from this.)
// 2. Its cache (bake/surface_cache.h) in closed form: a floor (albedo 0.5) under a sky that is
//    bright only in a band from the horizon to 10 degrees above it, and nothing else. A floor
//    point receives E_f = pi L sin^2(10 deg), all of it at grazing angles; the cache holds each
//    node's SH order 2, whose clamped-cosine kernel K(mu) = 1/4 + mu/2 + (5/16)(3 mu^2 - 1)/2
//    overestimates grazing light: it reads 2 pi L int_0^s K (s = sin 10 deg), 1.63 E_f. These
//    tests pin that value (a known limitation, measured, not hidden), so that a change of the
//    cache's representation or lookup shows here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "../libvdblight/src/bake/surface_cache.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/light/light.h"
#include "vdblight/reference/reference.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

#include "support/leak_scenes.h"

using namespace vdblight;

namespace {

/// The exact cache: reflected irradiance at p from `paths` cosine-sampled full paths of a
/// cache-free estimator, the directly hit emission left out (what NEE and the cosine ray at p
/// take), its random numbers from p's and n's bits.
class ExactCache : public SurfaceIrradianceCache {
public:
    ExactCache(const RadianceEstimator& plain, int paths) : plain_(plain), paths_(paths) {}
    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override {
        uint64_t h = 0x15;
        for (int k = 0; k < 3; ++k) {
            const float pk = p[k], nk = n[k];
            uint32_t a, b;
            std::memcpy(&a, &pk, 4);
            std::memcpy(&b, &nk, 4);
            h = hashCombine(hashCombine(h, a), b);
        }
        Rng rng(h, 3);
        Vec3f t, b;
        orthonormalBasis(n, t, b);
        Rgb sum{0, 0, 0};
        for (int i = 0; i < paths_; ++i) {
            const Vec3f l = cosineHemisphere(rng.uniform(), rng.uniform());
            Rgb emitted;
            sum += plain_.gatherRadiance(p, t * l.x + b * l.y + n * l.z, l.z * float(kInvPi), rng, rays, nullptr, &emitted) -
                   emitted;
        }
        out = sum * float(kPi / paths_);
        return true;
    }

private:
    const RadianceEstimator& plain_;
    int paths_;
};

/// Irradiance at x for normal n from `samples` cosine-sampled gathered paths plus one NEE
/// sample of the emitters each (MIS), as the bake's node sampler weighs them.
Rgb irradianceAt(const RadianceEstimator& est, const Vec3f& x, const Vec3f& n, uint32_t samples, uint64_t seed) {
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    Rng rng(seed, 4);
    RayCount rays;
    Rgbd sum{0, 0, 0};
    for (uint32_t k = 0; k < samples; ++k) {
        float u, v;
        sobol02(k, hashCombine(seed, 1), u, v);
        const Vec3f l = cosineHemisphere(u, v);
        Rgb e = est.gatherRadiance(x, t * l.x + b * l.y + n * l.z, l.z * float(kInvPi), rng, rays) * float(kPi);
        sobol02(k, hashCombine(seed, 2), u, v);
        LightSample s;
        if (est.sampleEmissiveTriangles(x, u, v, rng.uniform(), s, rays, &n)) {
            const float c = std::max(0.0f, dot(n, s.direction));
            e += s.weight * (c * misWeight(s.pdf, c * float(kInvPi)));
        }
        sum += Rgbd(e);
    }
    return Rgb(sum / double(samples));
}

const double kBandTop = 10.0 * kPi / 180.0;
constexpr float kAlbedo = 0.5f;
const Rgb kBand{1.0f, 0.8f, 0.6f};

Scene horizonBandScene() {
    Scene s;
    s.name = "horizon_band";
    Material m;
    m.name = "floor";
    m.albedo = {kAlbedo, kAlbedo, kAlbedo};
    const uint32_t floor = addMaterial(s, m);
    const float r = 100.0f;  // wide enough that a node's floor reaches 0.3 degrees below its horizon
    addTriangle(s, {-r, 0, -r}, {r, 0, r}, {r, 0, -r}, floor);
    addTriangle(s, {-r, 0, -r}, {-r, 0, r}, {r, 0, r}, floor);
    // Latitude-longitude rows of 10 degrees from the zenith (SkyMap::lookup): row 8 is
    // elevation (0, 10] degrees.
    auto map = std::make_shared<SkyMap>();
    map->width = 1;
    map->height = 18;
    map->texels.assign(18, Rgb(0, 0, 0));
    map->texels[8] = kBand;
    s.sky.map = map;
    return s;
}

/// The true irradiance at a floor point: pi L sin^2(band top).
Rgb floorIrradiance() {
    const double s = std::sin(kBandTop);
    return kBand * float(kPi * s * s);
}

/// 2 pi int_a^b K(mu) dmu, K the SH order-2 clamped-cosine kernel.
double shKernelIntegral(double a, double b) {
    auto f = [](double m) { return 0.09375 * m + 0.25 * m * m + 0.15625 * m * m * m; };
    return 2 * kPi * (f(b) - f(a));
}

/// Nodes at heights 0.5 and 25.5 over the floor.
/// A node's stored SH order-2 irradiance for the normal pointing down (at the floor).
Rgb irradianceFacingDown(const Volume& v, int node) {
    const float* c = v.levels[0].data.data() + std::size_t(node) * sh::kCoeffs * 3;
    Rgb coeffs[sh::kCoeffs];
    for (int j = 0; j < sh::kCoeffs; ++j) coeffs[j] = Rgb(c[3 * j], c[3 * j + 1], c[3 * j + 2]);
    return sh::irradiance(coeffs, {0, -1, 0});
}

GridSpec floorGrid() {
    GridSpec g;
    g.origin = {-100.0, 0.5, -100.0};
    g.spacing = 25.0;
    g.nx = g.nz = 9;
    g.ny = 2;
    return g;
}

}  // namespace

// The estimator with an exact cache against the reference, in both rooms of the thin-wall
// scene (light in x < 2, a door in the wall at x = 2): each point within 3 % and the sum over
// the points within 1 %. A cache that also held the directly hit emission (counted again by
// NEE at the hit), or a missing 1/pi, is off by far more (tens of percent). The bounds are not
// four standard errors: measured with the estimate's own standard error (8 independent
// batches; its exact cache averages 2 paths per hit), two of these six points differ from the
// reference by 5-6 of them (+1.3 % and -1.8 %), while the 200 points of bench_accuracy
// --probe-study average out to +0.03 / +0.19 % (docs/methods.md): a point-by-point difference
// that is not explained yet (issue 15), printed here.
TEST(ProbeCache, TheEstimatorWithAnExactCacheMatchesTheReference) {
    const LeakScene rooms = makeThinWallScene();
    const Tracer tracer(rooms.scene);
    const RadianceEstimator plain(rooms.scene, tracer);
    ExactCache cache(plain, 2);
    RadianceEstimator probe(rooms.scene, tracer);
    probe.setSurfaceCache(&cache);
    std::vector<ReferencePoint> points;
    Rng rng(41);
    for (int i = 0; i < 6; ++i) {
        // One draw per statement: the order in which a function's arguments are evaluated is
        // the compiler's (gcc and clang differ), and the points must be the same for both.
        float u[5];
        for (float& x : u) x = rng.uniform();
        points.push_back({Vec3f((i < 3 ? 0.4f : 2.4f) + 1.2f * u[0], 0.4f + 1.2f * u[1], 0.4f + 1.2f * u[2]),
                          uniformSphere(u[3], u[4])});
    }
    ReferenceOptions ro;
    ro.samples = 1 << 17;
    const auto truth = referenceIrradiance(rooms.scene, tracer, points, ro);
    constexpr int kBatches = 8;
    double sumGot = 0, sumWant = 0, sumVariance = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        double batch[kBatches], g = 0;
        for (int b = 0; b < kBatches; ++b) {
            batch[b] = luminance(irradianceAt(probe, points[i].position, normalize(points[i].normal), 1 << 13,
                                              100 + 16 * i + std::size_t(b)));
            g += batch[b] / kBatches;
        }
        double spread = 0;
        for (double x : batch) spread += (x - g) * (x - g);
        const double seGot = std::sqrt(spread / (kBatches - 1) / kBatches);
        const double w = luminance(Rgb(truth[i].irradiance)), seWant = luminance(Rgb(truth[i].standardError));
        const double se = std::sqrt(seGot * seGot + seWant * seWant);
        std::printf("  point %zu (%s room): probe estimator %.5f +- %.5f, reference %.5f +- %.5f (%+.2f %%)\n", i,
                    i < 3 ? "lit" : "unlit", g, seGot, w, seWant, 100 * (g / w - 1));
        std::printf("    difference %.1f standard errors\n", (g - w) / se);
        EXPECT_NEAR(g / w, 1.0, 0.03) << "point " << i;
        EXPECT_LT(seGot, 0.01 * w) << "point " << i << ": too noisy to tell a defect";
        sumGot += g;
        sumWant += w;
        sumVariance += se * se;
    }
    std::printf("  all points: %+.2f %% +- %.2f %%\n", 100 * (sumGot / sumWant - 1), 100 * std::sqrt(sumVariance) / sumWant);
    EXPECT_NEAR(sumGot / sumWant, 1.0, 0.01);
}

// The cache of pass 0 read at floor points: SH2's value for the band, 1.63 x the truth.
TEST(ProbeCache, ReadsSh2sValueOfGrazingLightAtAFloor) {
    const Scene scene = horizonBandScene();
    const Tracer tracer(scene);
    GatherOptions o;
    o.raysPerNode = 1 << 14;
    o.probePasses = 1;
    o.stage = 0;  // pass 0 alone: its reflected light is the stage volume's data
    const Volume stage0 = bakeShGather(scene, tracer, floorGrid(), o);
    const bake_detail::VolumeSurfaceCache cache(tracer, floorGrid(), stage0.levels[0].data.data());
    const Rgb want = kBand * float(shKernelIntegral(0, std::sin(kBandTop)));
    Rng rng(15);
    double sumGot = 0;
    for (int i = 0; i < 16; ++i) {
        const Vec3f p(-60.0f + 120.0f * rng.uniform(), 1e-3f, -60.0f + 120.0f * rng.uniform());
        Rgb got;
        RayCount rays;
        ASSERT_TRUE(cache.irradiance(p, {0, 1, 0}, got, rays));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 0.03 * want[c]) << "point " << i << " channel " << c;
        sumGot += luminance(got);
    }
    std::printf("  cache at 16 floor points: mean %.5f, SH2's closed form %.5f (%+.2f %%), the true irradiance %.5f "
                "(the cache reads %.2f x it)\n", sumGot / 16, luminance(want), 100 * (sumGot / 16 / luminance(want) - 1),
                luminance(floorIrradiance()), sumGot / 16 / luminance(floorIrradiance()));
}

// The whole probe pass: a node's stored SH2 irradiance facing the floor is the closed form of
// what it gathers: albedo x the cache's floor irradiance (the floor's radiance, pi x it) plus
// what SH2 lets in of the band above the node's horizon, which the node sees directly.
TEST(ProbeCache, AProbePassGivesTheClosedFormAboveAFloor) {
    const Scene scene = horizonBandScene();
    const Tracer tracer(scene);
    GatherOptions o;
    o.raysPerNode = 1 << 14;
    o.probePasses = 1;
    const GridSpec g = floorGrid();
    const Volume v = bakeShGather(scene, tracer, g, o);
    const double s = std::sin(kBandTop);
    for (const int node : {int(g.index(4, 0, 4)), int(g.index(2, 0, 6))}) {
        const Rgb got = irradianceFacingDown(v, node);
        // The band lies at mu in [-s, 0) for the normal pointing down.
        const Rgb want = kBand * float(kAlbedo * shKernelIntegral(0, s) + shKernelIntegral(-s, 0));
        const Rgb exact = kBand * float(kAlbedo * kPi * s * s + shKernelIntegral(-s, 0));  // with a true cache
        std::printf("  node %d, normal down: %.5f, closed form %.5f (%+.2f %%); with the floor's true irradiance %.5f\n", node,
                    luminance(got), luminance(want), 100 * (luminance(got) / luminance(want) - 1), luminance(exact));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 0.03 * want[k]) << "node " << node << " channel " << k;
    }
}

// The same probe pass with --probe-cache surface (bake/surface_bins.h): the first hit reads
// irradiance samples that pass 0's paths took at the floor itself, not the nodes' SH order 2,
// so the node facing the floor gets the floor's true irradiance, pi L sin^2(10 deg) x albedo,
// where the node cache gives SH2's 1.63 times it (the test above).
TEST(ProbeCache, TheSurfaceCacheGivesTheFloorsTrueIrradiance) {
    const Scene scene = horizonBandScene();
    const Tracer tracer(scene);
    GatherOptions o;
    o.raysPerNode = 1 << 14;
    o.probePasses = 1;
    o.surfaceProbeCache = true;
    const GridSpec g = floorGrid();
    const Volume v = bakeShGather(scene, tracer, g, o);
    const double s = std::sin(kBandTop);
    for (const int node : {int(g.index(4, 0, 4)), int(g.index(2, 0, 6))}) {
        const Rgb got = irradianceFacingDown(v, node);
        const Rgb exact = kBand * float(kAlbedo * kPi * s * s + shKernelIntegral(-s, 0));
        const Rgb nodeCache = kBand * float(kAlbedo * shKernelIntegral(0, s) + shKernelIntegral(-s, 0));
        std::printf("  node %d, normal down: %.5f, with the floor's true irradiance %.5f (%+.2f %%); the node cache's %.5f\n",
                    node, luminance(got), luminance(exact), 100 * (luminance(got) / luminance(exact) - 1), luminance(nodeCache));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], exact[k], 0.03 * exact[k]) << "node " << node << " channel " << k;
    }
}
