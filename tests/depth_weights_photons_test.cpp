// Visibility-aware interpolation of irradiance-vector volumes (issue 15, items 4 and 5):
// `bake --method photons --depth-moments` stores the nodes' depth moments (bake_depth.h) and
// VectorGridLookup weights its trilinear corners by them, as the SH lookups do.
#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/depth_moments.h"
#include "basis/irradiance_vectors_compact.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "volume/volume_compact.h"

#include "thin_wall_util.h"

namespace vdblight {
namespace {

using namespace test;  // thin_wall_util.h

class PhotonThinWall : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        scene_ = new Scene(thinWallScene());
        tracer_ = new Tracer(*scene_);
        PhotonOptions o;
        o.photons = 200'000;
        o.transport.maxBounces = 2;
        volume_ = new Volume(bakePhotons(*scene_, *tracer_, thinWallGrid(), o));
        DepthOptions d;
        d.raysPerNode = 96;
        bakeDepthMoments(*tracer_, *volume_, d);
    }
    static void TearDownTestSuite() {
        delete volume_;
        delete tracer_;
        delete scene_;
    }
    static Scene* scene_;
    static Tracer* tracer_;
    static Volume* volume_;
};
Scene* PhotonThinWall::scene_ = nullptr;
Tracer* PhotonThinWall::tracer_ = nullptr;
Volume* PhotonThinWall::volume_ = nullptr;

// No photon crosses the doorless wall, so the dark side's nodes hold exactly nothing; a point
// between the wall and them must read only them.
TEST_F(PhotonThinWall, DarkSideGetsNoneOfTheLitSidesLightWithWeightsAndPlentyWithout) {
    ASSERT_TRUE(volume_->hasDepth());
    const IrradianceQuery weighted(*volume_), plain(*volume_, OutsidePolicy::Clamp, false);
    ASSERT_STREQ(weighted.kind(), "irradiance-vectors-uniform");
    ASSERT_TRUE(weighted.depthWeighted());
    ASSERT_FALSE(plain.depthWeighted());
    const SideMeans w = measureSides(weighted), p = measureSides(plain);
    ASSERT_GT(w.litMean, 0.1);
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean) << "dark mean " << w.darkMean;
    EXPECT_GT(p.darkMean, 0.1 * p.litMean);  // the same volume and points, weights off: it leaks
}

TEST_F(PhotonThinWall, TheCompactFormKeepsTheDepthAndDoesNotLeak) {
    const Volume compact = iv::compact(*volume_);
    ASSERT_EQ(compact.levels[0].depth, volume_->levels[0].depth);
    const IrradianceQuery weighted(compact);
    ASSERT_TRUE(weighted.depthWeighted());
    const SideMeans w = measureSides(weighted);
    ASSERT_GT(w.litMean, 0.1);
    EXPECT_LT(w.darkMax, 1e-3 * w.litMean) << "dark mean " << w.darkMean;
}

TEST_F(PhotonThinWall, DepthSurvivesTheVdbFile) {
    test::TempDir dir;
    const std::string path = dir.file("photons.vdb");
    writeVolume(*volume_, path);
    const Volume back = readVolume(path);
    ASSERT_EQ(back.levels[0].depth.size(), volume_->levels[0].depth.size());
    for (std::size_t i = 0; i < back.levels[0].depth.size(); ++i)
        ASSERT_EQ(back.levels[0].depth[i], volume_->levels[0].depth[i]) << i;
    EXPECT_TRUE(IrradianceQuery(back).depthWeighted());
}

// Tricubic interpolation has no visibility test: it says so rather than pretend.
TEST_F(PhotonThinWall, TricubicInterpolationIsNotDepthWeighted) {
    VectorGridLookup cubic(*volume_, OutsidePolicy::Clamp, Interpolation::Tricubic);
    cubic.setDepthWeights(true);
    EXPECT_FALSE(cubic.depthWeighted());
}

// The fast lookup and its export hook against the simple reference, on a random volume with
// random depth moments (every branch of the Chebyshev test is taken) at random points.
TEST(VectorGridDepthLookup, MatchesTheReference) {
    Volume v;
    v.basis = iv::basis();
    v.levels.resize(1);
    v.levels[0].grid = GridSpec{Vec3d(-1, 0.5, 2), 0.3, 5, 4, 6};
    const std::size_t nodes = v.levels[0].grid.nodeCount();
    v.levels[0].data.resize(nodes * iv::kFloatsPerNode);
    randomData(v, 21);  // random_volumes.h
    randomDepth(v, 22);
    Rng rng(23, 1);
    const VectorGridLookup lookup(v, OutsidePolicy::Clamp);
    ASSERT_TRUE(lookup.depthWeighted());
    const Bounds b = lookup.bounds();
    int changed = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3d x = b.lo + Vec3d(double(rng.uniform()) * (b.hi.x - b.lo.x), double(rng.uniform()) * (b.hi.y - b.lo.y),
                                     double(rng.uniform()) * (b.hi.z - b.lo.z));
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgbd want = referenceVectorLookup(v, x, Vec3d(n));
        const Rgbd plain = referenceVectorLookup(v, x, Vec3d(n), iv::kDefaultBlend, false);
        if (std::fabs(plain.x - want.x) > 1e-2 * (1 + std::fabs(want.x))) ++changed;
        const Rgb got = lookup.irradiance(Vec3f(x), n);
        ASSERT_NEAR(got.x, want.x, 2e-4 * (1 + std::fabs(want.x))) << "point " << i;
        ASSERT_NEAR(got.y, want.y, 2e-4 * (1 + std::fabs(want.y)));
        ASSERT_NEAR(got.z, want.z, 2e-4 * (1 + std::fabs(want.z)));
        float vectors[iv::kFloatsPerNode];
        lookup.irradianceVectors(x, vectors);
        double exact[iv::kFloatsPerNode];
        for (int f = 0; f < iv::kFloatsPerNode; ++f) exact[f] = vectors[f];
        const Rgbd hook = iv::referenceIrradiance(exact, normalize(Vec3d(n)), iv::kDefaultBlend);
        ASSERT_NEAR(hook.x, want.x, 2e-4 * (1 + std::fabs(want.x))) << "export hook, point " << i;
    }
    EXPECT_GT(changed, 200);  // the weights changed many answers
}

}  // namespace
}  // namespace vdblight
