// Tiles end to end (issue 17): `bake --tiles N --tile I` + `merge` give the bytes of a
// single-process bake (photon bakes too: tiles of photon batches); bad sets of tiles are
// refused by name; passes that cannot be tiled say so; a tile already on disk with the same
// parameters is skipped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_util.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {
using test::runCli;

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Bakes without probe-to-probe passes tile in one stage (the default bake's pass is staged:
/// DefaultBakeTiledInStagesMergesToTheSingleBake): the preview before issue 32 (since then it
/// has a probe pass and the node filter, which the merge runs: the staged test has it).
const std::string kTileable =
    " --direct baked --quality preview --probe-passes 0 --node-filter 0 --no-depth-moments";

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

/// Bakes `args` once whole and once as `tiles` tiles in stages 0..`last` (bake --stage, each
/// stage after 0 reading the merged tiles of the one before), and expects the merged last
/// stage to have the single bake's bytes. Re-running a tile of every stage skips it.
void expectStagedMergeIdentical(const test::TempDir& dir, const std::string& args, int tiles, int last) {
    const std::string whole = dir.file("whole.vdb");
    const test::CliRun w = runCli("bake -q -o " + whole + " --threads 2 " + args);
    ASSERT_EQ(w.status, 0) << w.output;
    std::string merged;
    for (int stage = 0; stage <= last; ++stage) {
        const std::string input = stage > 0 ? " --stage-input " + merged : "";
        std::string list;
        for (int t = 0; t < tiles; ++t) {
            const std::string tile = dir.file("s" + std::to_string(stage) + "t" + std::to_string(t) + ".vdb");
            const std::string cmd = "bake -o " + tile + " --tiles " + std::to_string(tiles) + " --tile " + std::to_string(t) +
                                    " --stage " + std::to_string(stage) + input + " " + args;
            const test::CliRun r = runCli(cmd + " --threads " + std::to_string(1 + t % 2));
            ASSERT_EQ(r.status, 0) << r.output;
            EXPECT_NE(r.output.find("Baked tile " + std::to_string(t) + " of " + std::to_string(tiles) + " (stage " +
                                    std::to_string(stage)),
                      std::string::npos)
                << r.output;
            if (t == 0) {  // resumable in every stage: the same tile again is skipped
                const test::CliRun again = runCli(cmd);
                ASSERT_EQ(again.status, 0) << again.output;
                EXPECT_NE(again.output.find("already baked"), std::string::npos) << again.output;
            }
            list = tile + " " + list;
        }
        merged = dir.file("stage" + std::to_string(stage) + ".vdb");
        const test::CliRun m = runCli("merge " + list + "-o " + merged);
        ASSERT_EQ(m.status, 0) << m.output;
        if (stage < last)  // the reflected light of a pass is no volume to look up
            test::expectRefusal("query " + merged + " --at 0.2,0.2,0.2 --normal 0,1,0", "stage-input", "", "query a stage");
    }
    const std::string a = fileBytes(whole), b = fileBytes(merged);
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "merged file differs from the single bake (" << a.size() << " vs " << b.size() << " bytes)";
}

// --probe-cache surface: stage 1 reads bins of every tile's stage-0 paths, which each stage-0
// tile writes as integer sums and the merge adds (bake/surface_bins.h): the staged bake has the
// single bake's bytes. A stage-1 tile refuses a stage input baked without the surface cache.
TEST(CliTiles, SurfaceProbeCacheTiledInStagesMergesToTheSingleBake) {
    test::TempDir dir;
    expectStagedMergeIdentical(dir, "--probe-cache surface --resolution 10 --rays 32 --seed 4", 3, 1);
    const std::string nodes = dir.file("nodes0.vdb"), tile = dir.file("t.vdb");
    ASSERT_EQ(runCli("bake -q -o " + nodes + " --tiles 1 --tile 0 --stage 0 --resolution 10 --rays 32 --seed 4").status, 0);
    const std::string mergedNodes = dir.file("nodes_stage0.vdb");
    ASSERT_EQ(runCli("merge -q " + nodes + " -o " + mergedNodes).status, 0);
    test::expectRefusal("bake -o " + tile + " --tiles 1 --tile 0 --stage 1 --stage-input " + mergedNodes +
                            " --probe-cache surface --resolution 10 --rays 32 --seed 4",
                        "other options", tile, "a stage input without surface bins");
}

TEST(CliTiles, DefaultBakeTiledInStagesMergesToTheSingleBake) {
    // The default bake (one probe-to-probe pass, --direct occlusion with shadow edges, the
    // per-node error summary) at a small size, plus depth moments and one pass of the node
    // filter, whose kernel crosses tile borders (the merge of the last stage runs it, with the
    // tiles' per-node errors): stage 0, merge, stage 1, merge.
    test::TempDir dir;
    expectStagedMergeIdentical(dir, "--resolution 10 --rays 32 --seed 4 --depth-moments --node-filter 1", 3, 1);
    const test::CliRun info = runCli("info " + dir.file("stage1.vdb"));
    EXPECT_NE(info.output.find("light_visibility_0"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("estimated_error_worst_nodes"), std::string::npos) << info.output;
    // With the default's guided probe pass and pass 0 blended in (stage 0 carries what they read).
    EXPECT_NE(info.output.find("probe_directions"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("first_pass_blend"), std::string::npos) << info.output;
    // A stage file of another bake is refused; a stage-1 tile is baked again when the stage-0
    // file it read has changed.
    const std::string tile = dir.file("s1t0.vdb"),
                      cmd = "bake -o " + tile + " --tiles 3 --tile 0 --stage 1 --stage-input " + dir.file("stage0.vdb") +
                            " --resolution 10 --rays 32 --depth-moments";
    ASSERT_EQ(runCli("bake -q -o " + dir.file("other.vdb") + " --tiles 1 --tile 0 --stage 0 --resolution 10 --rays 32 --seed 5 --depth-moments").status, 0);
    ASSERT_EQ(runCli("merge -q " + dir.file("other.vdb") + " -o " + dir.file("stage0.vdb")).status, 0);
    test::expectRefusal(cmd, "is a stage of a bake with another scene or other options", "", "stage input of seed 5");
    const test::CliRun again = runCli(cmd + " --seed 5");  // the options of the new stage 0: baked again
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("Baked tile 0 of 3 (stage 1"), std::string::npos) << again.output;
}

TEST(CliTiles, ErrorTargetedBakeWithTwoProbePassesMergesToTheSingleBake) {
    // Every node to an error target, two probe passes (three stages); depth moments from
    // their own pass.
    test::TempDir dir;
    expectStagedMergeIdentical(dir, "--target-error 0.03 --probe-passes 2 --max-rays 64 --resolution 10 --depth-moments --half",
                               2, 2);
}

TEST(CliTiles, ATileWithoutNodesMergesWithShadowEdges) {
    // 9^3 nodes in three tiles: tile 0 gets none of them. With --direct occlusion's shadow
    // edges it aborted (heap corruption) before the fix in direct_pass.cpp.
    test::TempDir dir;
    expectMergeIdentical(dir, "--resolution 9 --rays 8 --bounces 1 --no-depth-moments --direct occlusion --probe-passes 0", 3);
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

TEST(CliTiles, PhotonBakesMergeToTheSingleBake) {
    // A tile traces a run of the photon batches (40 000 photons: 10 batches of 4096) and
    // holds the whole grid's exact sums, and the depth moments (on by default) of its run of
    // nodes; merges of 1, 2 and 3 tiles give the single bake, with and without depth.
    for (int tiles : {1, 2, 3}) {
        SCOPED_TRACE(tiles);
        test::TempDir dir;
        expectMergeIdentical(dir, "--method photons --photons 40000 --resolution 6 --seed 3", tiles);
        EXPECT_TRUE(readVolume(dir.file("merged.vdb")).hasDepth());
    }
    for (const std::string extra : {" --compact", " --no-depth-moments"}) {
        SCOPED_TRACE(extra);
        test::TempDir dir;
        expectMergeIdentical(dir, "--method photons --photons 40000 --resolution 6" + extra, 2);
        EXPECT_EQ(readVolume(dir.file("merged.vdb")).hasDepth(), extra == " --compact");
    }
}

TEST(CliTiles, BadSetsOfPhotonTilesAreRefusedByName) {
    test::TempDir dir;
    const std::string args = " --method photons --photons 40000 --resolution 6 -q --tiles 3 --tile ";
    for (int t = 0; t < 3; ++t)
        ASSERT_EQ(runCli("bake -o " + dir.file("t" + std::to_string(t) + ".vdb") + args + std::to_string(t)).status, 0);
    ASSERT_EQ(runCli("bake -o " + dir.file("more.vdb") + " --seed 9" + args + "1").status, 0);
    const std::string out = dir.file("out.vdb");
    const std::string t0 = dir.file("t0.vdb"), t1 = dir.file("t1.vdb"), t2 = dir.file("t2.vdb");
    test::expectRefusal("merge " + t0 + " " + t2 + " -o " + out, "tile 1 of 3 is missing", out, "missing");
    test::expectRefusal("merge " + t0 + " " + t1 + " " + t2 + " " + t1 + " -o " + out, "are both tile 1 of 3", out,
                        "duplicate");
    test::expectRefusal("merge " + t0 + " " + dir.file("more.vdb") + " " + t2 + " -o " + out,
                        "different scenes or parameters", out, "other seed");
    test::expectRefusal("bake --method photons --photons 40000 --resolution 6 --tiles 11 --tile 0 -o " + out,
                        "the photon batches of this bake", out, "more tiles than batches");
    const test::CliRun info = runCli("info " + t1);
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("tile 1 of 3"), std::string::npos) << info.output;
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
    test::expectRefusal("bake --invalidate-backface 0.1" + tile, "cannot be tiled", out, "invalidate");
    test::expectRefusal("bake --sh-window --resolution 4 --tiles 2 --tile 0 --probe-passes 0 -o " + out, "cannot be tiled", out,
                        "sh-window");
    // Probe-to-probe passes (the default) are tiled in stages, each reading the one before.
    const std::string uniformTile = " --tiles 2 --tile 0 --resolution 4 -o " + out;
    test::expectRefusal("bake" + uniformTile, "tiled in stages", out, "default without --stage");
    test::expectRefusal("bake --stage 2" + uniformTile, "--stage must be between 0 and 1", out, "stage range");
    test::expectRefusal("bake --stage 1" + uniformTile, "needs --stage-input", out, "no stage input");
    test::expectRefusal("bake --probe-cache surface --quality preview --probe-passes 0 --resolution 4 -o " + out, "needs exactly one probe pass",
                        out, "surface probe cache without a probe pass");
    test::expectRefusal("bake --stage 0 --stage-input " + out + uniformTile, "--stage-input needs --stage 1", out, "input at 0");
    test::expectRefusal("bake --stage 0 --resolution 4 -o " + out, "--stage needs --tiles", out, "stage without tiles");
    test::expectRefusal("bake --stage 0 --quality preview --probe-passes 0 --node-filter 0" + uniformTile, "--stage needs probe-to-probe passes", out, "no passes");
    const std::string volume = dir.file("volume.vdb");
    ASSERT_EQ(runCli("bake -q --quality preview --resolution 4 -o " + volume).status, 0);
    test::expectRefusal("bake --stage 1 --stage-input " + volume + uniformTile, "no probe stage file", out, "a volume as input");
    test::expectRefusal("bake --tiles 2 --resolution 4 -o " + out, "--tiles and --tile go together", out, "no --tile");
    test::expectRefusal("bake --quality preview" + uniformTile, "tiled in stages", out, "the preview's probe pass");
    // Three of what the preview and `fast` add to their probe pass choose rays by every node's
    // error: each refused by name (the guide and the blend tile:
    // DefaultBakeTiledInStagesMergesToTheSingleBake).
    for (const std::string flag : {"extra-cache-paths", "first-pass-by-error", "probe-pass-by-error"})
        test::expectRefusal("bake --stage 0 --quality preview --" + flag + uniformTile, "--" + flag + " cannot be tiled", out, flag);
    test::expectRefusal("bake --stage 0 --quality default --probe-passes 2 --guide-probe-directions" + uniformTile,
                        "tiles with one probe pass only", out, "guide with two probe passes");
    test::expectRefusal("bake --tiles 2 --tile 2 --resolution 4 -o " + out, "--tile must be between 0 and 1", out, "range");
    test::expectRefusal("bake --tiles 9 --tile 0 --layout bilevel --refine 2 --resolution 4 -o " + out + kTileable, "bricks of 8^3 nodes", out, "too many");
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
