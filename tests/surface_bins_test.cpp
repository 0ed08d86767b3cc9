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

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "../libvdblight/src/bake/node_sampler.h"
#include "../libvdblight/src/bake/surface_bins.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/light/light.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
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

// The bins are sparse: only cells where samples land hold bins. In the furnace box the samples
// lie on the walls, which the grid's outermost cells hold (points outside the node box go to
// the nearest cell), so every cell held is on the grid's shell and the inside holds nothing.
// Their sums survive a round trip through a stage volume's SurfaceBinSums exactly.
TEST(SurfaceBins, HoldOnlyTheCellsWhereSamplesLand) {
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(box);
    const RadianceEstimator estimator(box, tracer);
    GridSpec g;
    g.origin = Vec3d(-0.9375, -0.9375, -0.9375);
    g.spacing = 0.125;
    g.nx = g.ny = g.nz = 16;
    bake_detail::SurfaceBins bins(tracer, g, bake_detail::radianceScale(box, g.spacing));
    RayCount count;
    for (std::size_t n = 0; n < g.nodeCount(); n += 7) {
        detail::NodeSampler sampler(estimator, Vec3f(g.node(n)), 7, uint64_t(n), 64);
        sampler.recordSurface(&bins);
        sampler.addSamples(0, 64, count);
    }
    const std::array<int, 3> cells = SurfaceBinSums::cells(g);
    const SurfaceBinSums sums = bins.sums();
    ASSERT_NO_THROW(sums.validate(cells));
    const std::size_t shell = 15 * 15 * 15 - 13 * 13 * 13;
    std::printf("  %zu of %llu cells hold bins (shell %zu)\n", bins.cellsHeld(),
                (unsigned long long)SurfaceBinSums::cellCount(cells), shell);
    EXPECT_EQ(bins.cellsHeld(), sums.cellIndices.size());
    EXPECT_GT(bins.cellsHeld(), shell / 2);
    for (const uint64_t index : sums.cellIndices) {
        const std::array<int, 3> c = SurfaceBinSums::cellCoord(cells, index);
        const bool onShell = c[0] == 0 || c[1] == 0 || c[2] == 0 || c[0] == 14 || c[1] == 14 || c[2] == 14;
        EXPECT_TRUE(onShell) << "cell " << c[0] << ' ' << c[1] << ' ' << c[2] << " holds bins";
        EXPECT_EQ(SurfaceBinSums::cellIndex(cells, c[0], c[1], c[2]), index);
    }
    const bake_detail::SurfaceBins again(tracer, g, sums);
    const SurfaceBinSums back = again.sums();
    EXPECT_EQ(back.unit, sums.unit);
    EXPECT_EQ(back.cellIndices, sums.cellIndices);
    EXPECT_EQ(back.values, sums.values);
}

// The bins' inline rounding is std::llround's on what they round (0 <= x < 2^53), halves and
// the doubles next to them included.
TEST(SurfaceBins, RoundLikeLlround) {
    std::vector<double> xs = {0.0, 0.5, 1.5, 2.5, 0.49999999999999994, 0.5000000000000001, 1e12 + 0.5,
                              4503599627370495.5, 4503599627370496.0, 9007199254740991.0};
    uint64_t state = 12345;
    for (int i = 0; i < 100000; ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const double unit = double(state >> 11) * 0x1.0p-53;
        xs.push_back(unit * std::ldexp(1.0, int(state % 53)));
        xs.push_back(std::floor(xs.back()) + 0.5);
        xs.push_back(std::nextafter(xs.back(), 0.0));
    }
    for (const double x : xs)
        ASSERT_EQ(bake_detail::roundNonNegative(x), uint64_t(std::llround(x))) << std::hexfloat << x;
}

// The extra cache paths want the bins only (extra_cache_paths.h): recordSurfaceOnly skips the
// node's own light samples and sums, and the bins hold the same sums, bit for bit, for fewer
// shadow rays. The furnace's walls all emit, so every sample has a light sample to skip.
TEST(SurfaceBins, HoldTheSameSumsWhenOnlyTheyAreWanted) {
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, kLe, {0.7f, 0.7f, 0.7f});
    const Tracer tracer(box);
    const RadianceEstimator estimator(box, tracer);
    const GridSpec g = boxGrid();
    bake_detail::SurfaceBins all(tracer, g, bake_detail::radianceScale(box, g.spacing)),
        only(tracer, g, bake_detail::radianceScale(box, g.spacing));
    RayCount allRays, onlyRays;
    for (std::size_t n = 0; n < g.nodeCount(); ++n) {
        detail::NodeSampler whole(estimator, Vec3f(g.node(n)), 11, uint64_t(n), 96);
        whole.recordSurface(&all);
        whole.addSamples(0, 96, allRays);
        detail::NodeSampler surface(estimator, Vec3f(g.node(n)), 11, uint64_t(n), 96);
        surface.recordSurfaceOnly(&only);
        surface.addSamples(0, 96, onlyRays);
    }
    std::printf("  shadow rays: %llu with the node's own light samples, %llu without\n",
                (unsigned long long)allRays.occluded, (unsigned long long)onlyRays.occluded);
    EXPECT_EQ(only.sums().cellIndices, all.sums().cellIndices);
    EXPECT_EQ(only.sums().values, all.sums().values);
    EXPECT_EQ(onlyRays.intersect, allRays.intersect);
    EXPECT_EQ(onlyRays.occluded + uint64_t(g.nodeCount()) * 96, allRays.occluded);  // one light sample per sample
}

namespace {
/// Sums over cells `indices` of a grid of 4^3 cells, each value of cell c equal to c + base.
SurfaceBinSums someSums(const std::vector<uint64_t>& indices, uint64_t base, double unit = 0.5) {
    SurfaceBinSums s;
    s.unit = unit;
    s.cellIndices = indices;
    for (const uint64_t c : indices) s.values.insert(s.values.end(), SurfaceBinSums::kValuesPerCell, c + base);
    return s;
}
}  // namespace

// The merge of stage-0 tiles adds their sparse sums: the union of their cells, a cell in both
// with the sum of its values, in either order.
TEST(SurfaceBinSums, AddTheUnionOfTheirCellsExactly) {
    const SurfaceBinSums a = someSums({1, 5, 9}, 100), b = someSums({0, 5, 10, 63}, 1000);
    SurfaceBinSums ab = a, ba = b;
    ab.add(b);
    ba.add(a);
    EXPECT_EQ(ab.cellIndices, (std::vector<uint64_t>{0, 1, 5, 9, 10, 63}));
    EXPECT_EQ(ab.cellIndices, ba.cellIndices);
    EXPECT_EQ(ab.values, ba.values);
    ASSERT_NO_THROW(ab.validate({4, 4, 4}));
    const auto valueOf = [&](std::size_t listed) { return ab.values[listed * SurfaceBinSums::kValuesPerCell + 6]; };
    EXPECT_EQ(valueOf(0), 1000u);                  // cell 0: b only
    EXPECT_EQ(valueOf(1), 101u);                   // cell 1: a only
    EXPECT_EQ(valueOf(2), 105u + 1005u);           // cell 5: both
    EXPECT_EQ(valueOf(5), 1063u);                  // cell 63: b only
    SurfaceBinSums empty;
    empty.add(a);
    EXPECT_EQ(empty.values, a.values);
    EXPECT_THROW(ab.add(someSums({2}, 0, 0.25)), ValueError) << "different units";
}

TEST(SurfaceBinSums, RefuseCellsThatDoNotFitTheGrid) {
    EXPECT_NO_THROW(someSums({0, 63}, 0).validate({4, 4, 4}));
    EXPECT_THROW(someSums({0, 64}, 0).validate({4, 4, 4}), ValueError) << "outside";
    EXPECT_THROW(someSums({5, 3}, 0).validate({4, 4, 4}), ValueError) << "not ascending";
    EXPECT_THROW(someSums({5, 5}, 0).validate({4, 4, 4}), ValueError) << "twice";
    SurfaceBinSums shortValues = someSums({1, 2}, 0);
    shortValues.values.pop_back();
    EXPECT_THROW(shortValues.validate({4, 4, 4}), ValueError);
    EXPECT_THROW(someSums({1}, 0, 0.0).validate({4, 4, 4}), ValueError) << "unit";
}
