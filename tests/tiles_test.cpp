// The tile partition (tiles.h): every node of every level in exactly one tile, whole bricks
// of 8^3 nodes, balanced within one brick; tile files round-trip and merge exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "test_util.h"
#include "vdblight/volume/volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

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

TEST(Tiles, EveryChannelAndTheErrorSummaryMergeToTheSameFile) {
    // Depth moments, occlusion-mode light visibility and the light list travel with the
    // tiles' nodes; the error summary is recomputed from the tiles' per-node errors and the
    // counts (rays, samples, visibility rays) are summed, plus an earlier stage's once.
    test::TempDir dir;
    Volume whole = randomVolume();
    VolumeLevel& level = whole.levels[0];
    const std::size_t nodes = level.grid.nodeCount();
    level.depth.resize(nodes * depth::kFloatsPerNode);
    for (std::size_t i = 0; i < level.depth.size(); ++i) level.depth[i] = float((i * 31) % 256) / 255.0f;
    whole.direct.mode = DirectMode::Occlusion;
    for (int i = 0; i < 2; ++i) {
        DirectLight light;
        light.position = Vec3d(0.1 * i, 1, 0.5);
        light.value = Rgb(1, 2, 3);
        whole.direct.lights.push_back(light);
    }
    level.lightVisibility.resize(nodes * 2);
    for (std::size_t i = 0; i < level.lightVisibility.size(); ++i) level.lightVisibility[i] = float((i * 17) % 101) / 100.0f;
    std::vector<float> error(nodes);
    for (std::size_t n = 0; n < nodes; ++n) error[n] = float((n * 7727) % 389) / 997.0f;
    addErrorSummary(whole.meta, error, level.grid);
    whole.meta["rays_intersect"] = int64_t(5000);  // 1000 of earlier stages + 4000 of this one
    whole.meta["direct_visibility_rays"] = int64_t(nodes * 2);
    writeVolume(whole, dir.file("whole.vdb"));

    const int count = 3;
    std::vector<std::string> paths;
    for (int t = 0; t < count; ++t) {
        TileId id;
        id.index = t, id.count = count, id.paramsHash = tileParamsHash("scene", "rays=1\n");
        const NodeMask mask = tileNodeMask(whole.levels, count, t);
        const int64_t mine = int64_t(std::count(mask[0].begin(), mask[0].end(), uint8_t(1)));
        Volume part = whole;  // as a tile's bake: its own counts, a summary of its own nodes
        part.meta["rays_intersect"] = int64_t(t == 0 ? 2000 : 1000);
        part.meta["direct_visibility_rays"] = mine * 2;
        std::vector<float> own(nodes, 0.0f);
        for (std::size_t n = 0; n < nodes; ++n) own[n] = mask[0][n] ? error[n] : 0.0f;
        addErrorSummary(part.meta, own, level.grid);
        Metadata earlier;
        earlier["rays_intersect"] = int64_t(1000);
        addEarlierStageSums(part.meta, earlier);
        TileNodeStats stats;
        stats.estimatedError = own;
        paths.push_back(dir.file("tile" + std::to_string(t) + ".vdb"));
        writeTile(part, mask, id, paths.back(), {}, &stats);
    }
    const MergedTiles merged = mergeTiles(paths);
    EXPECT_EQ(merged.volume.direct.lights.size(), 2u);
    EXPECT_EQ(std::get<int64_t>(merged.volume.meta.at("rays_intersect")), 5000);
    writeVolume(merged.volume, dir.file("merged.vdb"), merged.write);
    EXPECT_TRUE(bytesOf(dir.file("merged.vdb")) == bytesOf(dir.file("whole.vdb")));
    const Volume back = readVolume(dir.file("merged.vdb"));
    EXPECT_EQ(back.levels[0].depth, level.depth);
    EXPECT_EQ(back.levels[0].lightVisibility, level.lightVisibility);
}

TEST(Tiles, AProbeStageFileIsReadOnlyAsAStageInput) {
    // The merged tiles of a stage before the last hold reflected light: readVolume refuses
    // them (not a volume to look up), readProbeStage reads them, and nothing else.
    test::TempDir dir;
    Volume stage = randomVolume();
    stage.basis = probeStageBasis();
    stage.meta["probe_stage"] = int64_t(0);
    stage.meta["probe_passes"] = int64_t(1);
    writeVolume(stage, dir.file("stage0.vdb"));
    try {
        readVolume(dir.file("stage0.vdb"));
        ADD_FAILURE() << "a probe stage file was read as a volume";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("--stage-input"), std::string::npos) << e.what();
    }
    const Volume back = readProbeStage(dir.file("stage0.vdb"));
    EXPECT_EQ(back.levels[0].data, stage.levels[0].data);
    writeVolume(randomVolume(), dir.file("whole.vdb"));
    EXPECT_THROW(readProbeStage(dir.file("whole.vdb")), FormatError);
    // A stage tile hashes its input once (its parameter hash) and hands that hash to the
    // damage check: a known hash that says "damaged" is what refuses the file, not a second pass.
    ContentHash known = fileContentHash(dir.file("stage0.vdb"));
    EXPECT_EQ(readProbeStage(dir.file("stage0.vdb"), &known).levels[0].data, stage.levels[0].data);
    known.damaged = true;
    try {
        readProbeStage(dir.file("stage0.vdb"), &known);
        ADD_FAILURE() << "the known hash was not used";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("is damaged"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdblight
