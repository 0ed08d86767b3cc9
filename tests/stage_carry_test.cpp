// What a probe stage carries for the default's guide and blend (bake/stage_carry.h, issue 32):
// a stage file's channels name what it carries, and a tile of stage 1 reads back pass 0's values,
// errors, solid flags and pooled guide exactly as the single bake holds them (the end-to-end
// bytes: CliTiles.DefaultBakeTiledInStagesMergesToTheSingleBake).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "bake/direction_guide.h"
#include "bake/stage_carry.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"

namespace vdblight {
namespace {

using bake_detail::DirectionGuide;
using bake_detail::StageCarry;
constexpr std::size_t kCells = DirectionGuide::kCells;

TEST(StageCarry, ChannelNamesSayWhatTheStageCarries) {
    for (const std::size_t floats : {std::size_t(0), std::size_t(27), std::size_t(75)})
        for (const bool guide : {false, true}) {
            StageCarry c;
            c.firstPassFloats = floats;
            c.guide = guide;
            const BasisDesc b = c.basis();
            EXPECT_TRUE(b.sameKind(probeStageBasis()));
            EXPECT_EQ(std::size_t(b.channelCount()) * 3, c.floatsPerNode());
            const StageCarry back = StageCarry::of(b);
            EXPECT_EQ(back.firstPassFloats, floats);
            EXPECT_EQ(back.guide, guide);
        }
    EXPECT_EQ(StageCarry::of(probeStageBasis()).floatsPerNode(), 27u);  // a stage without either lever
    BasisDesc bad = StageCarry{27, true}.basis();
    bad.channelNames.pop_back();  // a guide cut short
    EXPECT_THROW(StageCarry::of(bad), FormatError);
    bad = StageCarry{27, false}.basis();
    bad.channelNames.pop_back();  // values without their error channel
    EXPECT_THROW(StageCarry::of(bad), FormatError);
}

TEST(StageCarry, AWindowReadsBackWhatTheSingleBakeHolds) {
    GridSpec grid;
    grid.nx = 5;
    grid.ny = 4;
    grid.nz = 7;  // more slabs than the in-place pooling's ring (radius + 1)
    grid.spacing = 1;
    const std::size_t nodes = grid.nodeCount(), floats = 6;
    // Pass 0 at every node, as a stage-0 bake of all of them holds it.
    std::vector<float> values(nodes * floats), error(nodes), sums(nodes * kCells);
    std::vector<uint32_t> counts(nodes * kCells);
    std::vector<uint8_t> solid(nodes);
    for (std::size_t n = 0; n < nodes; ++n) {
        for (std::size_t f = 0; f < floats; ++f) values[n * floats + f] = 0.1f * float(n) + 0.01f * float(f);
        error[n] = 0.003f * float(n % 7) + 1e-4f;
        solid[n] = n % 5 == 2;
        for (std::size_t c = 0; c < kCells; ++c) {
            sums[n * kCells + c] = 0.37f * float((n * 31 + c * 17) % 23);
            counts[n * kCells + c] = uint32_t((n + c) % 4);
        }
    }
    Volume stage;
    stage.basis = probeStageBasis();
    stage.levels.resize(1);
    stage.levels[0].grid = grid;
    stage.levels[0].data.assign(nodes * 27, 0.5f);
    const StageCarry carry{floats, true};
    bake_detail::carryIntoStage(stage, carry, values, error, solid, sums, counts);
    EXPECT_EQ(stage.levels[0].data.size(), nodes * carry.floatsPerNode());
    EXPECT_EQ(stage.levels[0].data[carry.floatsPerNode()], 0.5f);  // node 1's reflected light first

    // The single bake pools every node's map at once, in place (poolGuideSums); first against
    // the plain sum over each node's neighbours within kPoolRadius steps, in the same order, on
    // one thread: on two it must give the same bits.
    std::vector<float> pooledSums = sums;
    std::vector<uint32_t> pooledCounts = counts;
    bake_detail::poolGuideSums(grid, DirectionGuide::kPoolRadius, 2, pooledSums, pooledCounts);
    const int r = DirectionGuide::kPoolRadius;
    for (int k = 0; k < grid.nz; ++k)
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i)
                for (std::size_t c = 0; c < kCells; ++c) {
                    float sum = 0.0f;
                    uint32_t count = 0;
                    for (int c3 = std::max(k - r, 0); c3 <= std::min(k + r, grid.nz - 1); ++c3)
                        for (int b = std::max(j - r, 0); b <= std::min(j + r, grid.ny - 1); ++b)
                            for (int a = std::max(i - r, 0); a <= std::min(i + r, grid.nx - 1); ++a) {
                                sum += sums[grid.index(a, b, c3) * kCells + c];
                                count += counts[grid.index(a, b, c3) * kCells + c];
                            }
                    const std::size_t n = grid.index(i, j, k);
                    ASSERT_EQ(pooledSums[n * kCells + c], sum) << n << " " << c;  // the same bits
                    ASSERT_EQ(pooledCounts[n * kCells + c], count) << n << " " << c;
                }

    const std::size_t first = 17, held = 21;  // a tile's window
    std::vector<float> v, e, s;
    std::vector<uint8_t> inside;
    std::vector<uint32_t> k;
    bake_detail::readCarriedFirstPass(stage, StageCarry::of(stage.basis), first, held, &v, &e, &inside);
    bake_detail::poolCarriedGuide(stage, carry, grid, DirectionGuide::kPoolRadius, 2, first, held, s, k);
    ASSERT_EQ(v.size(), held * floats);
    for (std::size_t h = 0; h < held; ++h) {
        const std::size_t n = first + h;
        EXPECT_EQ(e[h], error[n]);
        EXPECT_EQ(inside[h], solid[n]);
        for (std::size_t f = 0; f < floats; ++f) EXPECT_EQ(v[h * floats + f], values[n * floats + f]);
        for (std::size_t c = 0; c < kCells; ++c) {
            EXPECT_EQ(s[h * kCells + c], pooledSums[n * kCells + c]) << n << " " << c;  // the same bits
            EXPECT_EQ(k[h * kCells + c], pooledCounts[n * kCells + c]) << n << " " << c;
        }
    }
    // A window beyond the stage's nodes is refused, not read past the end.
    EXPECT_THROW(bake_detail::readCarriedFirstPass(stage, carry, nodes - 2, 3, &v, &e, nullptr), ValueError);
}

}  // namespace
}  // namespace vdblight
