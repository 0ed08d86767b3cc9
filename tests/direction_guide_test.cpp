// Guided probe directions (bake/direction_guide.h, GatherOptions::guideProbeDirections; issue
// 32, the preview): the guide draws each cell as often as its density says and weights it
// back, so the guided probe pass estimates what the uniform one does; the bake stays the same
// bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <variant>
#include <vector>

#include "bake/direction_guide.h"
#include "error_split_fixtures.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

#include "support/leak_scenes.h"

namespace vdblight {
namespace {

using bake_detail::DirectionGuide;
constexpr int kCells = DirectionGuide::kCells;

/// A node's map: luminance 1 per cell, `bright` in cell 37, one sample each.
std::vector<float> densityWithOneBrightCell(float bright, float share) {
    std::vector<float> sums(kCells, 1.0f), density(kCells);
    std::vector<uint32_t> counts(kCells, 1);
    sums[37] = bright;
    DirectionGuide::build(sums.data(), counts.data(), share, density.data());
    return density;
}

TEST(DirectionGuide, BuildNormalisesToMeanOneOverAUniformFloor) {
    const std::vector<float> d = densityWithOneBrightCell(128.0f, 0.5f);
    double sum = 0;
    for (float x : d) sum += x;
    EXPECT_NEAR(sum / kCells, 1.0, 1e-5);
    // Mean luminance (127 + 128) / 128: a dim cell's share is 0.5 + 0.5 * 128 / 255.
    EXPECT_NEAR(d[0], 0.5 + 0.5 * 128.0 / 255.0, 1e-5);
    EXPECT_NEAR(d[37], 0.5 + 0.5 * 128.0 * 128.0 / 255.0, 1e-3);

    // A dark node, and a map with unsampled cells (they take the node's mean, not darkness).
    std::vector<float> sums(kCells, 0.0f), density(kCells);
    std::vector<uint32_t> counts(kCells, 1);
    DirectionGuide::build(sums.data(), counts.data(), 0.5f, density.data());
    for (float x : density) EXPECT_EQ(x, 1.0f);
    sums.assign(kCells, 2.0f);
    counts.assign(kCells, 1);
    counts[5] = 0;
    sums[5] = 0;
    DirectionGuide::build(sums.data(), counts.data(), 0.5f, density.data());
    for (float x : density) EXPECT_NEAR(x, 1.0f, 1e-6);
}

TEST(DirectionGuide, DrawsEachCellAsOftenAsItsDensitySays) {
    const std::vector<float> d = densityWithOneBrightCell(64.0f, 0.5f);
    const DirectionGuide guide(d.data());
    constexpr uint32_t kPoints = 1u << 15;
    std::vector<uint32_t> hits(kCells, 0);
    int densityMismatches = 0;
    double fractionU = 0, fractionV = 0;  // where in its cell each point lands
    for (uint32_t i = 0; i < kPoints; ++i) {
        float u, v;
        sobol02(i, 99, u, v);
        const float density = guide.warp(u, v);
        ASSERT_TRUE(u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f) << u << " " << v;
        const int cell = DirectionGuide::cellOf(u, v);
        ++hits[cell];
        fractionU += u * DirectionGuide::kRows - std::floor(u * DirectionGuide::kRows);
        fractionV += v * DirectionGuide::kCols - std::floor(v * DirectionGuide::kCols);
        EXPECT_NEAR(density, d[cell], 1e-5 * d[cell]);
        // The pdf the emitters' MIS weights read at a direction is the one it was drawn with
        // (a direction on a cell border may round into its neighbour).
        if (guide.density(uniformSphere(u, v)) != d[cell]) ++densityMismatches;
    }
    for (int c = 0; c < kCells; ++c)
        EXPECT_NEAR(double(hits[c]) / kPoints, d[c] / kCells, 0.002) << "cell " << c;
    EXPECT_LT(densityMismatches, int(kPoints / 1000));
    // Uniform within each cell, as the density is constant there.
    EXPECT_NEAR(fractionU / kPoints, 0.5, 0.01);
    EXPECT_NEAR(fractionV / kPoints, 0.5, 0.01);
}

/// The mean of the DC coefficients (luminance-free: red) over the nodes behind the wall
/// (x > 2.2) of a bake of the thin-wall scene: lit only through the door.
double meanBehindTheWall(const Volume& v) {
    const VolumeLevel& l = v.levels[0];
    double sum = 0;
    int n = 0;
    for (int k = 0; k < l.grid.nz; ++k)
        for (int j = 0; j < l.grid.ny; ++j)
            for (int i = 0; i < l.grid.nx; ++i) {
                if (l.grid.node(i, j, k).x < 2.2) continue;
                sum += l.data[l.grid.index(i, j, k) * 27];
                ++n;
            }
    return sum / n;
}

struct ThinWallBake {
    LeakScene room = makeThinWallScene();
    Tracer tracer{room.scene};
    GridSpec grid() const { return test::thinWallNodes(); }
    GatherOptions options(bool guided, uint64_t seed, uint32_t rays, int threads = 2) const {
        GatherOptions o;
        o.raysPerNode = rays;
        o.seed = seed;
        o.threads = threads;
        o.probePasses = 1;
        o.surfaceProbeCache = true;
        o.depthMoments = true;
        o.guideProbeDirections = guided;
        return o;
    }
    Volume bake(const GatherOptions& o) const { return bakeShGather(room.scene, tracer, grid(), o); }
    Volume bake(bool guided, uint64_t seed, uint32_t rays, int threads = 2) const {
        return bake(options(guided, seed, rays, threads));
    }
};

TEST(GuidedProbePass, EstimatesWhatTheUniformOneDoesBehindTheDoor) {
    // Two seeds each: the means of the nodes lit only through the door agree (seed to seed
    // they differ by about 1 %; an estimator weighted wrongly, e.g. without 1 / density, is off
    // by far more).
    const ThinWallBake b;
    double uniform[2], guided[2];
    for (int s = 0; s < 2; ++s) {
        uniform[s] = meanBehindTheWall(b.bake(false, 11 + s, 64));
        guided[s] = meanBehindTheWall(b.bake(true, 11 + s, 64));
    }
    double mu = 0, mg = 0;
    for (int s = 0; s < 2; ++s) {
        mu += uniform[s] / 2;
        mg += guided[s] / 2;
    }
    ASSERT_GT(mu, 0.0);
    EXPECT_NEAR(mg / mu, 1.0, 0.03) << "uniform " << mu << ", guided " << mg;
    EXPECT_NE(std::get<std::string>(b.bake(true, 11, 64).meta.at("probe_directions")).find("guided"), std::string::npos);
}

TEST(GuidedProbePass, SameBitsForAnyThreadCount) {
    const ThinWallBake b;
    const Volume one = b.bake(true, 5, 32, 1), two = b.bake(true, 5, 32, 2);
    ASSERT_EQ(one.levels[0].data.size(), two.levels[0].data.size());
    EXPECT_EQ(std::memcmp(one.levels[0].data.data(), two.levels[0].data.data(), one.levels[0].data.size() * sizeof(float)), 0);
}

TEST(GuidedProbePass, RaysOneByOneGiveThePacketsBits) {
    // The reference sampling (addSamplesOneByOne) and the packets warp, weight and record alike
    // (both with the nodes' cache: the surface cache takes packeted samples only).
    const ThinWallBake b;
    GatherOptions o = b.options(true, 7, 32);
    o.surfaceProbeCache = false;
    const Volume packets = b.bake(o);
    o.transport.packetRays = false;
    const Volume single = b.bake(o);
    ASSERT_EQ(packets.levels[0].data.size(), single.levels[0].data.size());
    EXPECT_EQ(std::memcmp(packets.levels[0].data.data(), single.levels[0].data.data(),
                          packets.levels[0].data.size() * sizeof(float)), 0);
}

TEST(GuidedProbePass, RefusedInAStagedBakeWithTwoProbePasses) {
    // Stage 1 reads pass 0's map from stage 0 (stage_carry.h); a later pass has no map of its own.
    const ThinWallBake b;
    GatherOptions o;
    o.raysPerNode = 8;
    o.probePasses = 2;
    o.guideProbeDirections = true;
    o.stage = 0;
    EXPECT_THROW(bakeShGather(b.room.scene, b.tracer, b.grid(), o), ValueError);
}

}  // namespace
}  // namespace vdblight
