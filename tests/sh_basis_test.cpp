// Basis "sh:N" (src/basis/sh_basis.cpp), through the Basis interface only:
// - projection of a constant and of a clamped cosine lobe max(0, w . a) gives the closed-form
//   irradiance of the truncated expansion, E_N(n) = sum_{l <= N} A_l^2 (2l + 1) / (4 pi)
//   P_l(a . n) (Funk-Hecke: the lobe's coefficients are A_l Y_lm(a)); the quadrature is exact
//   for these integrands (Gauss-Legendre in t = w . a on [-1, 0] and [0, 1] separately, equal
//   steps in the azimuth), so the tolerance is float rounding. For N = 4 the truncated value
//   differs from the exact E(g) = 2/3 ((pi - g) cos g + sin g) by -0.0041 at g = 0;
// - its terms are A_l times sh::evalGeneric (the reference SH of sh.h);
// - sh:2 evaluates sh2's nodes as sh2's lookup does, and sh:2 baked by the generic gather
//   agrees with sh2's own gather on the Cornell box within noise;
// - the same bits for 1 and 2 threads; bad specs refused with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "bake/bake_basis.h"
#include "bake/bake_bins.h"
#include "vdblight/basis/basis.h"
#include "query/channel_lookup.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup

using namespace vdblight;

namespace {
double bandFactor(int l) {
    const double a[5] = {kPi, 2 * kPi / 3, kPi / 4, 0.0, -kPi / 24};
    return a[l];
}

double legendre(int l, double x) {
    double p0 = 1, p1 = x;
    if (l == 0) return 1;
    for (int k = 2; k <= l; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
    }
    return p1;
}

/// 8-point Gauss-Legendre nodes and weights on [-1, 1].
const double kGlX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                        0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
const double kGlW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                        0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

/// Projects the radiance L(w) = c0 + c1 max(0, w . a) (RGB scaled by `colour`) onto `basis`
/// with a quadrature exact for it (polynomials in t = w . a of degree <= 15 on each half).
std::vector<float> project(const Basis& basis, const Vec3d& a, double c0, double c1, const Rgb& colour) {
    Vec3d u = std::fabs(a.x) < 0.9 ? normalize(cross(a, Vec3d(1, 0, 0))) : normalize(cross(a, Vec3d(0, 1, 0)));
    const Vec3d v = cross(a, u);
    std::vector<Rgbd> acc(basis.accumulatorSize(), Rgbd(0, 0, 0));
    const int phis = 32;
    for (int half = 0; half < 2; ++half)
        for (int i = 0; i < 8; ++i) {
            const double t = half ? 0.5 * (kGlX[i] + 1) : 0.5 * (kGlX[i] - 1), wt = 0.5 * kGlW[i];
            const double s = std::sqrt(1 - t * t);
            for (int p = 0; p < phis; ++p) {
                const double phi = 2 * kPi * (p + 0.5) / phis;
                const Vec3d w = a * t + u * (s * std::cos(phi)) + v * (s * std::sin(phi));
                const double L = c0 + c1 * std::max(0.0, t);
                basis.accumulate(Vec3f(w), Rgbd(colour) * L, wt * 2 * kPi / phis, acc.data());
            }
        }
    std::vector<float> values(basis.floatsPerNode());
    basis.finish(acc.data(), values.data());
    return values;
}

/// E_N(n) of the truncated expansion of c0 + c1 max(0, w . a).
double truncatedIrradiance(int order, const Vec3d& a, const Vec3d& n, double c0, double c1) {
    double e = kPi * c0;
    for (int l = 0; l <= order; ++l) e += c1 * bandFactor(l) * bandFactor(l) * (2 * l + 1) / (4 * kPi) * legendre(l, dot(a, n));
    return e;
}
}  // namespace

TEST(ShBasis, ProjectionGivesTheClosedFormIrradianceOfEveryOrder) {
    const Vec3d a = normalize(Vec3d(1, 2, -3));
    const Rgb colour(0.5f, 1.0f, 2.0f);
    const Vec3d normals[] = {a, -a, normalize(Vec3d(0, 0, 1)), normalize(Vec3d(1, -1, 0.3)), normalize(Vec3d(2, 1, 1))};
    for (int order = 1; order <= 4; ++order) {
        SCOPED_TRACE(order);
        const std::unique_ptr<Basis> b = makeBasis("sh:" + std::to_string(order));
        EXPECT_EQ(b->channelCount(), (order + 1) * (order + 1));
        EXPECT_EQ(b->desc().kind, "sh:" + std::to_string(order));
        // A constant: pi L for every normal.
        const std::vector<float> constant = project(*b, a, 1.5, 0.0, colour);
        for (const Vec3d& n : normals) {
            const Rgb e = b->evaluate(constant.data(), Vec3f(n));
            EXPECT_NEAR(e.x, kPi * 1.5 * 0.5, 2e-6 * kPi);
            EXPECT_NEAR(e.z, kPi * 1.5 * 2.0, 8e-6 * kPi);
        }
        // A clamped cosine lobe plus a constant.
        const std::vector<float> lobe = project(*b, a, 0.25, 1.0, colour);
        for (const Vec3d& n : normals) {
            const double want = truncatedIrradiance(order, a, n, 0.25, 1.0);
            const Rgb e = b->evaluate(lobe.data(), Vec3f(n));
            EXPECT_NEAR(e.y, want, 1e-5) << "normal " << n.x << "," << n.y << "," << n.z;
            EXPECT_NEAR(e.z, 2 * want, 2e-5);
        }
    }
    // Order 4 is not the exact answer: at n = a the truncation residual is about -0.0041.
    const std::unique_ptr<Basis> b4 = makeBasis("sh:4");
    const std::vector<float> lobe = project(*b4, a, 0.0, 1.0, Rgb(1, 1, 1));
    const double exact = 2.0 * kPi / 3.0;  // integral of max(0, w . a)^2
    const double e4 = b4->evaluate(lobe.data(), Vec3f(a)).x;
    EXPECT_NEAR(e4 - exact, truncatedIrradiance(4, a, a, 0, 1) - exact, 1e-5);
    EXPECT_NEAR(e4 - exact, -0.0041, 2e-4);
}

TEST(ShBasis, TermsAreTheBandFactorsTimesTheReferenceSh) {
    for (int order = 1; order <= 4; ++order) {
        const std::unique_ptr<Basis> b = makeBasis("sh:" + std::to_string(order));
        for (int s = 0; s < 50; ++s) {
            const Vec3d d = normalize(Vec3d(std::sin(1.3 * s + 0.2), std::cos(0.7 * s), std::sin(2.1 * s + 1.0)));
            double y[25];
            sh::evalGeneric(order, d, y);
            int channels[25];
            float w[25];
            const int n = b->terms(Vec3f(d), channels, w);
            std::vector<double> weight(std::size_t(b->channelCount()), 0.0);
            for (int t = 0; t < n; ++t) weight[std::size_t(channels[t])] = w[t];
            for (int j = 0; j < b->channelCount(); ++j) {
                const int l = int(std::sqrt(double(j)));
                ASSERT_NEAR(weight[std::size_t(j)], bandFactor(l) * y[j], 2e-6) << "order " << order << " j " << j;
            }
        }
    }
    EXPECT_EQ(makeBasis("sh:2")->desc().channelNames, BasisDesc::sh2().channelNames);  // the same grids as sh2
}

TEST(ShBasis, Sh2EvaluatesShTwoVolumesAsShTwosLookup) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement p;
    p.resolution = 4;
    const GridSpec g = placeUniformGrid(s.bounds(), p, 1);
    GatherOptions o;
    o.raysPerNode = 64;
    o.transport.maxBounces = 1;
    Volume v = bakeShGather(s, tracer, g, o);
    const ShUniformLookup sh2(v, OutsidePolicy::Clamp);
    v.basis.kind = "sh:2";  // the same nine channels, read through the basis
    const ChannelLookup shN(v, OutsidePolicy::Clamp);
    for (int i = 0; i < 40; ++i) {
        const Vec3f x = Vec3f(g.origin) + Vec3f(0.37f * (i % 7), 0.61f * (i % 5), 0.23f * (i % 11)) * float(g.spacing * 0.5);
        const Vec3f n = normalize(Vec3f(std::sin(0.9f * i), 0.5f, std::cos(1.7f * i)));
        const Rgb a = sh2.irradiance(x, n), b = shN.irradiance(x, n);
        ASSERT_NEAR(b.x, a.x, 2e-5 * (1 + std::fabs(a.x)));
        ASSERT_NEAR(b.z, a.z, 2e-5 * (1 + std::fabs(a.z)));
    }
}

TEST(ShBasis, Sh2ThroughTheGenericGatherAgreesWithShTwosGatherWithinNoise) {
    // Two unbiased estimates of each node's irradiance from different sample patterns (the
    // generic gather's equal-area strata vs sh2's own), same seed and transport. Their per-node
    // difference d_i (mean irradiance over the six axis normals) has mean 0: the test fails if
    // |mean d| exceeds 4 standard errors of the mean estimated from the d_i themselves (a bias
    // of the generic gather or of sh:N's projection), or if the differences are not at the
    // noise level (mean |d| above 10 % of the mean irradiance; at ~1000 rays per node each
    // estimate's relative noise is a few per cent).
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement p;
    p.resolution = 5;
    const GridSpec g = placeUniformGrid(s.bounds(), p, 1);
    GatherOptions o;
    o.raysPerNode = 1024;
    o.transport.maxBounces = 3;
    const Volume a = bakeShGather(s, tracer, g, o);
    BasisBakeOptions go;
    go.raysPerNode = 1024;
    go.transport = o.transport;
    const Volume b = bakeBasis(s, tracer, uniformLayout(g), *makeBasis("sh:2"), go);
    const IrradianceQuery qa(a), qb(b);
    EXPECT_STREQ(qb.kind(), "basis");
    const Vec3f normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<double> d;
    double sumE = 0, sumAbs = 0;
    for (std::size_t n = 0; n < g.nodeCount(); ++n) {
        const Vec3f x(g.node(n));
        double ea = 0, eb = 0;
        for (const Vec3f& nn : normals) ea += qa.irradiance(x, nn).y / 6, eb += qb.irradiance(x, nn).y / 6;
        d.push_back(eb - ea);
        sumE += ea;
        sumAbs += std::fabs(eb - ea);
    }
    double mean = 0, var = 0;
    for (double x : d) mean += x / double(d.size());
    for (double x : d) var += (x - mean) * (x - mean) / double(d.size() - 1);
    const double stderrOfMean = std::sqrt(var / double(d.size()));
    EXPECT_LT(std::fabs(mean), 4 * stderrOfMean) << "mean difference " << mean << ", mean irradiance " << sumE / d.size();
    EXPECT_LT(sumAbs, 0.10 * sumE);
    std::printf("sh:2 generic vs sh2 gather: %zu nodes, mean irradiance %.4f, mean difference %.5f (%.2f standard errors), "
                "mean |difference| %.2f %%\n",
                d.size(), sumE / d.size(), mean, mean / stderrOfMean, 100 * sumAbs / sumE);
}

TEST(ShBasis, SameBitsForOneAndTwoThreadsUniformAndBilevel) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement p;
    p.resolution = 4;
    const GridSpec g = placeUniformGrid(s.bounds(), p, 1);
    LevelsPlacement lp;
    lp.kind = LayoutKind::Bilevel;
    lp.refine = 2;
    const LevelLayout bilevel = placeLevels(g, s.positions, s.indices, lp, 1), uniform = uniformLayout(g);
    const std::unique_ptr<Basis> basis = makeBasis("sh:3");
    for (const LevelLayout* layout : {&uniform, &bilevel}) {
        BasisBakeOptions o1, o2;
        o1.raysPerNode = o2.raysPerNode = 32;
        o1.threads = 1;
        o2.threads = 2;
        o1.transport.maxBounces = o2.transport.maxBounces = 2;
        const Volume a = bakeBasis(s, tracer, *layout, *basis, o1), b = bakeBasis(s, tracer, *layout, *basis, o2);
        ASSERT_EQ(a.levels.size(), b.levels.size());
        for (std::size_t l = 0; l < a.levels.size(); ++l) {
            ASSERT_EQ(a.levels[l].data.size(), b.levels[l].data.size());
            EXPECT_EQ(0, std::memcmp(a.levels[l].data.data(), b.levels[l].data.data(), a.levels[l].data.size() * sizeof(float)));
        }
    }
}

TEST(ShBasis, BadSpecsAreRefusedWithOneLine) {
    for (const char* bad : {"sh:0", "sh:5", "sh:x", "sh:", "sh:12", "sh:-1"}) {
        SCOPED_TRACE(bad);
        try {
            makeBasis(bad);
            ADD_FAILURE() << "no error";
        } catch (const ValueError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.find('\n'), std::string::npos);
            EXPECT_NE(what.find(std::string("'") + bad + "'"), std::string::npos) << what;
            EXPECT_NE(what.find("1, 2, 3 or 4"), std::string::npos) << what;
        }
    }
}
