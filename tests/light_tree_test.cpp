// The oriented light tree (light/light_tree.h) and emissive triangles chosen by it: cone
// unions contain their cones, the pmf is a distribution and matches sampling, the importance
// never rules out a light that contributes, and the NEE estimator with the tree is unbiased
// (its expectation over the light choice is the exact sum over every emitter; `reference`
// with the tree agrees with the global power CDF, with bounces, so the MIS pdfs match).
#include <gtest/gtest.h>

#include <cmath>

#include "../libvdblight/src/light/light_tree.h"
#include "vdblight/light/light.h"
#include "vdblight/reference/reference.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {
double angle(const Vec3d& a, const Vec3d& b) { return std::acos(std::clamp(dot(a, b), -1.0, 1.0)); }

LightBounds randomCone(Rng& rng) {
    LightBounds b;
    const Vec3d p(rng.uniform(), rng.uniform(), rng.uniform());
    b.box.extend(p);
    b.box.extend(p + Vec3d(0.1 * rng.uniform(), 0.1 * rng.uniform(), 0.1 * rng.uniform()));
    b.power = 0.1 + rng.uniform();
    b.axis = Vec3d(uniformSphere(rng.uniform(), rng.uniform()));
    b.axis = normalize(b.axis);
    b.thetaO = rng.uniform() < 0.3 ? 0.0 : kPi * rng.uniform();
    b.thetaE = rng.uniform() < 0.5 ? 0.5 * kPi : 0.0;
    b.twoSided = rng.uniform() < 0.3;
    return b;
}

/// The Cornell box with `count` small emissive triangles inside it, random positions and
/// orientations, a third of them two-sided (plus the ceiling light's two triangles).
Scene withManyEmitters(int count, uint64_t seed) {
    Scene s = loadScene(defaultScenePath());
    const Bounds b = s.bounds();
    Material one, two;
    one.name = "small_emitter";
    one.emission = Rgb(4, 3, 2);
    two = one;
    two.name = "small_emitter_two_sided";
    two.twoSidedEmission = true;
    const uint32_t m1 = addMaterial(s, one), m2 = addMaterial(s, two);
    Rng rng(seed);
    const float size = 0.02f * float(b.size().x);
    for (int i = 0; i < count; ++i) {
        const Vec3d t(0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform());
        const Vec3f c(b.lo + b.size() * t);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        Vec3f e1, e2;
        orthonormalBasis(n, e1, e2);
        addTriangle(s, c, c + e1 * size, c + e2 * size, i % 3 == 0 ? m2 : m1);
    }
    return s;
}
}  // namespace

TEST(LightTree, ConeUnionContainsBothCones) {
    Rng rng(1);
    for (int i = 0; i < 2000; ++i) {
        const LightBounds a = randomCone(rng), b = randomCone(rng);
        const LightBounds u = unionBounds(a, b);
        EXPECT_NEAR(length(u.axis), 1.0, 1e-9);
        if (u.thetaO < kPi) {
            EXPECT_LE(angle(u.axis, a.axis) + a.thetaO, u.thetaO + 1e-6) << i;  // acos near 1: ~1e-8
            EXPECT_LE(angle(u.axis, b.axis) + b.thetaO, u.thetaO + 1e-6) << i;  // acos near 1: ~1e-8
        }
        EXPECT_EQ(u.thetaE, std::max(a.thetaE, b.thetaE));
        EXPECT_DOUBLE_EQ(u.power, a.power + b.power);
    }
}

// The pmf over every light sums to 1, with and without a normal, and sample() reports it.
TEST(LightTree, PmfIsADistributionAndMatchesSampling) {
    Rng rng(2);
    std::vector<LightBounds> lights;
    for (int i = 0; i < 300; ++i) lights.push_back(randomCone(rng));
    const LightTree tree(lights);
    for (int k = 0; k < 20; ++k) {
        const Vec3d x(2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5, 2 * rng.uniform() - 0.5);
        const Vec3d n = normalize(Vec3d(uniformSphere(rng.uniform(), rng.uniform())));
        for (const Vec3d* normal : {static_cast<const Vec3d*>(nullptr), &n}) {
            double total = 0;
            for (uint32_t l = 0; l < lights.size(); ++l) {
                const double p = tree.pmf(x, normal, l);
                EXPECT_GT(p, 0) << l;  // the uniform mix keeps every light reachable
                total += p;
            }
            EXPECT_NEAR(total, 1.0, 1e-12);
            for (int j = 0; j < 20; ++j) {
                double pmf = 0;
                const uint32_t l = tree.sample(x, normal, rng.uniform(), pmf);
                EXPECT_NEAR(pmf, tree.pmf(x, normal, l), 1e-15 + 1e-12 * pmf);
            }
        }
    }
}

// Zero importance only where a light cannot contribute: behind a one-sided emitter (at any
// point of it), outside a spot cone, or behind the receiving surface.
TEST(LightTree, ImportanceIsZeroOnlyWhereNothingArrives) {
    Rng rng(3);
    LightBounds tri;  // a small one-sided triangle at the origin facing +z
    tri.box.extend(Vec3d(0, 0, 0));
    tri.box.extend(Vec3d(0.1, 0.1, 0));
    tri.power = 1;
    tri.axis = Vec3d(0, 0, 1);
    tri.thetaO = 0;
    tri.thetaE = 0.5 * kPi;
    for (int i = 0; i < 20000; ++i) {
        const Vec3d x(4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2);
        const Vec3d q(0.1 * rng.uniform(), 0.1 * rng.uniform() * 0, 0);  // a point of the emitter
        const Vec3d to = x - q;
        const bool reaches = to.z > 0;  // the front side sees it
        if (reaches) {
            EXPECT_GT(LightTree::importance(tri, x, nullptr), 0) << x.x << "," << x.y << "," << x.z;
        }
        const Vec3d n = normalize(Vec3d(uniformSphere(rng.uniform(), rng.uniform())));
        if (reaches && dot(n, -to) > 0) {
            EXPECT_GT(LightTree::importance(tri, x, &n), 0);
        }
    }
    LightBounds spot;  // a spot at the origin pointing down, 0.5 rad outer cone
    spot.box.extend(Vec3d(0, 0, 0));
    spot.power = 1;
    spot.axis = Vec3d(0, -1, 0);
    spot.thetaO = 0.5;
    spot.thetaE = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3d x(4 * rng.uniform() - 2, 4 * rng.uniform() - 2, 4 * rng.uniform() - 2);
        const bool inside = angle(normalize(x), spot.axis) < 0.5;
        EXPECT_EQ(LightTree::importance(spot, x, nullptr) > 0, inside);
    }
}

// The NEE estimator's expectation over the light choice w (midpoint rule, 2^18 values) with
// fixed points on the triangles (u, v) is the exact sum over every emitter of L A cos / d^2
// (unoccluded, front-facing), at free-space points.
TEST(LightTree, EmissiveTriangleSamplerExpectationIsTheExactSum) {
    const Scene s = withManyEmitters(400, 7);
    const Tracer tracer(s);
    const RadianceEstimator estimator(s, tracer, TransportOptions{});
    ASSERT_TRUE(estimator.usesEmitterTree());
    const Bounds b = s.bounds();
    Rng rng(9);
    for (int p = 0; p < 3; ++p) {
        const Vec3f x(b.lo + b.size() * Vec3d(0.2 + 0.6 * rng.uniform(), 0.2 + 0.6 * rng.uniform(), 0.2 + 0.6 * rng.uniform()));
        const float u = rng.uniform(), v = rng.uniform();
        double exact = 0;
        for (std::size_t t = 0; t < s.triangleCount(); ++t) {
            const Material& m = s.material(t);
            if (!m.isEmissive()) continue;
            float b1, b2;
            uniformTriangle(u, v, b1, b2);
            const Vec3f a = s.vertex(t, 0), e1 = s.vertex(t, 1) - a, e2 = s.vertex(t, 2) - a;
            const Vec3f q = a + e1 * b1 + e2 * b2;
            const Vec3f ng = cross(e1, e2);
            const double area = 0.5 * length(Vec3d(ng));
            const Vec3f toLight = q - x;
            const double d2 = dot(Vec3d(toLight), Vec3d(toLight));
            double cosLight = -dot(Vec3d(normalize(ng)), Vec3d(toLight)) / std::sqrt(d2);
            if (m.twoSidedEmission) cosLight = std::abs(cosLight);
            if (cosLight <= 0) continue;
            if (tracer.occluded(Ray{x, toLight, 0.0f, 1.0f - 1e-4f})) continue;
            exact += luminance(m.emission) * area * cosLight / d2;
        }
        const int K = 1 << 18;
        double sum = 0;
        RayCount rays;
        for (int k = 0; k < K; ++k) {
            LightSample ls;
            if (estimator.sampleEmissiveTriangles(x, u, v, (k + 0.5) / K, ls, rays)) sum += luminance(ls.weight);
        }
        std::printf("  point %d: exact sum over %zu emitters %.6f, expectation of the tree sampler %.6f\n", p,
                    s.triangleCount(), exact, sum / K);
        EXPECT_NEAR(sum / K, exact, 1e-3 * exact);
    }
}

// With bounces and MIS (gathered rays hitting emitters use the tree's pdf at their origin),
// `reference` with the emitter tree agrees with the global power CDF within their errors.
TEST(LightTree, ReferenceWithEmitterTreeMatchesTheCdf) {
    const Scene s = withManyEmitters(400, 8);
    const Tracer tracer(s);
    const Bounds b = s.bounds();
    Rng rng(4);
    std::vector<ReferencePoint> pts;
    for (int i = 0; i < 8; ++i)
        pts.push_back({Vec3f(b.lo + b.size() * Vec3d(0.15 + 0.7 * rng.uniform(), 0.15 + 0.7 * rng.uniform(),
                                                      0.15 + 0.7 * rng.uniform())),
                       uniformSphere(rng.uniform(), rng.uniform())});
    ReferenceOptions o;
    o.samples = 8192;
    o.transport.maxBounces = 2;
    const auto tree = referenceIrradiance(s, tracer, pts, o);
    o.transport.orientedLightTree = false;
    o.seed = 5;
    const auto cdf = referenceIrradiance(s, tracer, pts, o);
    double worstZ = 0, seTree = 0, seCdf = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double a = luminance(Rgb(tree[i].irradiance)), c = luminance(Rgb(cdf[i].irradiance));
        const double sa = luminance(Rgb(tree[i].standardError)), sc = luminance(Rgb(cdf[i].standardError));
        const double z = std::abs(a - c) / std::hypot(sa, sc);
        worstZ = std::max(worstZ, z);
        seTree += sa / a, seCdf += sc / c;
        EXPECT_LT(z, 4.5) << "point " << i << ": tree " << a << " +- " << sa << ", cdf " << c << " +- " << sc;
    }
    std::printf("  worst |z| %.2f over %zu points; mean relative standard error: tree %.4f, CDF %.4f\n", worstZ,
                pts.size(), seTree / pts.size(), seCdf / pts.size());
}
