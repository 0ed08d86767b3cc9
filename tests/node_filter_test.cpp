// The filter across nodes (node_filter.h, issue 32): what it keeps, what it removes and what
// stops it. Pure data on small grids: no bake.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "volume/node_filter.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

constexpr int kN = 6;  // nodes per axis
constexpr int kFloats = 27;

/// An SH order-2 volume on kN^3 nodes whose every value at node (i, j, k) is f(i, j, k);
/// with `depth`, every face free (mean 1 cell, sigma 0).
Volume volumeOf(double (*f)(int, int, int), bool depth) {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.spacing = 1.0;
    level.grid.nx = level.grid.ny = level.grid.nz = kN;
    level.data.resize(level.grid.nodeCount() * kFloats);
    for (int k = 0; k < kN; ++k)
        for (int j = 0; j < kN; ++j)
            for (int i = 0; i < kN; ++i)
                for (int c = 0; c < kFloats; ++c) level.data[level.grid.index(i, j, k) * kFloats + c] = float(f(i, j, k));
    if (depth) {
        level.depth.assign(level.grid.nodeCount() * depth::kFloatsPerNode, 0.0f);
        for (std::size_t n = 0; n < level.grid.nodeCount(); ++n)
            for (int a = 0; a < 3; ++a) {
                level.depth[n * depth::kFloatsPerNode + depth::kMeanPositive * 3 + a] = 1.0f;
                level.depth[n * depth::kFloatsPerNode + depth::kMeanNegative * 3 + a] = 1.0f;
            }
    }
    v.levels.push_back(std::move(level));
    return v;
}

float at(const Volume& v, int i, int j, int k) { return v.levels[0].data[v.levels[0].grid.index(i, j, k) * kFloats]; }

double linear(int i, int j, int k) { return 1.0 + 0.5 * i - 0.25 * j + 0.125 * k; }
double step(int i, int, int) { return i <= 2 ? 0.0 : 1.0; }

TEST(NodeFilter, KeepsALinearFieldInTheInterior) {
    Volume v = volumeOf(&linear, true);
    filterNodes(v, 2);
    for (int k = 2; k < kN - 2; ++k)
        for (int j = 2; j < kN - 2; ++j)
            for (int i = 2; i < kN - 2; ++i) EXPECT_NEAR(at(v, i, j, k), linear(i, j, k), 1e-5) << i << " " << j << " " << k;
}

TEST(NodeFilter, DoesNotCrossAWallTheDepthMomentsSee) {
    // A wall halfway between nodes x = 2 and x = 3: their faces towards it see it at half a cell.
    Volume v = volumeOf(&step, true);
    VolumeLevel& l = v.levels[0];
    for (int k = 0; k < kN; ++k)
        for (int j = 0; j < kN; ++j) {
            l.depth[l.grid.index(2, j, k) * depth::kFloatsPerNode + depth::kMeanPositive * 3 + 0] = 0.5f;
            l.depth[l.grid.index(3, j, k) * depth::kFloatsPerNode + depth::kMeanNegative * 3 + 0] = 0.5f;
        }
    Volume plain = volumeOf(&step, false);
    filterNodes(v, 1);
    filterNodes(plain, 1);
    for (int j = 0; j < kN; ++j) {
        EXPECT_NEAR(at(v, 2, j, 3), 0.0, 1e-6);
        EXPECT_NEAR(at(v, 3, j, 3), 1.0, 1e-6);
    }
    EXPECT_NEAR(at(plain, 2, 3, 3), 0.25, 1e-6);  // without depth moments the step blurs
}

TEST(NodeFilter, RemovesMostOfIndependentNoise) {
    static Rng* rng = nullptr;
    Rng r(7, 0);
    rng = &r;
    Volume v = volumeOf([](int, int, int) { return double(rng->uniform()) - 0.5; }, true);
    auto interiorVariance = [](const Volume& x) {
        double s = 0;
        int count = 0;
        for (int k = 1; k < kN - 1; ++k)
            for (int j = 1; j < kN - 1; ++j)
                for (int i = 1; i < kN - 1; ++i, ++count) s += double(at(x, i, j, k)) * at(x, i, j, k);
        return s / count;
    };
    const double before = interiorVariance(v);
    filterNodes(v, 1);
    // A binomial 3x3x3 kernel leaves (3/8)^3 = 0.053 of the variance of independent values.
    EXPECT_LT(interiorVariance(v), 0.12 * before);
}

TEST(NodeFilter, WithErrorEstimatesKeepsAStepTheNoiseDoesNotExplain) {
    Volume v = volumeOf(&step, false), plain = volumeOf(&step, false);
    const std::vector<float> error(v.levels[0].grid.nodeCount(), 0.01f);  // 1 % noise: the step is 100 x that
    filterNodes(v, 1, &error);
    filterNodes(plain, 1);
    EXPECT_NEAR(at(v, 2, 3, 3), 0.0, 1e-6);
    EXPECT_NEAR(at(v, 3, 3, 3), 1.0, 1e-6);
    EXPECT_GT(std::fabs(at(plain, 3, 3, 3) - 1.0), 0.2);
}

// Rows of nodes are filtered in parallel; each node's sum is its own, so one thread and two
// give the same bits (with depth moments and error estimates, every weight in play).
TEST(NodeFilter, GivesTheSameBitsOnOneThreadAndOnTwo) {
    const auto bumpy = [](int i, int j, int k) { return std::sin(1.7 * i) + 0.3 * j * j - std::cos(0.9 * k * i); };
    Volume one = volumeOf(bumpy, true);
    std::vector<float> error(one.levels[0].grid.nodeCount());
    for (std::size_t n = 0; n < error.size(); ++n) error[n] = 0.05f + 0.01f * float(n % 7);
    Volume two = one;
    filterNodes(one, 2, &error, 1);
    filterNodes(two, 2, &error, 2);
    ASSERT_EQ(one.levels[0].data.size(), two.levels[0].data.size());
    EXPECT_EQ(std::memcmp(one.levels[0].data.data(), two.levels[0].data.data(), one.levels[0].data.size() * sizeof(float)), 0);
}

TEST(NodeFilter, RefusesWhatItCannotFilter) {
    Volume v = volumeOf(&linear, false);
    EXPECT_THROW(filterNodes(v, -1), ValueError);
    const std::vector<float> wrong(3, 0.01f);
    EXPECT_THROW(filterNodes(v, 1, &wrong), ValueError);
    v.levels[0].windowNodes = 10;  // a tile's window
    EXPECT_THROW(filterNodes(v, 1), ValueError);
    Volume none = volumeOf(&linear, false);
    filterNodes(none, 0);
    EXPECT_EQ(at(none, 1, 2, 3), float(linear(1, 2, 3)));
}

}  // namespace
}  // namespace vdblight
