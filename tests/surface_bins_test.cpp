// The surface cache built from pass 0's own paths (bake/surface_bins.h, issue 15): every path
// that goes on past its first hit gives a one-sample estimate of the irradiance of reflected
// light and sky there (DeferredPaths::firstVertexIrradiance), binned by cell and normal.
//
// In a closed white furnace (every wall emits Le inwards, albedo rho) the radiance is
// Le / (1 - rho) everywhere; the part a surface cache holds leaves out the emission of the
// wall a ray hits (NEE and MIS at the vertex take it), so its irradiance is
// pi rho Le / (1 - rho). Counting that emission too, or forgetting to divide the
// continuation by the vertex's albedo, gives pi Le / (1 - rho) or pi rho^2 Le / (1 - rho).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <vector>

#include "../libvdblight/src/bake/node_sampler.h"
#include "../libvdblight/src/bake/surface_bins.h"
#include "vdblight/bake.h"
#include "vdblight/light.h"
#include "vdblight/errors.h"
#include "vdblight/query.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"
#include "test_util.h"

using namespace vdblight;

namespace {
const Rgb kLe{1.0f, 0.5f, 0.25f};

GridSpec boxGrid() {
    GridSpec g;
    g.origin = Vec3d(-0.75, -0.75, -0.75);
    g.spacing = 0.5;
    g.nx = g.ny = g.nz = 4;
    return g;
}
}  // namespace

TEST(SurfaceBins, HoldTheFurnacesReflectedIrradiance) {
    for (const float rho : {0.5f, 0.9f}) {
        const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {rho, rho, rho});
        const Tracer tracer(box);
        const RadianceEstimator estimator(box, tracer);
        const GridSpec g = boxGrid();
        bake_detail::SurfaceBins bins(tracer, g, bake_detail::radianceScale(box, g.spacing));
        RayCount count;
        for (std::size_t n = 0; n < g.nodeCount(); ++n) {
            detail::NodeSampler sampler(estimator, Vec3f(g.node(n)), 7, uint64_t(n), 512);
            sampler.recordSurface(&bins);
            sampler.addSamples(0, 512, count);
        }
        const Rgb mean = bins.meanIrradiance();
        std::printf("  rho %.2f: %llu samples, mean irradiance (%.4f %.4f %.4f), closed form %.4f x Le\n", rho,
                    (unsigned long long)bins.samples(), mean.x, mean.y, mean.z, kPi * rho / (1 - rho));
        EXPECT_EQ(bins.samples(), uint64_t(g.nodeCount()) * 512) << "every ray hits a wall and goes on";
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], kPi * rho * kLe[c] / (1 - rho), 0.02 * kPi * rho * kLe[c] / (1 - rho));
        // Each wall's bins read the same closed form at a point of that wall.
        Rgb e;
        ASSERT_TRUE(bins.irradiance({0.1f, -0.999f, 0.2f}, {0, 1, 0}, e, count));
        EXPECT_NEAR(e.x, kPi * rho * kLe.x / (1 - rho), 0.06 * kPi * rho * kLe.x / (1 - rho));
    }
}

// A whole bake with the surface cache in the furnace: the probe pass's answer is the closed
// form (no bias from the cache), and the same bits on one and two threads (the bins' sums are
// integers, so the order in which threads add to them does not matter).
TEST(SurfaceBins, AProbePassWithThemPassesTheFurnaceWithTheSameBitsOnAnyThreads) {
    const float rho = 0.9f;
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {rho, rho, rho});
    const Tracer tracer(box);
    GatherOptions o;
    o.raysPerNode = 4096;
    o.probePasses = 1;
    o.surfaceProbeCache = true;
    const GridSpec g = boxGrid();
    o.threads = 1;
    const Volume one = bakeShGather(box, tracer, g, o);
    o.threads = 2;
    const Volume two = bakeShGather(box, tracer, g, o);
    ASSERT_EQ(one.levels[0].data.size(), two.levels[0].data.size());
    EXPECT_EQ(0, std::memcmp(one.levels[0].data.data(), two.levels[0].data.data(), one.levels[0].data.size() * sizeof(float)));
    const IrradianceQuery q(two);
    std::vector<Vec3f> nodes;
    for (std::size_t n = 0; n < g.nodeCount(); ++n) nodes.push_back(Vec3f(g.node(n)));
    // Each node within 2 % (the bins' noise: rho = 0.9 paths are long), their mean within 0.5 %.
    test::expectWhiteFurnace(nodes, [&](const Vec3f& x, const Vec3f& n) { return q.irradiance(x, n); }, kLe, rho, 0.02);
    double mean = 0;
    for (const Vec3f& x : nodes) mean += q.irradiance(x, {0, 0, 1}).x / double(nodes.size());
    const double want = kPi * kLe.x / (1 - rho);
    std::printf("  mean over %zu nodes %.4f, closed form %.4f (%+.2f %%)\n", nodes.size(), mean, want, 100 * (mean / want - 1));
    EXPECT_NEAR(mean, want, 0.005 * want);
}

// Staged (tiles.h): stage 0 carries the bins' integer sums in its stage volume, and stage 1
// reading them gives the whole bake's bits; a stage input without them is refused.
TEST(SurfaceBins, AStagedBakeCarriesThemFromStageZeroToStageOne) {
    const float rho = 0.5f;
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {rho, rho, rho});
    const Tracer tracer(box);
    GatherOptions o;
    o.raysPerNode = 64;
    o.probePasses = 1;
    o.surfaceProbeCache = true;
    const Volume whole = bakeShGather(box, tracer, boxGrid(), o);
    o.stage = 0;
    const Volume stage0 = bakeShGather(box, tracer, boxGrid(), o);
    ASSERT_TRUE(stage0.surfaceBins);
    o.stage = 1;
    o.stageInput = &stage0;
    const Volume staged = bakeShGather(box, tracer, boxGrid(), o);
    ASSERT_EQ(whole.levels[0].data.size(), staged.levels[0].data.size());
    EXPECT_EQ(0, std::memcmp(whole.levels[0].data.data(), staged.levels[0].data.data(), whole.levels[0].data.size() * 4));
    Volume noBins = stage0;
    noBins.surfaceBins.reset();
    o.stageInput = &noBins;
    EXPECT_THROW(bakeShGather(box, tracer, boxGrid(), o), ValueError);
}

// The cache refuses what it cannot do: more or fewer probe passes.
TEST(SurfaceBins, RefuseWhatTheyCannotDo) {
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(box);
    GatherOptions o;
    o.raysPerNode = 16;
    o.surfaceProbeCache = true;
    for (const int passes : {0, 2}) {
        o.probePasses = passes;
        EXPECT_THROW(bakeShGather(box, tracer, boxGrid(), o), ValueError) << passes << " probe passes";
    }
}

// A wall thinner than a cell stands in the middle of a floor cell: that cell's floor bin holds
// both sides' samples (bright on the left, dark on the right). A floor point on the dark side
// must read only the dark side's light: the mixed bin's centroid lies at the wall, which the
// point does not see, so only the next cell's bin (dark samples alone) takes part. Without the
// visibility test it would read about 4 (0.7 of the mixed bin's 5.5 and 0.3 of the dark 1).
TEST(SurfaceBins, AReadDoesNotTakeLightFromBehindAThinWall) {
    Scene s;
    Material m;
    m.name = "wall";
    m.albedo = {0.5f, 0.5f, 0.5f};
    const uint32_t wall = addMaterial(s, m);
    addTriangle(s, {0.02f, -0.5f, -1}, {0.02f, 1, -1}, {0.02f, 1, 1}, wall);
    addTriangle(s, {0.02f, -0.5f, -1}, {0.02f, 1, 1}, {0.02f, -0.5f, 1}, wall);
    const Tracer tracer(s);
    GridSpec g;
    g.origin = Vec3d(-0.3, 0.1, -0.3);  // cells [-0.1, 0.1] and [0.1, 0.3] along x
    g.spacing = 0.2;
    g.nx = g.ny = g.nz = 4;
    bake_detail::SurfaceBins bins(tracer, g, 10.0);
    const Vec3f up{0, 1, 0};
    for (int k = 0; k < 64; ++k) {
        const float z = -0.05f + 0.1f * float(k % 8) / 8.0f;
        bins.add({-0.05f, 0.001f, z}, up, {10, 10, 10});  // left of the wall, the straddled cell
        bins.add({0.06f, 0.001f, z}, up, {1, 1, 1});      // right of it, the same cell
        bins.add({0.2f, 0.001f, z}, up, {1, 1, 1});       // right, the next cell
    }
    RayCount rays;
    Rgb e;
    ASSERT_TRUE(bins.irradiance({0.06f, 0.001f, 0.0f}, up, e, rays));
    EXPECT_NEAR(e.x, 1.0f, 1e-3f) << "light from behind the wall";
    EXPECT_GT(rays.occluded, 0u);
    // On the bright side the straddled bin's centroid is seen: it takes part (mixed 5.5).
    ASSERT_TRUE(bins.irradiance({-0.05f, 0.001f, 0.0f}, up, e, rays));
    EXPECT_GT(e.x, 2.0f);
}
