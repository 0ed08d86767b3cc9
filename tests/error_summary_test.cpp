// The bake's noise summary counts the nodes that lookups in free space read (issue 29):
// - with depth moments, a node inside a closed solid (most of its first hits are back faces)
//   is marked kNodeInsideSolid, and exactly those nodes are: a solid cube under a sky, the
//   nodes inside it known from geometry;
// - without depth moments free-space lookups do read them, so none is left out;
// - addErrorSummary's quantiles, maximum and worst nodes are those of the other nodes, and
//   nodes_inside_solids counts the left-out ones (the merge of tiles writes the same, from the
//   same function: tiles_test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "support/scene_generators.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/volume/volume.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {
constexpr float kHalf = 0.5f;  // the solid cube is [-0.5, 0.5]^3

/// A closed solid cube (front faces outwards) under a white sky.
Scene solidCubeUnderSky() {
    Scene s;
    s.name = "solid_cube";
    Material m;
    m.albedo = {0.5f, 0.5f, 0.5f};
    addMaterial(s, m);
    appendBox(s, {-kHalf, -kHalf, -kHalf}, {kHalf, kHalf, kHalf}, /*inward=*/false, 0);
    s.sky.constant = {1, 1, 1};
    return s;
}

/// 8^3 nodes over [-1, 1]^3: x = -1 + 2k/7, none on the cube's faces; k = 2..5 lie inside.
GridSpec gridAroundCube() {
    GridSpec g;
    g.origin = {-1, -1, -1};
    g.spacing = 2.0 / 7.0;
    g.nx = g.ny = g.nz = 8;
    return g;
}

bool insideCube(const Vec3d& p) {
    return std::fabs(p.x) < kHalf && std::fabs(p.y) < kHalf && std::fabs(p.z) < kHalf;
}

BakeStats gatherStats(bool depthMoments) {
    const Scene scene = solidCubeUnderSky();
    const Tracer tracer(scene);
    GatherOptions o;
    o.raysPerNode = 128;
    o.depthMoments = depthMoments;
    BakeStats stats;
    bakeShGather(scene, tracer, gridAroundCube(), o, nullptr, &stats);
    return stats;
}
}  // namespace

TEST(ErrorSummary, WithDepthWeightsTheNodesInsideSolidsAreExactlyTheMarkedOnes) {
    const GridSpec g = gridAroundCube();
    const BakeStats stats = gatherStats(true);
    ASSERT_EQ(stats.estimatedError.size(), 512u);
    std::size_t inside = 0;
    for (std::size_t n = 0; n < stats.estimatedError.size(); ++n) {
        const bool expected = insideCube(g.node(n));
        inside += expected;
        EXPECT_EQ(stats.estimatedError[n] == kNodeInsideSolid, expected) << "node " << n << " error " << stats.estimatedError[n];
        if (!expected) {
            EXPECT_GE(stats.estimatedError[n], 0.0f) << "node " << n;
        }
    }
    EXPECT_EQ(inside, 64u);
    EXPECT_EQ(nodesInsideSolids(stats.estimatedError), 64u);
}

TEST(ErrorSummary, WithoutDepthWeightsEveryNodeIsReadAndCounted) {
    const BakeStats stats = gatherStats(false);
    EXPECT_EQ(nodesInsideSolids(stats.estimatedError), 0u);
    for (float e : stats.estimatedError) EXPECT_GE(e, 0.0f);
}

TEST(ErrorSummary, QuantilesAndWorstNodesLeaveTheInsideNodesOut) {
    const GridSpec g = gridAroundCube();
    const BakeStats stats = gatherStats(true);
    std::vector<float> read;
    for (float e : stats.estimatedError)
        if (e >= 0.0f) read.push_back(e);
    ASSERT_EQ(read.size(), 512u - 64u);
    std::sort(read.begin(), read.end());
    Metadata m;
    addErrorSummary(m, stats.estimatedError, g);
    EXPECT_EQ(std::get<int64_t>(m.at("nodes_inside_solids")), 64);
    EXPECT_DOUBLE_EQ(std::get<double>(m.at("estimated_error_max")), read.back());
    EXPECT_DOUBLE_EQ(std::get<double>(m.at("estimated_error_p50")), read[std::size_t(std::ceil(0.5 * read.size())) - 1]);
    EXPECT_DOUBLE_EQ(stats.errorQuantile(1.0), read.back());
    // The five worst nodes "i,j,k:e;..." lie outside the cube.
    const std::string worst = std::get<std::string>(m.at("estimated_error_worst_nodes"));
    std::size_t at = 0;
    for (int k = 0; k < 5; ++k) {
        int i = 0, j = 0, l = 0;
        ASSERT_EQ(std::sscanf(worst.c_str() + at, "%d,%d,%d", &i, &j, &l), 3) << worst;
        EXPECT_FALSE(insideCube(g.node(i, j, l))) << worst;
        at = worst.find(';', at);
        if (at == std::string::npos) break;
        ++at;
    }
    // A volume without nodes inside solids keeps the summary it always had: no count.
    Metadata plain;
    addErrorSummary(plain, read, g);
    EXPECT_EQ(plain.count("nodes_inside_solids"), 0u);
}
