// Many punctual lights (light.h, light/punctual_sampler.h): with more point/spot lights
// than TransportOptions::exactLightLimit, each vertex picks one light by estimated
// contribution. The estimate must stay unbiased: `reference` and the bake with the sampler
// against the exact sum over every light (the exact path, exactLightLimit above the count).
#include <gtest/gtest.h>

#include <cmath>

#include "vdblight/bake/each_pass.h"
#include "bake/bake_antialiased.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

using namespace vdblight;

namespace {
// The default scene with `count` point lights (and a few spot lights) at random places
// inside the box, total intensity independent of the count.
Scene withManyLights(int count, uint64_t seed, double yLo = 0.1, double yHi = 0.9) {
    Scene s = loadScene(defaultScenePath());
    const Bounds b = s.bounds();
    Rng rng(seed);
    auto inside = [&] {
        const Vec3d t(0.1 + 0.8 * rng.uniform(), yLo + (yHi - yLo) * rng.uniform(), 0.1 + 0.8 * rng.uniform());
        return Vec3f(b.lo + b.size() * t);
    };
    const float scale = 20.0f * float(b.size().x * b.size().x) / float(count);
    for (int i = 0; i < count; ++i) {
        const float r = 0.5f + rng.uniform();
        s.pointLights.push_back({inside(), Rgb(r, 1.0f, 2.0f - r) * scale});
    }
    for (int i = 0; i < 3; ++i) {
        SpotLight spot;
        spot.position = inside();
        spot.direction = normalize(Vec3f(rng.uniform() - 0.5f, -1.0f, rng.uniform() - 0.5f));
        spot.intensity = Rgb(1, 1, 1) * scale * 10.0f;
        spot.innerConeAngle = 0.3f;
        spot.outerConeAngle = 0.6f;
        s.spotLights.push_back(spot);
    }
    return s;
}

std::vector<ReferencePoint> testPoints(const Scene& s, int n) {
    const Bounds b = s.bounds();
    Rng rng(5);
    std::vector<ReferencePoint> pts;
    for (int i = 0; i < n; ++i) {
        const Vec3d t(0.15 + 0.7 * rng.uniform(), 0.15 + 0.7 * rng.uniform(), 0.15 + 0.7 * rng.uniform());
        pts.push_back({Vec3f(b.lo + b.size() * t), uniformSphere(rng.uniform(), rng.uniform())});
    }
    return pts;
}

/// withManyLights(count, seed), its tracer and `points` test points.
struct ManyLights {
    ManyLights(int count, uint64_t seed, int pointCount)
        : scene(withManyLights(count, seed)), tracer(scene), points(testPoints(scene, pointCount)) {}
    const Scene scene;
    const Tracer tracer;
    const std::vector<ReferencePoint> points;
};

/// Transport with `bounces` bounces, with every light summed exactly at every vertex
/// (exactLightLimit above the count) or with the default exactLightLimit (sampled above it).
TransportOptions transport(int bounces, bool exactLights) {
    TransportOptions t;
    t.maxBounces = bounces;
    if (exactLights) t.exactLightLimit = 1u << 30;
    return t;
}

/// How the reference treats the lights: every light exactly everywhere; one sampled light per
/// bounce vertex but every light exactly at the point (the default); sampled at the point too.
enum class Lights { Exact, SampledExactAtPoint, Sampled };

/// referenceIrradiance at the test points, 8192 samples, `bounces` bounces. The sampled runs
/// use seed 2, independent of the exact run, so that the z-scores mean what they say.
std::vector<ReferenceResult> reference(const ManyLights& m, int bounces, Lights lights) {
    ReferenceOptions o;
    o.samples = 8192;
    o.transport.maxBounces = bounces;
    if (lights == Lights::Exact) {
        o.transport.exactLightLimit = 1u << 30;
        return referenceIrradiance(m.scene, m.tracer, m.points, o);
    }
    o.transport.exactLightLimit = 16;
    o.punctualExactAtPoint = lights == Lights::SampledExactAtPoint;
    o.seed = 2;
    return referenceIrradiance(m.scene, m.tracer, m.points, o);
}

void expectAgree(const std::vector<ReferenceResult>& sampled, const std::vector<ReferenceResult>& exact,
                 const char* what) {
    int agree = 0;
    double maxZ = 0, maxRelSe = 0;
    for (std::size_t i = 0; i < sampled.size(); ++i) {
        const double a = luminance(Rgb(sampled[i].irradiance)), e = luminance(Rgb(exact[i].irradiance));
        const double sa = luminance(Rgb(sampled[i].standardError)), se = luminance(Rgb(exact[i].standardError));
        const double z = std::abs(a - e) / std::sqrt(sa * sa + se * se + 1e-30);
        maxZ = std::max(maxZ, z);
        maxRelSe = std::max(maxRelSe, std::sqrt(sa * sa + se * se) / e);
        if (z < 3.0) ++agree;
        EXPECT_LT(z, 4.5) << what << " point " << i << ": sampled " << a << " +- " << sa << ", exact " << e << " +- " << se;
    }
    std::printf("  %s: %d of %zu points within 3 standard errors, max |z| %.2f (largest relative standard error "
                "of the difference %.2f %%)\n", what, agree, sampled.size(), maxZ, 100 * maxRelSe);
    EXPECT_GE(agree, int(sampled.size()) - 2);
}
}  // namespace

TEST(ManyLights, SamplerExpectationIsTheExactSum) {
    // The expectation of one sampled light's weight over u in [0, 1) is the sum over every
    // light: integrated here by the midpoint rule with 2^19 values of u (each light's
    // interval of u is as wide as its pmf, so only lights with pmf below 2^-19 -- negligible
    // contributions by construction of the importance -- can be missed; observed 1e-5).
    const ManyLights m(1000, 14, 3);
    const RadianceEstimator estimator(m.scene, m.tracer);
    ASSERT_TRUE(estimator.samplesPunctualLights());
    for (const ReferencePoint& p : m.points) {
        const Vec3f n = normalize(p.normal);
        std::vector<LightSample> all;
        RayCount rays;
        estimator.punctualLights(p.position, all, rays);
        double exact = 0, exactFacing = 0;
        for (const LightSample& l : all) {
            exact += luminance(l.weight);
            exactFacing += luminance(l.weight) * std::max(0.0f, dot(n, l.direction));
        }
        const int K = 1 << 19;
        double sum = 0, sumFacing = 0, sumWithNormal = 0;
        for (int k = 0; k < K; ++k) {
            LightSample l;
            if (estimator.samplePunctualLight(p.position, (k + 0.5) / K, l, rays)) {
                sum += luminance(l.weight);
                sumFacing += luminance(l.weight) * std::max(0.0f, dot(n, l.direction));
            }
            // At a surface the oriented tree also weighs lights by the normal (light_tree.h).
            if (estimator.samplePunctualLight(p.position, (k + 0.5) / K, l, rays, &n))
                sumWithNormal += luminance(l.weight) * std::max(0.0f, dot(n, l.direction));
        }
        std::printf("  exact sum %.6f, expectation of the sampler %.6f (facing a normal: %.6f vs %.6f, "
                    "sampled with the normal %.6f)\n", exact, sum / K, exactFacing, sumFacing / K, sumWithNormal / K);
        EXPECT_NEAR(sum / K, exact, 5e-4 * exact);
        EXPECT_NEAR(sumFacing / K, exactFacing, 5e-4 * exact);
        EXPECT_NEAR(sumWithNormal / K, exactFacing, 5e-4 * exact);
    }
}

TEST(ManyLights, ReferenceWithSamplerMatchesExactSumDirect) {
    const ManyLights m(300, 11, 24);
    const auto exact = reference(m, 0, Lights::Exact);  // direct light only: the exact path stays cheap
    const auto sampled = reference(m, 0, Lights::Sampled);  // the sampler at the point too (what this test checks)
    expectAgree(sampled, exact, "300 point + 3 spot lights, direct");
    // The sampled estimate carries variance (the test compares two different estimators).
    double se = 0;
    for (const auto& r : sampled) se = std::max(se, double(luminance(Rgb(r.standardError))));
    EXPECT_GT(se, 0.0);
}

TEST(ManyLights, ReferenceWithSamplerMatchesExactSumWithBounces) {
    // Sampled lights at every path vertex (directAtSurface) as well as at the point.
    const ManyLights m(60, 12, 8);
    const auto exact = reference(m, 3, Lights::Exact);
    const auto sampled = reference(m, 3, Lights::Sampled);  // the sampler at the point too (what this test checks)
    expectAgree(sampled, exact, "60 point + 3 spot lights, 3 bounces");
}

// The default reference with many lights evaluates them exactly at the point (bounce vertices
// still sample one): it agrees with the exact path and is less noisy than sampling at the point.
TEST(ManyLights, ReferenceExactAtThePointMatchesTheExactPath) {
    const ManyLights m(60, 13, 8);
    const auto exact = reference(m, 3, Lights::Exact);
    const auto atPoint = reference(m, 3, Lights::SampledExactAtPoint);
    expectAgree(atPoint, exact, "60 point + 3 spot lights, 3 bounces, exact at the point");
    const auto sampled = reference(m, 3, Lights::Sampled);
    double seAtPoint = 0, seSampled = 0;
    for (std::size_t i = 0; i < m.points.size(); ++i) {
        seAtPoint += luminance(Rgb(atPoint[i].standardError)) / luminance(Rgb(atPoint[i].irradiance));
        seSampled += luminance(Rgb(sampled[i].standardError)) / luminance(Rgb(sampled[i].irradiance));
    }
    std::printf("  mean relative standard error: exact at the point %.4f, sampled at the point %.4f\n",
                seAtPoint / m.points.size(), seSampled / m.points.size());
    EXPECT_LT(seAtPoint, seSampled);
}

double dcLuminance(const Rgbd c[9]) { return 0.2126 * c[0].x + 0.7152 * c[0].y + 0.0722 * c[0].z; }

TEST(ManyLights, BakeWithSamplerMatchesExactProjectionWithBounces) {
    // The SH projection at a node (bake.h) with lights sampled at every path vertex against
    // the exact sum: the DC coefficient from 4096 rays agrees within the noise of the
    // sampled lights at the bounce (a few percent; unbiasedness is tested above), for a
    // fraction of the shadow rays. (At the node itself the 203 lights are fewer than the
    // rays, so both evaluate them exactly there.)
    const ManyLights m(200, 13, 6);
    const auto& pts = m.points;
    const RadianceEstimator exact(m.scene, m.tracer, transport(1, true));
    const RadianceEstimator sampled(m.scene, m.tracer, transport(1, false));
    ASSERT_FALSE(exact.samplesPunctualLights());
    ASSERT_TRUE(sampled.samplesPunctualLights());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        Rgbd a[9], b[9];
        RayCount ca, cb;
        projectIncidentRadiance(exact, pts[i].position, 4096, 1, i, a, ca);
        projectIncidentRadiance(sampled, pts[i].position, 4096, 1, i, b, cb);
        std::printf("  point %zu: DC exact %.5f, sampled %.5f; shadow rays %llu vs %llu\n", i, dcLuminance(a),
                    dcLuminance(b), (unsigned long long)ca.occluded, (unsigned long long)cb.occluded);
        EXPECT_NEAR(dcLuminance(b), dcLuminance(a), 0.06 * dcLuminance(a)) << "point " << i;
        EXPECT_LT(cb.occluded * 20, ca.occluded);
    }
}

TEST(ManyLights, BakeSamplesLightsAtTheNodeWhenTheyOutnumberRays) {
    // 1000 lights, 256 rays per node, direct light only: the node picks one light per ray.
    // The mean over 32 seeds against the exact projection, within 4 standard errors.
    const ManyLights m(1000, 14, 3);
    const auto& pts = m.points;
    const RadianceEstimator exact(m.scene, m.tracer, transport(0, true));
    const RadianceEstimator sampled(m.scene, m.tracer, transport(0, false));
    for (std::size_t i = 0; i < pts.size(); ++i) {
        // Paired by seed: the sky, NEE and direction parts are the same in both and cancel.
        RayCount ca, cb;
        double sum = 0, sumSq = 0, exactMean = 0;
        const int seeds = 32;
        for (int seed = 0; seed < seeds; ++seed) {
            Rgbd a[9], b[9];
            projectIncidentRadiance(exact, pts[i].position, 256, 100 + seed, i, a, ca);
            projectIncidentRadiance(sampled, pts[i].position, 256, 100 + seed, i, b, cb);
            const double d = dcLuminance(b) - dcLuminance(a);
            sum += d;
            sumSq += d * d;
            exactMean += dcLuminance(a) / seeds;
        }
        const double mean = sum / seeds, se = std::sqrt(std::max(0.0, sumSq / seeds - mean * mean) / (seeds - 1));
        std::printf("  point %zu: DC exact %.5f, sampled - exact over %d seeds %.5f +- %.5f; shadow rays per node %llu vs %llu\n",
                    i, exactMean, seeds, mean, se, (unsigned long long)(ca.occluded / seeds),
                    (unsigned long long)(cb.occluded / seeds));
        EXPECT_GT(se, 0.0);
        EXPECT_LT(std::abs(mean), 4 * se + 1e-4 * exactMean) << "point " << i;
        EXPECT_LT(cb.occluded * 2, ca.occluded);  // 256 NEE + 256 light rays vs 256 + 1003
    }
}

TEST(ManyLights, AntialiasedPassSamplesLightsPerOrigin) {
    // The anti-aliased pass (bake_antialiased.h) with one light per ray origin against every
    // light at every origin: node DC terms agree within the light-sampling noise, for a
    // fraction of the shadow rays. The lights are kept above the baked cells: a point light
    // inside a cell gives the origins' estimate an infinite variance (1/d^4 is not integrable
    // in a volume), exact or sampled, and no comparison would converge.
    const Scene s = withManyLights(300, 15, 0.7, 0.9);
    const Tracer tracer(s);
    const Bounds sb = s.bounds();
    GridPlacement p;
    p.resolution = 3;
    Bounds box = sb;
    box.lo = sb.lo + sb.size() * 0.1;
    box.hi = sb.lo + sb.size() * Vec3d(0.9, 0.5, 0.9);
    p.bounds = box;
    const GridSpec g = placeUniformGrid(box, p, 1);
    AntialiasedOptions o;
    o.raysPerCell = 2048;
    o.domain = DomainMode::All;
    o.transport.maxBounces = 0;
    BakeStats sampledStats, exactStats;
    const Volume sampled = bakeShAntialiased(s, tracer, g, o, nullptr, &sampledStats);
    o.transport.exactLightLimit = 1u << 30;
    const Volume exact = bakeShAntialiased(s, tracer, g, o, nullptr, &exactStats);
    double worst = 0;
    for (std::size_t n = 0; n < g.nodeCount(); ++n) {
        const float* a = exact.levels[0].data.data() + n * 27;
        const float* b = sampled.levels[0].data.data() + n * 27;
        const double ea = luminance(Rgb(a[0], a[1], a[2])), eb = luminance(Rgb(b[0], b[1], b[2]));
        worst = std::max(worst, std::abs(eb - ea) / ea);
        EXPECT_NEAR(eb, ea, 0.05 * ea) << "node " << n;
    }
    std::printf("  anti-aliased, 303 lights: worst node DC difference %.2f %%; shadow rays %llu sampled vs %llu exact\n",
                100 * worst, (unsigned long long)sampledStats.rays.occluded, (unsigned long long)exactStats.rays.occluded);
    EXPECT_LT(sampledStats.rays.occluded * 20, exactStats.rays.occluded);
}
