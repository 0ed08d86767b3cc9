// The tile partition (tiles.h): every node of every level in exactly one tile, whole bricks
// of 8^3 nodes, balanced within one brick; tile files round-trip and merge exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "test_util.h"
#include "vdblight/errors.h"
#include "vdblight/tiles.h"
#include "vdblight/vdb_io.h"

namespace vdblight {
namespace {

/// A dense 20^3 level 0 and a sparse level 1 (every third node of a 39^3 box).
std::vector<VolumeLevel> twoLevels() {
    std::vector<VolumeLevel> levels(2);
    levels[0].grid.nx = levels[0].grid.ny = levels[0].grid.nz = 20;
    levels[0].grid.spacing = 1;
    levels[1].grid.nx = levels[1].grid.ny = levels[1].grid.nz = 39;
    levels[1].grid.spacing = 0.5;
    for (uint64_t n = 0; n < levels[1].grid.nodeCount(); n += 3) levels[1].activeNodes.push_back(n);
    return levels;
}

uint64_t brickOf(const VolumeLevel& l, std::size_t n) {
    const uint64_t linear = l.sparse() ? l.activeNodes[n] : n;
    const uint64_t nx = uint64_t(l.grid.nx), ny = uint64_t(l.grid.ny);
    return ((linear / (nx * ny)) / 8 * 100 + (linear / nx) % ny / 8) * 100 + linear % nx / 8;
}

TEST(Tiles, PartitionCoversEveryNodeOnceInWholeBricksBalanced) {
    const std::vector<VolumeLevel> levels = twoLevels();
    const uint64_t total = levels[0].storedNodes() + levels[1].storedNodes();
    EXPECT_EQ(countBricks(levels), 27u + 125u);
    for (int count : {1, 2, 5, 16}) {
        SCOPED_TRACE(count);
        std::vector<std::vector<int>> owner(levels.size());
        for (std::size_t l = 0; l < levels.size(); ++l) owner[l].assign(levels[l].storedNodes(), -1);
        for (int t = 0; t < count; ++t) {
            const NodeMask mask = tileNodeMask(levels, count, t);
            ASSERT_EQ(mask.size(), levels.size());
            uint64_t mine = 0;
            for (std::size_t l = 0; l < levels.size(); ++l)
                for (std::size_t n = 0; n < mask[l].size(); ++n)
                    if (mask[l][n]) {
                        EXPECT_EQ(owner[l][n], -1) << "node in two tiles";
                        owner[l][n] = t;
                        ++mine;
                    }
            // Balanced to within one brick (512 nodes) of the mean.
            EXPECT_LE(std::abs(double(mine) - double(total) / count), 512.0) << "tile " << t;
        }
        for (std::size_t l = 0; l < levels.size(); ++l) {
            for (std::size_t n = 0; n < owner[l].size(); ++n) ASSERT_GE(owner[l][n], 0) << "node in no tile";
            // Whole bricks: all nodes of a brick share the tile.
            for (std::size_t n = 0; n < owner[l].size(); ++n)
                for (std::size_t m = n + 1; m < std::min(owner[l].size(), n + 40); ++m) {
                    if (brickOf(levels[l], n) == brickOf(levels[l], m)) {
                        EXPECT_EQ(owner[l][n], owner[l][m]);
                    }
                }
        }
    }
    EXPECT_THROW(tileNodeMask(levels, 153, 0), ValueError);  // more tiles than bricks
    EXPECT_THROW(tileNodeMask(levels, 4, 4), ValueError);
    EXPECT_THROW(tileNodeMask(levels, 0, 0), ValueError);
}

Volume randomVolume() {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.origin = Vec3d(-1, 0, 2);
    level.grid.spacing = 0.125;
    level.grid.nx = 17, level.grid.ny = 9, level.grid.nz = 10;
    level.data.resize(level.grid.nodeCount() * 27);
    for (std::size_t i = 0; i < level.data.size(); ++i) level.data[i] = float((i * 7919) % 1013) / 17.0f;
    v.levels.push_back(level);
    v.meta["seed"] = int64_t(1);
    v.meta["rays_intersect"] = int64_t(1000);
    return v;
}

std::string bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Tiles, WrittenTilesMergeToTheSameFile) {
    test::TempDir dir;
    const Volume whole = randomVolume();
    writeVolume(whole, dir.file("whole.vdb"));
    const int count = 3;
    std::vector<std::string> paths;
    for (int t = count - 1; t >= 0; --t) {  // any order
        TileId id;
        id.index = t, id.count = count, id.paramsHash = tileParamsHash("scene", "rays=1\n");
        const NodeMask mask = tileNodeMask(whole.levels, count, t);
        // Each tile counted its own rays; the merge sums them back.
        Volume part = whole;
        part.meta["rays_intersect"] = int64_t(t == 0 ? 400 : 300);
        paths.push_back(dir.file("tile" + std::to_string(t) + ".vdb"));
        writeTile(part, mask, id, paths.back());
        TileId back;
        ASSERT_TRUE(readTileId(paths.back(), back));
        EXPECT_EQ(back.index, t);
        EXPECT_EQ(back.paramsHash, id.paramsHash);
        EXPECT_THROW(readVolume(paths.back()), FormatError);  // not a complete volume
    }
    const MergedTiles merged = mergeTiles(paths);
    writeVolume(merged.volume, dir.file("merged.vdb"), merged.write);
    EXPECT_TRUE(bytesOf(dir.file("merged.vdb")) == bytesOf(dir.file("whole.vdb")));
    TileId none;
    EXPECT_FALSE(readTileId(dir.file("whole.vdb"), none));
    // Missing and duplicate tiles are named.
    try {
        mergeTiles({paths[0], paths[2]});
        ADD_FAILURE() << "merged with a tile missing";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("tile 1 of 3 is missing"), std::string::npos) << e.what();
    }
    try {
        mergeTiles({paths[0], paths[1], paths[2], paths[1]});
        ADD_FAILURE() << "merged a duplicate";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("are both tile 1 of 3"), std::string::npos) << e.what();
    }
}

TEST(Tiles, AVolumeWithDirectLightOutOfTheShIsNotTiled) {
    // Tile files do not carry the light list or visibility grids (bake --direct): the merged
    // file would claim to hold all its direct light, so writeTile refuses.
    test::TempDir dir;
    Volume v = randomVolume();
    v.direct.mode = DirectMode::Runtime;
    TileId id;
    id.index = 0, id.count = 2, id.paramsHash = tileParamsHash("scene", "rays=1\n");
    const std::string path = dir.file("tile0.vdb");
    try {
        writeTile(v, tileNodeMask(v.levels, 2, 0), id, path);
        ADD_FAILURE() << "a --direct runtime volume was written as a tile";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("add --direct baked"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace vdblight
