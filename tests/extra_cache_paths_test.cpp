// More paths for the surface probe cache where pass 0 is noisiest (bake/extra_cache_paths.h,
// issue 32, the preview): which nodes trace them. Pure data on a small grid: no bake.
#include <gtest/gtest.h>

#include <vector>

#include "bake/extra_cache_paths.h"
#include "error_split_fixtures.h"

namespace vdblight {
namespace {

using bake_detail::extraCachePaths;
using bake_detail::kExtraCachePaths;

constexpr int kN = test::kTwoRoomsN;
using test::twoRoomsErrors;

GridSpec grid() { return test::twoRoomsGrid(); }

TEST(ExtraCachePaths, GoToTheNodesWhosePooledErrorIsFarAboveTheMedian) {
    const GridSpec g = grid();
    // The dark quarter at 8 x the rest's error: the median is the rest's, 0.05.
    const std::vector<uint32_t> paths = extraCachePaths(g, twoRoomsErrors(0.4f), {});
    for (int k = 0; k < kN; ++k)
        for (int j = 0; j < kN; ++j) {
            // Lit nodes whose 3 x 3 x 3 neighbourhood is all lit: none.
            for (int i = 0; i <= 4; ++i) EXPECT_EQ(paths[g.index(i, j, k)], 0u) << i << " " << j << " " << k;
            // The dark nodes, and the lit node next to them (it pools nine or more dark
            // neighbours: RMS 0.23 or more, above 2 x 0.05): all of them.
            for (int i = 5; i < kN; ++i) EXPECT_EQ(paths[g.index(i, j, k)], kExtraCachePaths) << i << " " << j << " " << k;
        }
}

TEST(ExtraCachePaths, AsManyPerNodeAsTheBakeAsks) {
    // --quality fast's 128 (kFastExtraCachePaths): the same nodes, that many paths each.
    const GridSpec g = grid();
    const std::vector<uint32_t> preset = extraCachePaths(g, twoRoomsErrors(0.4f), {});
    const std::vector<uint32_t> fast = extraCachePaths(g, twoRoomsErrors(0.4f), {}, bake_detail::kFastExtraCachePaths);
    ASSERT_EQ(fast.size(), preset.size());
    std::size_t chosen = 0;
    for (std::size_t n = 0; n < fast.size(); ++n) {
        EXPECT_EQ(fast[n], preset[n] ? bake_detail::kFastExtraCachePaths : 0u) << n;
        chosen += preset[n] != 0;
    }
    EXPECT_GT(chosen, 0u);
}

TEST(ExtraCachePaths, NoneWhereTheErrorIsEven) {
    // Less than twice the rest's error is not "far above" the median (kNoisyFactor 2), and a
    // uniform error chooses nothing: a scene without a dark room traces no extra paths.
    for (const float dark : {0.05f, 0.09f})
        for (const uint32_t p : extraCachePaths(grid(), twoRoomsErrors(dark), {})) EXPECT_EQ(p, 0u) << dark;
}

TEST(ExtraCachePaths, NoneInsideSolidsOrWithoutAnEstimate) {
    const GridSpec g = grid();
    std::vector<float> e = twoRoomsErrors(0.4f);
    std::vector<uint8_t> inside(e.size(), 0);
    const std::size_t solid = g.index(6, 3, 3), unknown = g.index(7, 3, 3);
    inside[solid] = 1;
    e[unknown] = -1.0f;  // an error estimate of a node inside a solid (kNodeInsideSolid) or none
    const std::vector<uint32_t> paths = extraCachePaths(g, e, inside);
    EXPECT_EQ(paths[solid], 0u);
    EXPECT_EQ(paths[unknown], 0u);
    EXPECT_EQ(paths[g.index(6, 4, 4)], kExtraCachePaths);
}

}  // namespace
}  // namespace vdblight
