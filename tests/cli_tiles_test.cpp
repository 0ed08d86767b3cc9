// Tiles end to end (issue 17): `bake --tiles N --tile I` + `merge` give the bytes of a
// single-process bake; bad sets of tiles are refused by name; passes that cannot be tiled
// say so; a tile already on disk with the same parameters is skipped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_util.h"
#include "vdblight/vdb_io.h"

namespace vdblight {
namespace {
using test::runCli;

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The defaults of the uniform SH point gather are not tileable (a probe-to-probe pass, the
/// visibility pass of --direct occlusion): tests of tileable bakes say so explicitly.
const std::string kTileable = " --direct baked --quality preview";

/// Bakes `args` once whole and once as `tiles` tiles (tile i on 1 + i % 2 threads), merges
/// the tiles given in reverse order and expects the same bytes.
void expectMergeIdentical(const test::TempDir& dir, const std::string& args, int tiles) {
    const std::string whole = dir.file("whole.vdb"), merged = dir.file("merged.vdb");
    const test::CliRun w = runCli("bake -q -o " + whole + " --threads 2 " + args);
    ASSERT_EQ(w.status, 0) << w.output;
    std::string list;
    for (int t = 0; t < tiles; ++t) {
        const std::string tile = dir.file("tile" + std::to_string(t) + ".vdb");
        const test::CliRun r = runCli("bake -o " + tile + " --threads " + std::to_string(1 + t % 2) + " --tiles " +
                                      std::to_string(tiles) + " --tile " + std::to_string(t) + " " + args);
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find("Baked tile " + std::to_string(t) + " of " + std::to_string(tiles)), std::string::npos)
            << r.output;
        list = tile + " " + list;
    }
    const test::CliRun m = runCli("merge " + list + "-o " + merged);
    ASSERT_EQ(m.status, 0) << m.output;
    const std::string a = fileBytes(whole), b = fileBytes(merged);
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "merged file differs from the single bake (" << a.size() << " vs " << b.size() << " bytes)";
    EXPECT_EQ(fileContentHash(whole).sha256, fileContentHash(merged).sha256);
}

TEST(CliTiles, UniformBinsMergeToTheSingleBake) {
    test::TempDir dir;
    expectMergeIdentical(dir, "--basis bins:2 --resolution 20 --rays 8 --seed 3" + kTileable, 3);
}

TEST(CliTiles, AdaptiveLayoutMergesToTheSingleBakeSeamsIncluded) {
    test::TempDir dir;
    expectMergeIdentical(dir, "--layout adaptive --levels 3 --refine 2 --resolution 6 --rays 8 --seed 2" + kTileable, 4);
}

TEST(CliTiles, BinsOnBilevelAndHalfFloatsMergeToTheSingleBake) {
    test::TempDir dir;
    expectMergeIdentical(dir, "--basis bins:2 --layout bilevel --refine 2 --resolution 6 --rays 8 --half" + kTileable, 2);
}

TEST(CliTiles, CulledBilevelMergesToTheSingleBake) {
    test::TempDir dir;
    expectMergeIdentical(dir, "--layout bilevel --refine 2 --cull-solids --resolution 8 --rays 8" + kTileable, 3);
}

TEST(CliTiles, BadSetsOfTilesAreRefusedByName) {
    test::TempDir dir;
    const std::string args = kTileable + " --layout bilevel --refine 2 --resolution 10 --rays 4 -q --tiles 3 --tile ";
    for (int t = 0; t < 3; ++t)
        ASSERT_EQ(runCli("bake -o " + dir.file("t" + std::to_string(t) + ".vdb") + args + std::to_string(t)).status, 0);
    ASSERT_EQ(runCli("bake -o " + dir.file("seed.vdb") + " --seed 9" + args + "1").status, 0);
    ASSERT_EQ(runCli("bake -o " + dir.file("four.vdb") + kTileable + " --layout bilevel --refine 2 --resolution 10 --rays 4 -q --tiles 4 --tile 1").status, 0);
    const std::string out = dir.file("out.vdb");
    const std::string t0 = dir.file("t0.vdb"), t1 = dir.file("t1.vdb"), t2 = dir.file("t2.vdb");
    test::expectRefusal("merge " + t0 + " " + t2 + " -o " + out, "tile 1 of 3 is missing", out, "missing");
    test::expectRefusal("merge " + t0 + " " + t1 + " " + t2 + " " + t1 + " -o " + out, "are both tile 1 of 3", out,
                        "duplicate");
    test::expectRefusal("merge " + t0 + " " + dir.file("seed.vdb") + " " + t2 + " -o " + out,
                        "different scenes or parameters", out, "other seed");
    test::expectRefusal("merge " + t0 + " " + dir.file("four.vdb") + " " + t2 + " -o " + out, "is a tile of 4", out,
                        "other count");
    // A tile is not a volume: query and export say to merge it.
    test::expectRefusal("query " + t0 + " --at 0.2,0.2,0.2 --normal 0,1,0", "vdblight merge", out, "query a tile");
    const test::CliRun info = runCli("info " + t1);
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("tile 1 of 3"), std::string::npos) << info.output;
}

TEST(CliTiles, PassesThatCannotBeTiledSaySo) {
    test::TempDir dir;
    const std::string out = dir.file("x.vdb"), tile = " --tiles 2 --tile 0 --layout bilevel --refine 2 --resolution 4 -o " + out;
    test::expectRefusal("bake --sampling antialiased" + tile, "cannot be tiled", out, "antialiased");
    test::expectRefusal("bake --method photons" + tile, "cannot be tiled", out, "photons");
    test::expectRefusal("bake --invalidate-backface 0.1" + tile, "cannot be tiled", out, "invalidate");
    test::expectRefusal("bake --target-error 0.1" + tile, "cannot be tiled", out, "target error");
    // The defaults: one probe-to-probe pass, then --direct occlusion (its visibility pass bakes
    // every node and tile files do not carry the visibility grids).
    const std::string uniformTile = " --tiles 2 --tile 0 --resolution 4 -o " + out;
    test::expectRefusal("bake --direct baked" + uniformTile, "add --probe-passes 0 or --quality preview", out, "probe pass");
    test::expectRefusal("bake --quality preview" + uniformTile, "add --direct baked", out, "default occlusion");
    test::expectRefusal("bake --quality preview --direct occlusion" + uniformTile, "add --direct baked", out, "occlusion");
    test::expectRefusal("bake --quality preview --direct runtime" + uniformTile, "add --direct baked", out, "runtime");
    test::expectRefusal("bake --tiles 2 --resolution 4 -o " + out, "--tiles and --tile go together", out, "no --tile");
    test::expectRefusal("bake --tiles 2 --tile 2 --resolution 4 -o " + out, "--tile must be between 0 and 1", out, "range");
    test::expectRefusal("bake --tiles 9 --tile 0 --layout bilevel --refine 2 --resolution 4 -o " + out + kTileable, "bricks of 8^3 nodes", out, "too many");
    // The uniform point gather's per-node error summary is not merged yet.
    test::expectRefusal("bake --tiles 2 --tile 0 --resolution 4 -o " + out + kTileable, "the uniform SH point gather cannot be tiled yet", out, "uniform gather");
}

TEST(CliTiles, ATileAlreadyOnDiskWithTheSameParametersIsSkipped) {
    test::TempDir dir;
    const std::string tile = dir.file("t.vdb"), args = kTileable + " --layout bilevel --refine 2 --resolution 10 --rays 8 --tiles 2 --tile 1 -o " + tile;
    ASSERT_EQ(runCli("bake -q" + args).status, 0);
    const std::string before = fileBytes(tile);
    const auto stamp = std::filesystem::last_write_time(tile);
    const test::CliRun again = runCli("bake --threads 1" + args);  // threads do not change the result
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("already baked"), std::string::npos) << again.output;
    EXPECT_EQ(std::filesystem::last_write_time(tile), stamp);
    const test::CliRun other = runCli("bake --seed 4" + args);  // another seed: baked again
    ASSERT_EQ(other.status, 0) << other.output;
    EXPECT_NE(other.output.find("Baked tile 1 of 2"), std::string::npos) << other.output;
    EXPECT_FALSE(fileBytes(tile) == before);
}

}  // namespace
}  // namespace vdblight
