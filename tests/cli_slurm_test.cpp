// `vdblight slurm` (issue 17): the job-array and merge scripts it writes, run here without
// Slurm (each array task by hand with SLURM_ARRAY_TASK_ID), give the bytes of a single bake;
// re-running the array redoes only missing tiles. On a real one-node Slurm:
// tests/slurm_cluster_test.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_util.h"

namespace vdblight {
namespace {
using test::runCli;

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

const std::string kScene = std::string(VDBLIGHT_SOURCE_DIR) + "/data/cornell_box.obj";

TEST(CliSlurm, ScriptsRunByHandGiveTheSingleBake) {
    test::TempDir dir;
    const std::string world = dir.file("world.vdb"), whole = dir.file("whole.vdb");
    // One stage (no probe pass): one array and one merge (the default bake: the test below).
    const std::string opts = " --layout adaptive --levels 2 --refine 2 --resolution 6 --rays 8 --seed 4 --direct baked --quality preview";
    ASSERT_EQ(runCli("bake " + kScene + " -q -o " + whole + opts).status, 0);
    const test::CliRun w = runCli("slurm " + kScene + " -o " + world + " --tiles 3 --sbatch '--time=10 --mem 1G'" + opts);
    ASSERT_EQ(w.status, 0) << w.output;
    const std::string d = world + ".tiles";
    const std::string array = fileBytes(d + "/tiles.sbatch"), merge = fileBytes(d + "/merge.sbatch");
    EXPECT_NE(array.find("#SBATCH --array=0-2\n"), std::string::npos) << array;
    EXPECT_NE(array.find("#SBATCH --time=10\n#SBATCH --mem 1G\n"), std::string::npos) << array;
    EXPECT_NE(fileBytes(d + "/submit.sh").find("--dependency=afterok:$id"), std::string::npos);
    for (int t = 0; t < 3; ++t)
        ASSERT_EQ(test::runCommand("SLURM_ARRAY_TASK_ID=" + std::to_string(t) + " sh " + d + "/tiles.sbatch"), 0);
    ASSERT_EQ(test::runCommand("sh " + d + "/merge.sbatch"), 0) << merge;
    EXPECT_TRUE(fileBytes(world) == fileBytes(whole)) << "merged world differs from the single bake";
    // Resumable: with tile 1 lost, the array redoes only tile 1.
    std::filesystem::remove(d + "/tile-1.vdb");
    const auto kept = std::filesystem::last_write_time(d + "/tile-0.vdb");
    for (int t = 0; t < 3; ++t)
        ASSERT_EQ(test::runCommand("SLURM_ARRAY_TASK_ID=" + std::to_string(t) + " sh " + d + "/tiles.sbatch"), 0);
    EXPECT_EQ(std::filesystem::last_write_time(d + "/tile-0.vdb"), kept);
    EXPECT_TRUE(std::filesystem::exists(d + "/tile-1.vdb"));
    std::filesystem::remove(world);
    ASSERT_EQ(test::runCommand("sh " + d + "/merge.sbatch"), 0);
    EXPECT_TRUE(fileBytes(world) == fileBytes(whole));
    const test::CliRun status = runCli("slurm --status " + world);
    EXPECT_NE(status.output.find("3 of 3 tiles on disk"), std::string::npos) << status.output;
}

TEST(CliSlurm, PhotonBakesTileByBatchesAndGiveTheSingleBake) {
    test::TempDir dir;
    const std::string world = dir.file("world.vdb"), whole = dir.file("whole.vdb");
    const std::string opts = " --method photons --photons 40000 --resolution 6 --seed 4";
    ASSERT_EQ(runCli("bake " + kScene + " -q -o " + whole + opts).status, 0);
    const test::CliRun w = runCli("slurm " + kScene + " -o " + world + " --tiles 3" + opts);
    ASSERT_EQ(w.status, 0) << w.output;
    const std::string d = world + ".tiles";
    EXPECT_NE(fileBytes(d + "/tiles.sbatch").find("#SBATCH --array=0-2\n"), std::string::npos);
    for (int t = 0; t < 3; ++t)
        ASSERT_EQ(test::runCommand("SLURM_ARRAY_TASK_ID=" + std::to_string(t) + " sh " + d + "/tiles.sbatch"), 0);
    ASSERT_EQ(test::runCommand("sh " + d + "/merge.sbatch"), 0);
    EXPECT_TRUE(fileBytes(world) == fileBytes(whole)) << "merged photon world differs from the single bake";
}

TEST(CliSlurm, TheDefaultBakeIsAChainOfStagesThatGivesTheSingleBake) {
    // The default bake has a probe-to-probe pass: two job arrays, each followed by its merge,
    // the second array after the first merge (afterok), the second reading the merged stage 0.
    test::TempDir dir;
    const std::string world = dir.file("world.vdb"), whole = dir.file("whole.vdb");
    const std::string opts = " --resolution 10 --rays 16 --seed 4";
    ASSERT_EQ(runCli("bake " + kScene + " -q -o " + whole + opts).status, 0);
    const test::CliRun w = runCli("slurm " + kScene + " -o " + world + " --tiles 2" + opts);
    ASSERT_EQ(w.status, 0) << w.output;
    EXPECT_NE(w.output.find("stages S = 0..1"), std::string::npos) << w.output;
    const std::string d = world + ".tiles";
    const std::string submit = fileBytes(d + "/submit.sh");
    const std::size_t array1 = submit.find("sbatch --parsable $dep '" + d + "/tiles-1.sbatch'");
    ASSERT_NE(array1, std::string::npos) << submit;
    EXPECT_LT(submit.find("dep=--dependency=afterok:$mid"), array1) << submit;  // after the merge of stage 0
    EXPECT_NE(fileBytes(d + "/tiles-1.sbatch").find("--stage 1 --stage-input '" + d + "/stage-0.vdb'"), std::string::npos);
    auto runStage = [&](int s) {
        for (int t = 0; t < 2; ++t)
            ASSERT_EQ(test::runCommand("SLURM_ARRAY_TASK_ID=" + std::to_string(t) + " sh " + d + "/tiles-" + std::to_string(s) + ".sbatch"), 0);
        ASSERT_EQ(test::runCommand("sh " + d + "/merge-" + std::to_string(s) + ".sbatch"), 0);
    };
    runStage(0);
    runStage(1);
    EXPECT_TRUE(fileBytes(world) == fileBytes(whole)) << "merged world differs from the single bake";
    // Resumable in both stages: with a tile of stage 1 lost, the re-run chain bakes only it.
    std::filesystem::remove(d + "/stage-1-tile-0.vdb");
    std::filesystem::remove(world);
    const auto kept0 = std::filesystem::last_write_time(d + "/stage-0-tile-0.vdb");
    const auto kept1 = std::filesystem::last_write_time(d + "/stage-1-tile-1.vdb");
    runStage(0);
    runStage(1);
    EXPECT_EQ(std::filesystem::last_write_time(d + "/stage-0-tile-0.vdb"), kept0);
    EXPECT_EQ(std::filesystem::last_write_time(d + "/stage-1-tile-1.vdb"), kept1);
    EXPECT_TRUE(fileBytes(world) == fileBytes(whole));
    const test::CliRun status = runCli("slurm --status " + world);
    EXPECT_NE(status.output.find("2 of 2 tiles on disk in " + d + " (stage 1 of 0..1)"), std::string::npos) << status.output;
}

TEST(CliSlurm, RefusesOptionsItSetsItself) {
    test::TempDir dir;
    const std::string world = dir.file("w.vdb");
    test::expectRefusal("slurm " + kScene + " -o " + world + " --tiles 2 --tile 1", "set by vdblight slurm", world, "tile");
    test::expectRefusal("slurm " + kScene + " -o " + world + " --tiles 0", "--tiles must be at least 1", world, "zero");
    test::expectRefusal("slurm " + kScene + " -o " + world + " --tiles 2 --stage 1", "set by vdblight slurm", world, "stage");
    // What cannot be tiled is refused before any script is written.
    test::expectRefusal("slurm " + kScene + " -o " + world + " --tiles 2 --sampling antialiased", "cannot be tiled", world,
                        "antialiased");
    // The preview's guided probe pass and blend need both passes in one bake: a tiled preview
    // leaves them off (BakeRequest.PresetsResolve...), and refuses them when asked for.
    for (const char* flag : {"--guide-probe-directions", "--blend-first-pass"})
        test::expectRefusal("slurm " + kScene + " -o " + world + " --tiles 2 --quality preview " + flag, "cannot be tiled",
                            world, flag);
    EXPECT_FALSE(std::filesystem::exists(world + ".tiles"));
}

}  // namespace
}  // namespace vdblight
