// ShFourUniformLookup (query/sh4_uniform_lookup.h), the fast lookup of single-level sh:4
// volumes: it must give the generic ChannelLookup's answers (irradiance, channelValues,
// shRadiance, the outside policy, depth weights on and off) on random volumes at random
// points, outside the box, on cell faces and edges and at nodes, and on a baked volume;
// IrradianceQuery must pick it for sh:4 uniform volumes only. The comparison is shown to fail
// on a band-4 factor off by 0.1 %, on depth weights left out, and to ignore band 3 (A_3 = 0).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "random_volumes.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "query/channel_lookup.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/query/sh4_uniform_lookup.h"  // internal: ShFourUniformLookup

using namespace vdblight;

namespace {

constexpr int kFloats = ShFourUniformLookup::kCoeffs * 3;  // 75 per node

/// An sh:4 level (test::randomUniformVolume: values in [-0.5, 1.5), so that every band matters
/// and terms cancel). With `depth`, random depth moments k/255: means in [0, 1] (a near wall
/// hides the corner from part of the cell), deviations in [0, 0.25].
Volume randomShFourVolume(int nx, int ny, int nz, double spacing, uint64_t seed, bool depth) {
    Volume v = test::randomUniformVolume(makeBasis("sh:4")->desc(), nx, ny, nz, spacing, seed);
    if (depth) {
        VolumeLevel& level = v.levels[0];
        Rng rng(seed + 1000);
        level.depth.resize(level.grid.nodeCount() * depth::kFloatsPerNode);
        for (std::size_t i = 0; i < level.depth.size(); ++i) {
            const bool sigma = (i % depth::kFloatsPerNode) >= 6;  // channels 2 and 3
            level.depth[i] = depth::quantize(sigma ? 0.25 * rng.uniform() : rng.uniform());
        }
    }
    v.validate();
    return v;
}

/// A point of one of four kinds around the node box of g: inside; anywhere in the box grown by
/// half its size on every side (about 3/4 of them outside); inside with one coordinate on a node
/// plane (a cell face); inside with two coordinates on node planes (a cell edge; a node if the
/// third falls on one too, which the last kind forces).
Vec3f samplePoint(const GridSpec& g, Rng& rng, int kind) {
    const Bounds b = g.nodeBounds();
    Vec3d u(rng.uniform(), rng.uniform(), rng.uniform());
    if (kind == 1) u = u * 2.0 - Vec3d(0.5, 0.5, 0.5);
    Vec3d x = b.lo + b.size() * u;
    const int dims[3] = {g.nx, g.ny, g.nz};
    const int snapped = kind >= 2 ? kind - 1 : 0;  // kind 2: one axis, 3: two, 4: three
    const int first = int(rng.uniform() * 3) % 3;
    for (int s = 0; s < snapped; ++s) {
        const int a = (first + s) % 3;
        const int node = std::min(int(rng.uniform() * dims[a]), dims[a] - 1);
        x[a] = g.origin[a] + node * g.spacing;
    }
    return Vec3f(x);
}

/// How far `fast` is from `reference` at `count` points (samplePoint, every kind in turn) and
/// random unit normals: points whose difference in a colour exceeds the tolerance
/// 1e-5 * max(1, |reference|), and the largest difference relative to max(1, |reference|).
struct Agreement {
    int failures = 0;
    double worst = 0;
    int count = 0;
};
Agreement compareIrradiance(const VolumeLookup& fast, const VolumeLookup& reference, const GridSpec& g, uint64_t seed,
                            int count) {
    Agreement a;
    Rng rng(seed);
    for (int t = 0; t < count; ++t) {
        const Vec3f x = samplePoint(g, rng, t % 5);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb e = fast.irradiance(x, n), want = reference.irradiance(x, n);
        bool bad = false;
        for (int c = 0; c < 3; ++c) {
            const double rel = std::fabs(double(e[c]) - want[c]) / std::max(1.0, std::fabs(double(want[c])));
            a.worst = std::max(a.worst, rel);
            bad = bad || !(rel <= 1e-5);  // NaN fails too
        }
        a.failures += bad;
        ++a.count;
    }
    return a;
}

}  // namespace

TEST(ShFourUniformLookup, IrradianceMatchesChannelLookupWithAndWithoutDepthWeights) {
    for (const bool depth : {false, true}) {
        const Volume v = randomShFourVolume(7, 5, 6, 0.3, 11, depth);
        ASSERT_TRUE(ShFourUniformLookup::accepts(v));
        const ShFourUniformLookup fast(v, OutsidePolicy::Clamp);
        const ChannelLookup generic(v, OutsidePolicy::Clamp);
        EXPECT_EQ(fast.depthWeighted(), depth);
        const Agreement a = compareIrradiance(fast, generic, v.levels[0].grid, 12, 20000);
        EXPECT_EQ(a.failures, 0) << "depth " << depth << ": worst relative difference " << a.worst;
        std::printf("[ info ] depth %d: %d points, worst relative difference %.3g\n", int(depth), a.count, a.worst);

        // Switched off, both fall back to plain trilinear weights alike.
        ShFourUniformLookup fastOff(v, OutsidePolicy::Clamp);
        ChannelLookup genericOff(v, OutsidePolicy::Clamp);
        fastOff.setDepthWeights(false);
        genericOff.setDepthWeights(false);
        EXPECT_FALSE(fastOff.depthWeighted());
        EXPECT_EQ(compareIrradiance(fastOff, genericOff, v.levels[0].grid, 13, 5000).failures, 0) << "depth " << depth;
    }
}

TEST(ShFourUniformLookup, FlatAxesMatchChannelLookup) {
    // Axes with a single node (no interpolation along them), as ChannelLookup reads them.
    const int shapes[][3] = {{5, 1, 3}, {1, 4, 1}, {1, 1, 1}, {2, 2, 1}};
    for (const auto& s : shapes) {
        const Volume v = randomShFourVolume(s[0], s[1], s[2], 0.4, 21, true);
        const ShFourUniformLookup fast(v, OutsidePolicy::Clamp);
        const ChannelLookup generic(v, OutsidePolicy::Clamp);
        const Agreement a = compareIrradiance(fast, generic, v.levels[0].grid, 22, 3000);
        EXPECT_EQ(a.failures, 0) << s[0] << "x" << s[1] << "x" << s[2] << ": worst " << a.worst;
    }
}

TEST(ShFourUniformLookup, ThrowPolicyRefusesTheSamePointsAsChannelLookup) {
    const Volume v = randomShFourVolume(4, 5, 3, 0.5, 31, true);
    const ShFourUniformLookup fast(v, OutsidePolicy::Throw);
    const ChannelLookup generic(v, OutsidePolicy::Throw);
    const GridSpec& g = v.levels[0].grid;
    const Bounds b = g.nodeBounds();
    Rng rng(32);
    int thrown = 0;
    for (int t = 0; t < 4000; ++t) {
        // Near a face of the box: within +-3e-4 of a cell of it, across the 1e-4 tolerance.
        Vec3d x = b.lo + b.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform());
        const int a = t % 3;
        const double off = (rng.uniform() * 2 - 1) * 3e-4 * g.spacing;
        x[a] = (t % 2 ? b.hi[a] : b.lo[a]) + off;
        const Vec3f xf(x), n = uniformSphere(rng.uniform(), rng.uniform());
        bool fastThrew = false, genericThrew = false;
        Rgb e{0, 0, 0}, want{0, 0, 0};
        try {
            e = fast.irradiance(xf, n);
        } catch (const ValueError&) {
            fastThrew = true;
        }
        try {
            want = generic.irradiance(xf, n);
        } catch (const ValueError&) {
            genericThrew = true;
        }
        ASSERT_EQ(fastThrew, genericThrew) << "t " << t;
        thrown += fastThrew;
        if (fastThrew) continue;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(e[c], want[c], 1e-5 * std::max(1.0f, std::fabs(want[c]))) << "t " << t;
    }
    EXPECT_GT(thrown, 500);  // both sides of the tolerance were tried
    EXPECT_LT(thrown, 3500);
}

TEST(ShFourUniformLookup, ChannelValuesAndShRadianceMatchChannelLookup) {
    for (const bool depth : {false, true}) {
        const Volume v = randomShFourVolume(5, 4, 6, 0.35, 41, depth);
        const ShFourUniformLookup fast(v, OutsidePolicy::Clamp);
        const ChannelLookup generic(v, OutsidePolicy::Clamp);
        const GridSpec& g = v.levels[0].grid;
        Rng rng(42);
        float a[kFloats], b[kFloats];
        for (int t = 0; t < 3000; ++t) {
            const Vec3d x(samplePoint(g, rng, t % 5));
            fast.channelValues(x, a);
            generic.channelValues(x, b);
            for (int f = 0; f < kFloats; ++f) ASSERT_NEAR(a[f], b[f], 1e-6 * std::max(1.0f, std::fabs(b[f]))) << "t " << t;
            Rgb la[9], lb[9];
            fast.shRadiance(x, la);
            generic.shRadiance(x, lb);
            for (int j = 0; j < 9; ++j)
                for (int c = 0; c < 3; ++c) ASSERT_EQ(la[j][c], a[3 * j + c]) << "shRadiance is channelValues' first nine";
            for (int j = 0; j < 9; ++j)
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(la[j][c], lb[j][c], 1e-6 * std::max(1.0f, std::fabs(lb[j][c])));
        }
        // At a node: exactly that node's stored values (what export relies on).
        for (std::size_t n = 0; n < g.nodeCount(); n += 3) {
            fast.channelValues(g.node(n), a);
            for (int f = 0; f < kFloats; ++f) ASSERT_EQ(a[f], v.levels[0].data[n * kFloats + f]) << "node " << n;
        }
    }
}

TEST(ShFourUniformLookup, BakedVolumeWithDepthMomentsMatchesChannelLookup) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement p;
    p.resolution = 5;
    GatherOptions o;
    o.raysPerNode = 64;
    o.transport.maxBounces = 2;
    o.basis = makeBasis("sh:4");
    o.depthMoments = true;
    const Volume v = bakeShGather(s, tracer, placeUniformGrid(s.bounds(), p, 1), o);
    ASSERT_TRUE(v.hasDepth());
    const IrradianceQuery q(v);
    ASSERT_STREQ(q.kind(), "sh4-uniform");
    EXPECT_TRUE(q.depthWeighted());
    const ChannelLookup generic(v, OutsidePolicy::Clamp);
    const Agreement a = compareIrradiance(q.lookup(), generic, v.levels[0].grid, 51, 20000);
    EXPECT_EQ(a.failures, 0) << "worst relative difference " << a.worst;
}

TEST(ShFourUniformLookup, RegistryPicksItForUniformShFourVolumesOnly) {
    EXPECT_STREQ(IrradianceQuery(randomShFourVolume(3, 3, 3, 0.5, 61, false)).kind(), "sh4-uniform");
    EXPECT_TRUE(IrradianceQuery(randomShFourVolume(3, 3, 3, 0.5, 61, true)).depthWeighted());
    EXPECT_FALSE(IrradianceQuery(randomShFourVolume(3, 3, 3, 0.5, 61, true), OutsidePolicy::Clamp, false).depthWeighted());

    // sh:3 on one level: the generic lookup.
    Volume sh3 = randomShFourVolume(3, 3, 3, 0.5, 62, false);
    sh3.basis = makeBasis("sh:3")->desc();
    sh3.levels[0].data.resize(sh3.levels[0].grid.nodeCount() * 16 * 3);
    EXPECT_FALSE(ShFourUniformLookup::accepts(sh3));
    EXPECT_STREQ(IrradianceQuery(sh3).kind(), "basis");

    // sh:4 on several levels: the generic lookup (it descends through refined cells).
    for (const LayoutKind kind : {LayoutKind::Bilevel, LayoutKind::Adaptive}) {
        const Volume levels = test::randomLevelsVolume(kind, kind == LayoutKind::Bilevel ? 2 : 3,
                                                       makeBasis("sh:4")->desc(), 63, -0.5f, 1.5f);
        ASSERT_GT(levels.levels.size(), 1u);
        EXPECT_FALSE(ShFourUniformLookup::accepts(levels));
        EXPECT_STREQ(IrradianceQuery(levels).kind(), "basis");
    }

    // "sh:4" with channel names that are not the basis's: no registered basis, no fast lookup.
    Volume renamed = randomShFourVolume(3, 3, 3, 0.5, 64, false);
    renamed.basis.channelNames[20] = "something_else";
    EXPECT_FALSE(ShFourUniformLookup::accepts(renamed));
    EXPECT_THROW((void)ShFourUniformLookup(renamed, OutsidePolicy::Clamp), FormatError);
}

TEST(ShFourUniformLookup, ComparisonCatchesAWrongBandFourFactorAndIgnoresBandThree) {
    // Negative controls of compareIrradiance: the generic lookup on a volume whose band-4
    // channels are scaled by 1.001 is what a lookup with A_4 off by 0.1 % would return.
    const Volume v = randomShFourVolume(6, 5, 4, 0.3, 71, true);
    const ShFourUniformLookup fast(v, OutsidePolicy::Clamp);
    Volume wrongA4 = v;
    for (std::size_t n = 0; n < v.levels[0].grid.nodeCount(); ++n)
        for (int f = 16 * 3; f < kFloats; ++f) wrongA4.levels[0].data[n * kFloats + f] *= 1.001f;
    const Agreement bad = compareIrradiance(fast, ChannelLookup(wrongA4, OutsidePolicy::Clamp), v.levels[0].grid, 72, 4000);
    EXPECT_GT(bad.failures, 100) << "worst " << bad.worst;

    // Depth weights left out (plain trilinear against depth-weighted): caught too.
    ShFourUniformLookup plain(v, OutsidePolicy::Clamp);
    plain.setDepthWeights(false);
    EXPECT_GT(compareIrradiance(plain, ChannelLookup(v, OutsidePolicy::Clamp), v.levels[0].grid, 73, 4000).failures, 100);

    // Band 3 changed wholesale: no irradiance difference at all (A_3 = 0), which is why the
    // fast lookup leaves it out of its blend.
    Volume otherBand3 = v;
    Rng rng(74);
    for (std::size_t n = 0; n < v.levels[0].grid.nodeCount(); ++n)
        for (int f = 9 * 3; f < 16 * 3; ++f) otherBand3.levels[0].data[n * kFloats + f] = rng.uniform() * 10.0f;
    const Agreement same = compareIrradiance(fast, ChannelLookup(otherBand3, OutsidePolicy::Clamp), v.levels[0].grid, 75, 4000);
    EXPECT_EQ(same.failures, 0) << "worst " << same.worst;
}

TEST(ShFourUniformLookup, RepeatedLookupsGiveTheSameBits) {
    const Volume v = randomShFourVolume(6, 6, 6, 0.25, 81, true);
    const ShFourUniformLookup a(v, OutsidePolicy::Clamp), b(v, OutsidePolicy::Clamp);
    Rng rng(82);
    for (int t = 0; t < 2000; ++t) {
        const Vec3f x = samplePoint(v.levels[0].grid, rng, t % 5), n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb e1 = a.irradiance(x, n), e2 = b.irradiance(x, n), e3 = a.irradiance(x, n);
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(e1[c], e2[c]);
            ASSERT_EQ(e1[c], e3[c]);
        }
    }
}
