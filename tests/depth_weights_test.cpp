// Visibility-aware interpolation (issue 15, item 4): depth moments per node (bake_depth.h,
// depth_moments.h) and the lookups that weight corners by them (query.h, query_levels.h).
// Their export as textures: export_depth_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "bake/bake_bins.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "query/query_direct.h"
#include "query/query_levels.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup

#include "support/scene_generators.h"
#include "thin_wall_util.h"

namespace vdblight {
namespace {

using namespace test;  // thin_wall_util.h

GatherOptions fastGather(int threads = 0) {
    GatherOptions o;
    o.raysPerNode = 96;
    o.transport.maxBounces = 2;
    o.threads = threads;
    return o;
}

class ThinWall : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        scene_ = new Scene(thinWallScene());
        tracer_ = new Tracer(*scene_);
    }
    static void TearDownTestSuite() {
        delete tracer_;
        delete scene_;
    }
    static Scene* scene_;
    static Tracer* tracer_;
};
Scene* ThinWall::scene_ = nullptr;
Tracer* ThinWall::tracer_ = nullptr;

TEST_F(ThinWall, DarkSideGetsNoneOfTheLitSidesLightWithWeightsAndPlentyWithout) {
    Volume v = bakeShGather(*scene_, *tracer_, thinWallGrid(), fastGather());
    DepthOptions d;
    d.raysPerNode = 96;
    bakeDepthMoments(*tracer_, v, d);
    const IrradianceQuery weighted(v), plain(v, OutsidePolicy::Clamp, false);
    ASSERT_TRUE(weighted.depthWeighted());
    ASSERT_FALSE(plain.depthWeighted());
    const SideMeans w = measureSides(weighted), p = measureSides(plain);
    ASSERT_GT(w.litMean, 0.1);  // the lit side is lit
    // Exactly no light reaches x > 2. With the weights the dark side reads only its own nodes.
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean) << "dark mean " << w.darkMean;
    // The same volume, the same points, weights off: trilinear interpolation leaks through.
    EXPECT_GT(p.darkMean, 0.1 * p.litMean);
}

// `--direct occlusion` (issue 15 item 2): the point light's visibility channel is 1 at the lit
// side's nodes and 0 at the dark side's; a point just behind the wall must not get the light's
// exact irradiance times a share of the lit nodes' visibility. With depth moments the
// visibility is interpolated with the SH's weights; switched off (trilinear) it leaks.
TEST_F(ThinWall, LightVisibilityDoesNotLeakThroughTheWallWithWeights) {
    DirectOptions d;
    d.mode = DirectMode::Occlusion;
    // The visibility channels alone: the shadow edges (issue 32, on by default) keep this wall's
    // shadow out of the lit side's cells by themselves, so the trilinear case below would no
    // longer show what the weights do.
    d.shadowEdges = false;
    const GridSpec grid = thinWallGrid();
    const DirectPlan plan = planDirectLight(*scene_, *tracer_, grid, d);
    ASSERT_EQ(plan.lights.size(), 1u);
    GatherOptions o = fastGather();
    o.transport.skipAtReceiver = plan.filter;
    o.depthMoments = true;
    Volume v = bakeShGather(*scene_, *tracer_, grid, o);
    bakeLightVisibility(*scene_, *tracer_, plan, d, v);
    const IrradianceQuery weighted(v), plain(v, OutsidePolicy::Clamp, false);
    const auto* ow = dynamic_cast<const OcclusionLookup*>(&weighted.lookup());
    const auto* op = dynamic_cast<const OcclusionLookup*>(&plain.lookup());
    ASSERT_TRUE(ow && op);
    ASSERT_TRUE(ow->visibilityDepthWeighted());
    ASSERT_FALSE(op->visibilityDepthWeighted());
    // The direct part alone at points on both sides within the cells that straddle the wall.
    Rng rng(11, 5);
    double litMean = 0, darkMax = 0, darkPlain = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i) {
        const float y = 0.2f + 1.6f * rng.uniform(), z = 0.2f + 1.6f * rng.uniform();
        const Vec3f normal = uniformSphere(rng.uniform(), rng.uniform());
        const double xl = 1.8 + (kWallLo - 1.8) * rng.uniform(), xd = kWallHi + 1e-3 + (2.2 - kWallHi - 1e-3) * rng.uniform();
        litMean += luminance(ow->direct(Vec3d(xl, y, z), normal)) / n;
        darkMax = std::max(darkMax, double(luminance(ow->direct(Vec3d(xd, y, z), normal))));
        darkPlain += luminance(op->direct(Vec3d(xd, y, z), normal)) / n;
    }
    ASSERT_GT(litMean, 0.1);
    EXPECT_LT(darkMax, 1e-3 * litMean);
    EXPECT_GT(darkPlain, 0.1 * litMean);  // the same volume and points, trilinear visibility
    // The whole answer (indirect + direct) on the dark side is dark too, and the SH part's
    // weights alone (visibility trilinear) do not make it so.
    const SideMeans w = measureSides(weighted);
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean);
    // Switching the visibility's weights off alone.
    auto lookup = std::make_unique<OcclusionLookup>(std::make_unique<ShUniformLookup>(v, OutsidePolicy::Clamp), v);
    lookup->setVisibilityDepthWeights(false);
    ASSERT_TRUE(lookup->depthWeighted());
    const IrradianceQuery mixed(std::move(lookup), "sh2-uniform");
    EXPECT_GT(measureSides(mixed).darkMean, 0.02 * w.litMean);  // 3.8 % measured
}

TEST_F(ThinWall, BilevelVolumeDoesNotLeakWithWeights) {
    LevelsPlacement placement;
    placement.kind = LayoutKind::Bilevel;
    placement.refine = 2;  // finest spacing 0.2, still wider than the 0.08 wall
    // Level 0 from x = 0.3: the finest nodes next to the wall are at 1.9 (lit) and 2.1 (dark),
    // none inside the wall (an in-wall node is black and would hide the leak by itself).
    const LevelLayout layout = placeLevels(thinWallGrid(0.3), scene_->positions, scene_->indices, placement, 256);
    GatherOptions o = fastGather();
    o.depthMoments = true;  // from the gather's own rays
    Volume v = bakeShGatherLevels(*scene_, *tracer_, layout, o);
    ASSERT_GT(v.levels.size(), 1u);
    const IrradianceQuery weighted(v), plain(v, OutsidePolicy::Clamp, false);
    ASSERT_STREQ(weighted.kind(), "sh2-levels");
    const SideMeans w = measureSides(weighted, 1.9, 2.1), p = measureSides(plain, 1.9, 2.1);
    ASSERT_GT(w.litMean, 0.1);
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean) << "dark mean " << w.darkMean;
    EXPECT_GT(p.darkMean, 0.05 * p.litMean);
}

TEST_F(ThinWall, BinsVolumeDoesNotLeakWithWeights) {
    BinsBakeOptions o;
    o.basis.kind = bins::BasisSpec::Kind::Bins;
    o.basis.resolution = 4;
    o.samplesPerBin = 3;
    o.transport.maxBounces = 2;
    Volume v = bakeBins(*scene_, *tracer_, uniformLayout(thinWallGrid()), o);
    bakeDepthMoments(*tracer_, v, DepthOptions());
    const IrradianceQuery weighted(v), plain(v, OutsidePolicy::Clamp, false);
    ASSERT_STREQ(weighted.kind(), "bins");
    ASSERT_TRUE(weighted.depthWeighted());
    const SideMeans w = measureSides(weighted), p = measureSides(plain);
    ASSERT_GT(w.litMean, 0.1);
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean) << "dark mean " << w.darkMean;
    EXPECT_GT(p.darkMean, 0.1 * p.litMean);
}

TEST_F(ThinWall, DepthMomentsOfANodeFacingTheWall) {
    // The node at (1.8, 1.0, 1.0) sees the wall 0.16 away along +x: every +x ray has axial
    // depth 0.16 / 0.4 = 0.4 cells, so the mean is 0.4 (to 1/255) and sigma 0.
    Volume v = bakeShGather(*scene_, *tracer_, thinWallGrid(), fastGather());
    bakeDepthMoments(*tracer_, v, DepthOptions());
    const std::size_t node = thinWallGrid().index(4, 2, 2);
    const float* d = v.levels[0].nodeDepth(node);
    EXPECT_NEAR(d[depth::kMeanPositive * 3 + 0], 0.4f, 0.5f / 255);
    EXPECT_EQ(d[depth::kSigmaPositive * 3 + 0], 0.0f);
    // -x: the room wall at x = 0 is 4.5 cells away: clamped to one cell, free.
    EXPECT_EQ(d[depth::kMeanNegative * 3 + 0], 1.0f);
    // A dark-side point behind the wall is hidden from it; a lit point in front is not.
    EXPECT_LT(depth::visibility(d, 0.7f, 0.1f, -0.2f), 1e-4f);
    EXPECT_EQ(depth::visibility(d, 0.3f, 0.1f, -0.2f), 1.0f);
}

TEST_F(ThinWall, DepthMomentsHaveTheSameBitsOnOneAndTwoThreads) {
    Volume a = bakeShGather(*scene_, *tracer_, thinWallGrid(), fastGather(1));
    Volume b = a;
    DepthOptions d;
    d.threads = 1;
    bakeDepthMoments(*tracer_, a, d);
    d.threads = 2;
    bakeDepthMoments(*tracer_, b, d);
    ASSERT_EQ(a.levels[0].depth.size(), b.levels[0].depth.size());
    EXPECT_EQ(0, std::memcmp(a.levels[0].depth.data(), b.levels[0].depth.data(), a.levels[0].depth.size() * sizeof(float)));
    // and another seed gives other rays (the test above would pass for a constant)
    d.seed = 2;
    Volume c = a;
    bakeDepthMoments(*tracer_, c, d);
    EXPECT_NE(0, std::memcmp(a.levels[0].depth.data(), c.levels[0].depth.data(), a.levels[0].depth.size() * sizeof(float)));
}

TEST_F(ThinWall, TheGatherRecordsTheSameDepthAsTheSeparatePassWithoutExtraRays) {
    // Uniform: the gather's hook against bakeDepthMoments on the same rays; and the SH values
    // are untouched by the hook (same bits with and without it).
    GatherOptions o = fastGather();
    BakeStats plainStats, hookStats;
    const Volume plain = bakeShGather(*scene_, *tracer_, thinWallGrid(), o, nullptr, &plainStats);
    o.depthMoments = true;
    const Volume hooked = bakeShGather(*scene_, *tracer_, thinWallGrid(), o, nullptr, &hookStats);
    EXPECT_EQ(plain.levels[0].data, hooked.levels[0].data);
    EXPECT_EQ(plainStats.rays.total(), hookStats.rays.total());
    Volume separate = plain;
    DepthOptions d;
    d.raysPerNode = o.raysPerNode;
    bakeDepthMoments(*tracer_, separate, d);
    EXPECT_EQ(hooked.levels[0].depth, separate.levels[0].depth);
    // One-ray-at-a-time reference path: the same depth.
    o.transport.packetRays = false;
    const Volume single = bakeShGather(*scene_, *tracer_, thinWallGrid(), o);
    EXPECT_EQ(single.levels[0].depth, hooked.levels[0].depth);

    // Levels, seam nodes included (they take the coarser level's radiance, their own depth).
    LevelsPlacement placement;
    placement.kind = LayoutKind::Bilevel;
    placement.refine = 2;
    const LevelLayout layout = placeLevels(thinWallGrid(), scene_->positions, scene_->indices, placement, 256);
    o = fastGather();
    o.depthMoments = true;
    const Volume levels = bakeShGatherLevels(*scene_, *tracer_, layout, o);
    Volume levelsSeparate = levels;
    bakeDepthMoments(*tracer_, levelsSeparate, d);
    ASSERT_TRUE(levels.hasDepth());
    for (std::size_t l = 0; l < levels.levels.size(); ++l)
        EXPECT_EQ(levels.levels[l].depth, levelsSeparate.levels[l].depth) << "level " << l;
}

TEST_F(ThinWall, DepthMomentsSurviveTheVdbFile) {
    LevelsPlacement placement;
    placement.kind = LayoutKind::Bilevel;
    placement.refine = 2;
    const LevelLayout layout = placeLevels(thinWallGrid(), scene_->positions, scene_->indices, placement, 256);
    Volume v = bakeShGatherLevels(*scene_, *tracer_, layout, fastGather());
    bakeDepthMoments(*tracer_, v, DepthOptions());
    test::TempDir dir;
    const std::string path = dir.file("depth.vdb");
    writeVolume(v, path);
    const Volume r = readVolume(path);
    ASSERT_TRUE(r.hasDepth());
    for (std::size_t l = 0; l < v.levels.size(); ++l) EXPECT_EQ(v.levels[l].depth, r.levels[l].depth) << "level " << l;
    bool found = false;
    for (const GridInfo& g : inspectVolumeFile(path).grids)
        if (g.name == "depth_mean_pos" && g.valueType == "vec3s") found = true;
    EXPECT_TRUE(found);
    // Half floats hold k/255 to 2^-11 relative: the lookup sees the same weights within that.
    WriteOptions half;
    half.halfFloat = true;
    writeVolume(v, path, half);
    const Volume h = readVolume(path);
    for (std::size_t i = 0; i < v.levels[0].depth.size(); ++i)
        ASSERT_NEAR(h.levels[0].depth[i], v.levels[0].depth[i], 1e-3f);
}

// The fast lookups against the simple reference, on random volumes with random depth
// moments (so every branch of the Chebyshev test is taken) and at random points.
void expectMatchesReference(const Volume& v, int points, uint64_t seed) {
    const IrradianceQuery q(v);
    ASSERT_TRUE(q.depthWeighted());
    Rng rng(seed, 9);
    const Bounds b = q.bounds();
    int hidden = 0;
    for (int i = 0; i < points; ++i) {
        const Vec3d x = b.lo + Vec3d(double(rng.uniform()) * (b.hi.x - b.lo.x), double(rng.uniform()) * (b.hi.y - b.lo.y),
                                     double(rng.uniform()) * (b.hi.z - b.lo.z));
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgbd want = referenceDepthWeightedLookup(v, x, Vec3d(n));
        const Rgb got = q.irradiance(Vec3f(x), n);
        const Rgbd plain = referenceLookup(v, x, Vec3d(n));
        if (std::fabs(plain.x - want.x) > 1e-2) ++hidden;
        ASSERT_NEAR(got.x, want.x, 2e-4 * (1 + std::fabs(want.x))) << "point " << i;
        ASSERT_NEAR(got.y, want.y, 2e-4 * (1 + std::fabs(want.y)));
        ASSERT_NEAR(got.z, want.z, 2e-4 * (1 + std::fabs(want.z)));
    }
    EXPECT_GT(hidden, points / 10);  // the weights changed many answers
}

TEST(DepthWeightedLookup, UniformMatchesTheReference) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels.resize(1);
    v.levels[0].grid = GridSpec{Vec3d(-1, 0.5, 2), 0.3, 6, 5, 7};
    v.levels[0].data.resize(v.levels[0].grid.nodeCount() * 27);
    randomData(v, 1);
    randomDepth(v, 2);
    expectMatchesReference(v, 2000, 3);
}

TEST_F(ThinWall, LevelsMatchTheReference) {
    const Volume v = randomAdaptiveVolume(*scene_, 4, 5);
    ASSERT_EQ(v.levels.size(), 3u);
    expectMatchesReference(v, 2000, 6);
}

// A leaf cell of a coarser level was not refined, so it holds no geometry: every corner sees
// every point of it, and the weights must leave it plain trilinear whatever its corners' depth
// says (measured over pyramids reaching into neighbouring cells). In cells of the finest level
// they still apply. The fast and the streaming lookups and the reference agree.
TEST_F(ThinWall, CoarseLeafCellsAreInterpolatedWithoutWeights) {
    const Volume v = randomAdaptiveVolume(*scene_, 14, 15);
    const ShLevelsLookup lookup(v, OutsidePolicy::Clamp);
    const IrradianceQuery weighted(v), plain(v, OutsidePolicy::Clamp, false);
    ASSERT_TRUE(weighted.depthWeighted());
    Rng rng(16, 1);
    const Bounds b = weighted.bounds();
    int coarse = 0, fineChanged = 0;
    for (int i = 0; i < 4000; ++i) {
        const Vec3f x(float(b.lo.x + rng.uniform() * (b.hi.x - b.lo.x)), float(b.lo.y + rng.uniform() * (b.hi.y - b.lo.y)),
                      float(b.lo.z + rng.uniform() * (b.hi.z - b.lo.z)));
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb w = weighted.irradiance(x, n), p = plain.irradiance(x, n);
        if (lookup.levelAt(x) + 1 < int(v.levels.size())) {
            ++coarse;
            ASSERT_EQ(w.x, p.x) << "point " << i << " in a cell of level " << lookup.levelAt(x);
            ASSERT_EQ(w.z, p.z);
        } else if (std::fabs(w.x - p.x) > 1e-3f * (1 + std::fabs(p.x))) {
            ++fineChanged;
        }
    }
    EXPECT_GT(coarse, 400);
    EXPECT_GT(fineChanged, 400);
}

TEST(DepthWeightedLookup, FreeNodesGiveTheTrilinearAnswer) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels.resize(1);
    v.levels[0].grid = GridSpec{Vec3d(0, 0, 0), 1.0, 3, 3, 3};
    v.levels[0].data.resize(27 * 27);
    randomData(v, 8);
    v.levels[0].depth.assign(27 * depth::kFloatsPerNode, 0.0f);
    for (std::size_t i = 0; i < v.levels[0].depth.size(); ++i)
        if (i % depth::kFloatsPerNode < 6) v.levels[0].depth[i] = 1.0f;  // every face free for a whole cell
    const IrradianceQuery q(v);
    Rng rng(3, 3);
    for (int i = 0; i < 200; ++i) {
        const Vec3d x(2 * double(rng.uniform()), 2 * double(rng.uniform()), 2 * double(rng.uniform()));
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgbd want = referenceLookup(v, x, Vec3d(n));
        ASSERT_NEAR(q.irradiance(Vec3f(x), n).x, want.x, 1e-4 * (1 + std::fabs(want.x)));
    }
}

TEST(DepthWeightedLookup, InvalidDepthIsRefused) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels.resize(1);
    v.levels[0].grid = GridSpec{Vec3d(0, 0, 0), 1.0, 2, 2, 2};
    v.levels[0].data.resize(8 * 27);
    v.levels[0].depth.assign(7 * depth::kFloatsPerNode, 0.5f);  // one node short
    EXPECT_THROW(v.validate(), FormatError);
    v.levels[0].depth.assign(8 * depth::kFloatsPerNode, 0.5f);
    v.levels[0].depth[3] = 1.5f;  // outside [0, 1]
    EXPECT_THROW(v.validate(), FormatError);
    v.levels[0].depth[3] = 0.5f;
    EXPECT_NO_THROW(v.validate());
}

}  // namespace
}  // namespace vdblight
