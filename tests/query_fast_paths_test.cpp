// The query paths rearranged for speed (issue 33, part 4) against the plain forms they
// replace: the depth weights of every SH lookup (query/depth_weights.h) against
// depth::visibility applied corner by corner, as depth_moments.h writes the formula, bit for
// bit; the sh:4 lookup's node records (sh4_uniform_lookup.h) against the generic lookup of the
// volume's own arrays, the same values; the sh2 and sh:4 lookups' AVX2 versions against their portable ones, bit for bit; the occlusion
// lookup sharing its base's cell against base + direct() (query/shared_cell.h), bit for bit
// where both locate a point alike, shadow edges (issue 32) included; the shared cell's edge
// visibility against shadow_edge::visibility, bit for bit. The lights' float terms themselves
// are tested in fast_exact_lights_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "basis/shadow_edges.h"
#include "query/channel_lookup.h"
#include "query/query_direct.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "../libvdblight/src/query/depth_weights.h"       // internal: query_detail::weightByDepth
#include "../libvdblight/src/query/direct_sum.h"          // internal: query_detail::directLight
#include "../libvdblight/src/query/fast_exact_lights.h"   // internal: the float polygon term
#include "../libvdblight/src/query/shared_cell.h"         // internal: edgeVisibility
#include "../libvdblight/src/query/sh4_uniform_lookup.h"  // internal: the default's sh:4 lookup
#include "../libvdblight/src/query/sh_uniform_lookup.h"   // internal: the sh2 lookup
#include "../libvdblight/src/query/wide_vectors.h"        // internal: cpuHasAvx2

namespace vdblight {
namespace {

/// What the shared path should give at x: `reference`'s base lookup (`base`, the same kind)
/// plus the lights of FastExactLights (point, spot and directional lights in the shader's float
/// operations, fast_exact_lights.h) times `reference`'s visibility, summed as direct() sums.
Rgb baseCellExpected(const VolumeLookup& base, const OcclusionLookup& reference, const query_detail::FastExactLights& fast,
                     const Vec3f& x, const Vec3f& n) {
    const Vec3f nf = query_detail::floatPathNormal(n);
    return base.irradiance(x, n) +
           query_detail::directLight(
               fast.size(), Vec3d(x), n, [&](std::size_t i, const Vec3d& at, const Vec3d& nd) { return fast.irradiance(i, at, nd, nf); },
               [&](float* v) { reference.visibility(Vec3d(x), v); });
}

/// The weights as the formula reads: each corner's visibility from depth::visibility at the
/// point's offset from it, plus the floor, times its trilinear weight, renormalised.
void weightCornerByCorner(float w[8], const float* const depth[8], float fx, float fy, float fz) {
    float sum = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const float v = depth::visibility(depth[c], fx - float(c & 1), fy - float((c >> 1) & 1), fz - float(c >> 2));
        w[c] *= v + depth::kDepthFloor;
        sum += w[c];
    }
    const float inv = 1.0f / sum;
    for (int c = 0; c < 8; ++c) w[c] *= inv;
}

/// A fraction in [0, 1]: often exactly 0, 1 or 1/2 (a node, a cell face), else uniform.
float randomFraction(Rng& rng) {
    const double u = rng.uniform();
    if (u < 0.1) return 0.0f;
    if (u < 0.2) return 1.0f;
    if (u < 0.25) return 0.5f;
    return float(rng.uniform());
}

TEST(QueryFastPaths, DepthWeightsHaveTheBitsOfTheCornerByCornerFormula) {
    Rng rng(3301);
    float depth[8][depth::kFloatsPerNode];
    const float* corners[8];
    for (int c = 0; c < 8; ++c) corners[c] = depth[c];
    int weighted = 0;  // lookups where some corner was (half) hidden, so the weights moved
    for (int t = 0; t < 200000; ++t) {
        // Stored depth: k / 255; means anywhere in a cell (a wall at any distance, or free: 1),
        // deviations small or large.
        for (int c = 0; c < 8; ++c)
            for (int i = 0; i < depth::kFloatsPerNode; ++i) {
                const bool sigma = i >= 6;
                const double u = rng.uniform();
                depth[c][i] = depth::quantize(sigma ? (t % 2 ? 0.1 : 1.0) * u : (u < 0.3 ? 1.0 : u));
            }
        const float f[3] = {randomFraction(rng), randomFraction(rng), randomFraction(rng)};
        float fast[8], plain[8];
        for (int c = 0; c < 8; ++c)
            fast[c] = plain[c] = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
        query_detail::weightByDepth(fast, corners, f[0], f[1], f[2]);
        weightCornerByCorner(plain, corners, f[0], f[1], f[2]);
        for (int c = 0; c < 8; ++c)
            ASSERT_EQ(std::memcmp(&fast[c], &plain[c], sizeof(float)), 0)
                << "t " << t << " f " << f[0] << " " << f[1] << " " << f[2] << ": corner " << c << " " << fast[c] << " vs "
                << plain[c];
        bool hidden = false;
        for (int c = 0; c < 8; ++c)
            hidden = hidden || depth::visibility(depth[c], f[0] - float(c & 1), f[1] - float((c >> 1) & 1),
                                                 f[2] - float(c >> 2)) < 0.5f;
        weighted += hidden;
    }
    EXPECT_GT(weighted, 50000);  // the inputs did exercise the hidden case
    std::printf("[ info ] %d of 200000 lookups had a corner with visibility < 0.5\n", weighted);
}

bool sameBits(const Rgb& a, const Rgb& b) { return std::memcmp(&a, &b, sizeof(Rgb)) == 0; }

/// A random point of the lookup's box widened by 0.1 on every side (so the clamp is exercised too).
Vec3f pointAround(const Bounds& b, Rng& rng) {
    Vec3f x;
    for (int a = 0; a < 3; ++a) x[a] = float(b.lo[a] - 0.1 + (b.hi[a] - b.lo[a] + 0.2) * rng.uniform());
    return x;
}

/// The default bake's kind, small: sh:4 coefficients, depth moments as the bake stores them
/// (k / 255, sigmas below 0.3 cells), visibility in [0, 1] per listed light. 6 x 5 x 7 nodes
/// 0.25 apart from (-0.5, 0.25, 1.0) (randomUniformVolume): lattice coordinates of points on a
/// 1/64 lattice are exact in float and in double.
void fillDepthAsTheBake(VolumeLevel& level, Rng& rng) {
    level.depth.resize(level.grid.nodeCount() * depth::kFloatsPerNode);
    for (std::size_t i = 0; i < level.depth.size(); ++i)
        level.depth[i] = depth::quantize((i % depth::kFloatsPerNode) >= 6 ? 0.3 * rng.uniform() : rng.uniform());
}

Volume defaultKindVolume(std::vector<DirectLight> lights, uint64_t seed) {
    Volume v = test::randomUniformVolume(makeBasis("sh:4")->desc(), 6, 5, 7, 0.25, seed);
    VolumeLevel& level = v.levels[0];
    Rng rng(seed + 1);
    fillDepthAsTheBake(level, rng);
    level.lightVisibility.resize(level.grid.nodeCount() * lights.size());
    for (float& f : level.lightVisibility) f = float(rng.uniform());
    v.direct.mode = DirectMode::Occlusion;
    v.direct.lights = std::move(lights);
    return v;
}

DirectLight pointLight(const Vec3d& at, const Rgb& intensity) {
    DirectLight l;
    l.position = at;
    l.value = intensity;
    return l;
}

/// The sh:4 lookup reads one record per node (coefficients side by side in colour, prepared
/// depth values) and sums the colours in the lanes of one vector: the generic ChannelLookup,
/// which reads the volume's arrays as stored through the basis's terms, gives the same values
/// (each float summed in the same order), with and without depth weights, in and around the box.
TEST(QueryFastPaths, Sh4NodeRecordsGiveTheGenericLookupsValues) {
    const Volume v = defaultKindVolume({}, 17);
    for (const bool depth : {true, false}) {
        ShFourUniformLookup records(v, OutsidePolicy::Clamp);
        ChannelLookup generic(v, OutsidePolicy::Clamp);
        records.setDepthWeights(depth);
        generic.setDepthWeights(depth);
        ASSERT_EQ(records.depthWeighted(), depth);
        Rng rng(18);
        const Bounds b = records.bounds();
        for (int t = 0; t < 20000; ++t) {
            const Vec3f x = pointAround(b, rng);
            const Vec3f n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
            const Rgb a = records.irradiance(x, n), c = generic.irradiance(x, n);
            ASSERT_TRUE(a.x == c.x && a.y == c.y && a.z == c.z)
                << "depth " << depth << " at " << x.x << " " << x.y << " " << x.z << ": " << a.x << " " << a.y << " " << a.z
                << " vs " << c.x << " " << c.y << " " << c.z;
        }
    }
}

TEST(QueryFastPaths, WideVectorsGiveTheBitsOfThePortableSh4Lookup) {
    const Volume v = defaultKindVolume({}, 11);
    for (const bool depth : {true, false}) {
        ShFourUniformLookup wide(v, OutsidePolicy::Clamp), portable(v, OutsidePolicy::Clamp);
        wide.setWideVectors(true);
        wide.setDepthWeights(depth);
        portable.setDepthWeights(depth);
        portable.setWideVectors(false);
        Rng rng(5);
        const Bounds b = wide.bounds();
        for (int t = 0; t < 20000; ++t) {
            const Vec3f x = pointAround(b, rng);
            const Vec3f n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
            const Rgb a = wide.irradiance(x, n), c = portable.irradiance(x, n);
            ASSERT_TRUE(sameBits(a, c)) << "depth " << depth << " at " << x.x << " " << x.y << " " << x.z << ": " << a.x
                                        << " vs " << c.x;
        }
    }
    std::printf("[ info ] this CPU %s AVX2\n", query_detail::cpuHasAvx2() ? "runs the lookup's version for" : "has no");
}

TEST(QueryFastPaths, WideVectorsGiveTheBitsOfThePortableSh2Lookup) {
    Volume v = test::randomShVolume(6, 5, 7, 0.25, 13);
    Rng rng(14);
    fillDepthAsTheBake(v.levels[0], rng);
    for (const bool depth : {true, false}) {
        ShUniformLookup wide(v, OutsidePolicy::Clamp), portable(v, OutsidePolicy::Clamp);
        wide.setWideVectors(true);
        wide.setDepthWeights(depth);
        portable.setDepthWeights(depth);
        portable.setWideVectors(false);
        const Bounds b = wide.bounds();
        for (int t = 0; t < 20000; ++t) {
            const Vec3f x = pointAround(b, rng);
            const Vec3f n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
            const Rgb a = wide.irradiance(x, n), c = portable.irradiance(x, n);
            ASSERT_TRUE(sameBits(a, c)) << "depth " << depth << " at " << x.x << " " << x.y << " " << x.z << ": " << a.x
                                        << " vs " << c.x;
            if (!depth) {  // and the simple reference (double, trilinear, x clamped) within float rounding
                const Rgbd r = referenceLookup(v, Vec3d(x), Vec3d(n));
                ASSERT_NEAR(a.x, r.x, 1e-4 * (1 + std::fabs(r.x))) << t;
            }
        }
    }
    std::printf("[ info ] this CPU %s AVX2\n", query_detail::cpuHasAvx2() ? "runs the lookup's version for" : "has no");
}

/// Sharing the sh:4 lookup's cell gives base + direct()'s visibility times the float path's
/// lights, bit for bit, where both locate x alike (points on a 1/64 lattice; point lights, in
/// float as the shader evaluates them: within float rounding of direct()'s double); with a
/// polygon light, within the float contour's rounding of direct().
TEST(QueryFastPaths, OcclusionSharingTheBaseCellGivesBasePlusDirect) {
    const std::vector<DirectLight> points = {pointLight({0.3, 2.0, 1.4}, Rgb(8, 6, 4)), pointLight({-1.5, 0.6, 2.0}, Rgb(2, 3, 5))};
    std::vector<DirectLight> withSquare = points;
    withSquare.push_back(squareLight({0.1, 1.2, 1.8}, {0.2, -1, 0.1}, 0.5, Rgb(20, 18, 15)));
    for (const bool square : {false, true}) {
        const Volume v = defaultKindVolume(square ? withSquare : points, 21);
        const IrradianceQuery query(v);
        const auto* occlusion = dynamic_cast<const OcclusionLookup*>(&query.lookup());
        ASSERT_NE(occlusion, nullptr);
        ASSERT_TRUE(occlusion->sharesBaseCell());  // the default kind takes the shared path
        auto reference = std::make_unique<OcclusionLookup>(std::make_unique<ShFourUniformLookup>(v, OutsidePolicy::Clamp), v);
        reference->setShareBaseCell(false);
        ASSERT_FALSE(reference->sharesBaseCell());
        const ShFourUniformLookup base(v, OutsidePolicy::Clamp);
        const query_detail::FastExactLights fast(v.direct.lights);
        Rng rng(9);
        const Bounds b = query.bounds();
        double worst = 0;
        int lit = 0;
        for (int t = 0; t < 20000; ++t) {
            Vec3f x;  // 1/64 steps, a little beyond the box too (clamped alike)
            for (int a = 0; a < 3; ++a) x[a] = float(std::floor((b.lo[a] - 0.1 + (b.hi[a] - b.lo[a] + 0.2) * rng.uniform()) * 64) / 64);
            const Vec3f n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
            const Rgb shared = query.irradiance(x, n), plain = reference->irradiance(x, n);
            lit += occlusion->direct(Vec3d(x), n) != Rgb(0, 0, 0);
            if (!square) {
                const Rgb expected = baseCellExpected(base, *reference, fast, x, n);
                ASSERT_TRUE(sameBits(shared, expected)) << "at " << x.x << " " << x.y << " " << x.z << ": " << shared.x << " vs "
                                                        << expected.x;
                for (int c = 0; c < 3; ++c)  // the point lights' float formulas against direct()'s double
                    ASSERT_NEAR(shared[c], plain[c], 1e-6 * (1 + std::fabs(plain[c])));
                continue;
            }
            const Rgb d = shared - plain;
            worst = std::max(worst, double(std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)})) /
                                        std::max(1e-3, double(std::max({std::fabs(plain.x), std::fabs(plain.y), std::fabs(plain.z)}))));
        }
        EXPECT_GT(lit, 5000);  // the direct light was added, not only the SH
        // The float contour (fast_exact_lights_test.cpp): near the light's plane, where the
        // points see it edge-on, it keeps fewer digits.
        EXPECT_LE(worst, 5e-5);
        if (square) std::printf("[ info ] with a square light: largest change %.3g of the answer\n", worst);
    }
}

/// A default-kind volume (sh:4, depth moments) 15 x 5 x 15 nodes 0.25 apart below a tilted
/// square blocker and a bar narrower than a cell (its shadow is a strip that one edge per node
/// cannot hold: shadow_edges.h, kFar), lit by a sun and a point light, its visibility baked
/// with shadow edges.
Volume defaultKindUnderBlocker() {
    Scene s;
    Material grey;
    grey.albedo = {0.5f, 0.5f, 0.5f};
    const uint32_t m = addMaterial(s, grey);
    const Vec3f c[4] = {{-0.7f, 1.5f, -0.2f}, {0.3f, 1.5f, -0.8f}, {0.8f, 1.5f, 0.3f}, {-0.2f, 1.5f, 0.7f}};
    addTriangle(s, c[0], c[1], c[2], m);
    addTriangle(s, c[0], c[2], c[3], m);
    const Vec3f bar[4] = {{-1.5f, 2.2f, -1.25f}, {1.5f, 2.2f, -1.15f}, {1.5f, 2.2f, -1.07f}, {-1.5f, 2.2f, -1.17f}};
    addTriangle(s, bar[0], bar[1], bar[2], m);
    addTriangle(s, bar[0], bar[2], bar[3], m);
    s.directionalLights.push_back({Vec3f(normalize(Vec3d(0.3, -1.0, 0.2))), Rgb(3, 3, 3)});
    s.pointLights.push_back({Vec3f(0.4f, 3.0f, -0.3f), Rgb(9, 8, 7)});
    Volume out = test::randomUniformVolume(makeBasis("sh:4")->desc(), 15, 5, 15, 0.25, 33);
    out.levels[0].grid.origin = Vec3d(-1.75, 0.0, -1.75);
    Rng rng(34);
    fillDepthAsTheBake(out.levels[0], rng);
    const Tracer tracer(s);
    DirectOptions o;
    o.mode = DirectMode::Occlusion;
    o.shadowEdges = true;
    const DirectPlan plan = planDirectLight(s, tracer, out.levels[0].grid, o);
    bakeLightVisibility(s, tracer, plan, o, out);
    return out;
}

/// With shadow edges the shared cell's visibility is shadow_edge::visibility of the same
/// corners and weights: base + the float path's lights (point and directional) times
/// direct()'s visibility, bit for bit, in memory and streamed; and the edges matter (without
/// them the answers differ near the shadow's outline).
TEST(QueryFastPaths, OcclusionSharingTheBaseCellKeepsTheShadowEdges) {
    const Volume v = defaultKindUnderBlocker();
    ASSERT_FALSE(v.levels[0].lightShadowEdges.empty());
    int strips = 0;  // nodes that see the bar's shadow as a strip: their cells take the strip's lookup
    for (std::size_t p = 0; p < v.levels[0].lightShadowEdges.size(); p += shadow_edge::kFloatsPerLight)
        strips += v.levels[0].lightShadowEdges[p + shadow_edge::kFar] > 0.0f;
    EXPECT_GT(strips, 10);
    const test::TempDir dir;
    writeVolume(v, dir.file("edges.vdb"));
    const IrradianceQuery query(v);
    const IrradianceQuery streamed =
        makeStreamingQuery(std::make_shared<const StreamedVolume>(dir.file("edges.vdb")), OutsidePolicy::Clamp);
    const auto* occlusion = dynamic_cast<const OcclusionLookup*>(&query.lookup());
    ASSERT_NE(occlusion, nullptr);
    ASSERT_TRUE(occlusion->sharesBaseCell() && occlusion->shadowEdges());
    auto reference = std::make_unique<OcclusionLookup>(std::make_unique<ShFourUniformLookup>(v, OutsidePolicy::Clamp), v);
    reference->setShareBaseCell(false);
    auto trilinear = std::make_unique<OcclusionLookup>(std::make_unique<ShFourUniformLookup>(v, OutsidePolicy::Clamp), v);
    trilinear->setShadowEdges(false);
    const ShFourUniformLookup base(v, OutsidePolicy::Clamp);
    const query_detail::FastExactLights fast(v.direct.lights);
    Rng rng(13);
    const Bounds b = query.bounds();
    int edgesChanged = 0;
    for (int t = 0; t < 6000; ++t) {
        Vec3f x;  // 1/64 steps, a little beyond the box too
        for (int a = 0; a < 3; ++a) x[a] = float(std::floor((b.lo[a] - 0.1 + (b.hi[a] - b.lo[a] + 0.2) * rng.uniform()) * 64) / 64);
        const Vec3f n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
        const Rgb shared = query.irradiance(x, n), plain = reference->irradiance(x, n);
        const Rgb expected = baseCellExpected(base, *reference, fast, x, n);
        ASSERT_TRUE(sameBits(shared, expected)) << "at " << x.x << " " << x.y << " " << x.z << ": " << shared.x << " vs " << expected.x;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(shared[c], plain[c], 1e-6 * (1 + std::fabs(plain[c])));  // float lights against double
        const Rgb fromFile = streamed.irradiance(x, n);
        ASSERT_TRUE(sameBits(fromFile, expected)) << "streamed at " << x.x << " " << x.y << " " << x.z << ": " << fromFile.x << " vs "
                                                  << expected.x;
        edgesChanged += !sameBits(trilinear->irradiance(x, n), shared);  // both with the float path's lights
    }
    EXPECT_GT(edgesChanged, 100);
    std::printf("[ info ] the shadow edges changed %d of 6000 answers\n", edgesChanged);
}

/// The shared cell's edge visibility (eight corners' ramps in vector lanes) against
/// shadow_edge::visibility, bit for bit: random weights (some exactly 0), visibilities,
/// distances across the range and penumbra widths from none to kNoEdge.
TEST(QueryFastPaths, EdgeVisibilityOfEightCornersIsTheScalarOnes) {
    Rng rng(404);
    for (int t = 0; t < 200000; ++t) {
        float weight[8], vis[8], distance[8], width[8];
        for (int c = 0; c < 8; ++c) {
            weight[c] = rng.uniform() < 0.2 ? 0.0f : float(rng.uniform());
            vis[c] = float(rng.uniform());
            distance[c] = float((2 * rng.uniform() - 1) * shadow_edge::kRange);
            const double u = rng.uniform();
            width[c] = u < 0.2 ? 0.0f : (u < 0.3 ? shadow_edge::kNoEdge : float(3 * rng.uniform()));
        }
        const float fast = query_detail::edgeVisibility(weight, vis, distance, width);
        const float plain = shadow_edge::visibility(weight, vis, distance, width);
        ASSERT_EQ(std::memcmp(&fast, &plain, sizeof fast), 0) << "t " << t << ": " << fast << " vs " << plain;
    }
}

}  // namespace
}  // namespace vdblight
