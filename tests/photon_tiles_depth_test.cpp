// Depth moments of photon tiles (bake --method photons --depth-moments --tiles N): tile i
// bakes those of a run of the nodes (photonTileDepthNodes) beside its photon sums; the merge
// puts the runs together and writes the single bake's bytes, and refuses tiles that disagree
// (some with depth, some without; a node held twice or by none) with one line.
#include <gtest/gtest.h>

#include <algorithm>

#include "../libvdblight/src/volume/tile_io.h"
#include "cli_util.h"
#include "grids.h"
#include "photon_tile_fixtures.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {

using test::bytesOf;

TEST(PhotonTilesDepth, TwoAndThreeTilesMergeToTheSingleBakeFullAndCompact) {
    const Scene scene = test::photonRoom();
    for (const bool compact : {false, true}) {
        SCOPED_TRACE(compact ? "compact" : "full");
        test::TempDir dir;
        BakeRequest r = test::photonRequest();
        r.params.set("depth-moments", true);  // the default's too; explicit so that the test does not follow the default
        r.tileParameters += "--depth-moments=true\n";
        r.params.set("compact", compact);
        if (compact) r.tileParameters += "--compact=true\n";
        bakeToFile(scene, r, dir.file("whole.vdb"));
        const Volume whole = readVolume(dir.file("whole.vdb"));
        ASSERT_TRUE(whole.hasDepth());
        const std::size_t nodes = whole.levels[0].grid.nodeCount();
        for (int count : {2, 3}) {
            SCOPED_TRACE(count);
            std::vector<std::string> paths = test::bakePhotonTiles(scene, r, dir, count, "t" + std::to_string(count) + "_");
            // Every tile holds the depth of its own run of nodes only, the runs all of them.
            std::size_t held = 0;
            for (int t = 0; t < count; ++t) {
                const vdb_detail::TileFile tile = vdb_detail::readTileFile(paths[std::size_t(t)]);
                ASSERT_TRUE(tile.depth);
                const std::vector<uint64_t>& own = tile.part.levels[0].activeNodes;
                ASSERT_FALSE(own.empty());
                EXPECT_EQ(own.front(), uint64_t(t) * nodes / uint64_t(count));
                EXPECT_EQ(own.size(), (uint64_t(t) + 1) * nodes / uint64_t(count) - own.front());
                held += own.size();
            }
            EXPECT_EQ(held, nodes);
            std::reverse(paths.begin(), paths.end());  // any order
            const MergedTiles merged = mergeTiles(paths);
            ASSERT_TRUE(merged.volume.hasDepth());
            const std::string out = dir.file("merged" + std::to_string(count) + ".vdb");
            writeVolume(merged.volume, out, merged.write);  // compact: half floats, as the whole file's
            EXPECT_TRUE(readVolume(out).levels[0].depth == whole.levels[0].depth) << "depth moments differ";
            EXPECT_TRUE(bytesOf(out) == bytesOf(dir.file("whole.vdb")))
                << "merge of " << count << " photon tiles with depth differs from the single bake";
        }
    }
}

TEST(PhotonTilesDepth, RunsOfNodesCoverEveryNodeOnceForAnyTileCount) {
    const GridSpec g = test::makeGrid({0, 0, 0}, 1.0, 2, 2, 2);  // 8 nodes
    for (int count = 1; count <= 11; ++count) {
        std::vector<int> holders(g.nodeCount(), 0);
        for (int t = 0; t < count; ++t) {
            const NodeMask m = photonTileDepthNodes(g, count, t);
            ASSERT_EQ(m.size(), 1u);
            ASSERT_EQ(m[0].size(), g.nodeCount());
            const auto first = std::find(m[0].begin(), m[0].end(), uint8_t(1));
            const auto n = std::count(m[0].begin(), m[0].end(), uint8_t(1));
            EXPECT_TRUE(std::all_of(first, first + n, [](uint8_t b) { return b == 1; })) << "run not contiguous";
            EXPECT_LE(n, (8 + count - 1) / count);  // equal shares within one node
            EXPECT_GE(n, 8 / count);
            for (std::size_t i = 0; i < m[0].size(); ++i) holders[i] += m[0][i];
        }
        EXPECT_TRUE(std::all_of(holders.begin(), holders.end(), [](int h) { return h == 1; })) << count << " tiles";
    }
    EXPECT_THROW(photonTileDepthNodes(g, 0, 0), ValueError);
    EXPECT_THROW(photonTileDepthNodes(g, 3, 3), ValueError);
    EXPECT_THROW(photonTileDepthNodes(g, 3, -1), ValueError);
}

/// Two photon tiles of one bake on a 3 x 2 x 4 grid (24 nodes): tile 0 batches 0..1, tile 1
/// batches 2..4, each with the depth of the nodes [first, end) given (first < 0: none).
class TwoPhotonTiles : public ::testing::Test {
protected:
    void SetUp() override {
        sums.grid = test::makeGrid({-1, 2, 0.5}, 0.25, 3, 2, 4);
        sums.exponent = -70;
        sums.batches = 5;
        sums.values.assign(sums.grid.nodeCount() * iv::kFloatsPerNode, PhotonFixed(1) << 70);
    }
    /// Depth values of node n: distinct, on the 8-bit grid as the bake stores them.
    static float depthValue(uint64_t n, int k) { return depth::quantize(double((n * 7 + uint64_t(k)) % 256) / 255.0); }
    std::string write(int index, int first, int end) {
        PhotonSums s = sums;
        s.firstBatch = index == 0 ? 0 : 2;
        s.endBatch = index == 0 ? 2 : 5;
        TileId id;
        id.index = index, id.count = 2, id.paramsHash = tileParamsHash("scene", "photons\n");
        VolumeLevel depth;
        depth.grid = sums.grid;
        for (int n = std::max(first, 0); n < end; ++n) {
            depth.activeNodes.push_back(uint64_t(n));
            for (int k = 0; k < depth::kFloatsPerNode; ++k) depth.depth.push_back(depthValue(uint64_t(n), k));
        }
        const std::string path = dir.file("p" + std::to_string(index) + ".vdb");
        writePhotonTile(s, {}, id, path, {}, false, first < 0 ? nullptr : &depth);
        return path;
    }
    /// mergeTiles' refusal (FormatError), or "merged".
    static std::string refusal(const std::vector<std::string>& paths) {
        try {
            mergeTiles(paths);
        } catch (const FormatError& e) {
            return e.what();
        }
        return "merged";
    }
    test::TempDir dir;
    PhotonSums sums;
};

TEST_F(TwoPhotonTiles, RunsThatMeetMergeIntoTheWholeDepth) {
    const std::string a = write(0, 0, 10), b = write(1, 10, 24);
    const MergedTiles merged = mergeTiles({b, a});
    const VolumeLevel& level = merged.volume.levels[0];
    ASSERT_TRUE(level.hasDepth());
    for (uint64_t n = 0; n < 24; ++n)
        for (int k = 0; k < depth::kFloatsPerNode; ++k)
            ASSERT_EQ(level.nodeDepth(n)[k], depthValue(n, k)) << "node " << n << " value " << k;
    // Through the file: the depth grids of the complete volume.
    writeVolume(merged.volume, dir.file("merged.vdb"), merged.write);
    EXPECT_TRUE(readVolume(dir.file("merged.vdb")).levels[0].depth == level.depth);
    // A tile may hold the depth of no node at all (more tiles than nodes).
    const std::string empty = write(0, 0, 0), all = write(1, 0, 24);
    EXPECT_TRUE(mergeTiles({empty, all}).volume.levels[0].depth == level.depth);
}

TEST_F(TwoPhotonTiles, TilesWithAndWithoutDepthAreRefusedInOneLine) {
    const std::string a = write(0, 0, 12), b = write(1, -1, 0);
    const std::string why = refusal({a, b});
    EXPECT_NE(why.find("'" + b + "' has no depth moments but '" + a + "' has"), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << why;
    EXPECT_NE(refusal({b, a}).find("has no depth moments"), std::string::npos);
    // The command line prints the same one line, exits non-zero and writes nothing.
    const std::string out = dir.file("out.vdb");
    test::expectRefusal("merge " + a + " " + b + " -o " + out, "has no depth moments", out, "depth in one tile only");
}

TEST_F(TwoPhotonTiles, ANodeHeldTwiceOrByNoTileIsRefused) {
    std::string a = write(0, 0, 12), b = write(1, 10, 24);
    const std::string twice = refusal({a, b});
    EXPECT_NE(twice.find("both hold the depth moments of node 10"), std::string::npos) << twice;
    EXPECT_NE(twice.find(a), std::string::npos) << twice;
    EXPECT_NE(twice.find(b), std::string::npos) << twice;
    b = write(1, 13, 24);
    const std::string none = refusal({a, b});
    EXPECT_NE(none.find("hold the depth moments of 23 of the 24 nodes (node 12 in none)"), std::string::npos) << none;
    const std::string out = dir.file("out.vdb");
    test::expectRefusal("merge " + a + " " + b + " -o " + out, "node 12 in none", out, "a node without depth");
}

TEST_F(TwoPhotonTiles, DepthThatDoesNotMatchItsNodesIsNotWritten) {
    VolumeLevel bad;
    bad.grid = sums.grid;
    bad.activeNodes = {3, 2};  // not ascending
    bad.depth.assign(2 * depth::kFloatsPerNode, 0.5f);
    PhotonSums s = sums;
    s.endBatch = 2;
    TileId id;
    id.count = 2, id.paramsHash = "x";
    EXPECT_THROW(writePhotonTile(s, {}, id, dir.file("bad.vdb"), {}, false, &bad), ValueError);
    bad.activeNodes = {2, 24};  // outside the grid
    EXPECT_THROW(writePhotonTile(s, {}, id, dir.file("bad.vdb"), {}, false, &bad), ValueError);
    bad.activeNodes = {2};  // fewer nodes than values
    EXPECT_THROW(writePhotonTile(s, {}, id, dir.file("bad.vdb"), {}, false, &bad), ValueError);
}

}  // namespace
}  // namespace vdblight
