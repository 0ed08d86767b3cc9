// End-to-end: `vdblight bake --layout bilevel|adaptive`, `info` and `query` on the result,
// and bad layout options refused with one line, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <sstream>

#include "cli_util.h"
#include "test_util.h"

using namespace vdblight;
namespace fs = std::filesystem;

using test::CliRun;
using test::firstIrradiance;
using test::runCli;

TEST(CliLayouts, BilevelAndAdaptiveBakeInfoAndQuery) {
    test::TempDir dir;
    for (const std::string layout : {"bilevel", "adaptive"}) {
        const std::string out = dir.file(layout + ".vdb");
        const CliRun bake = runCli("bake -o " + out + " --resolution 5 --rays 32 --bounces 2 --layout " + layout +
                                   (layout == "adaptive" ? " --levels 3 --refine 2" : ""));
        ASSERT_EQ(bake.status, 0) << bake.output;
        EXPECT_NE(bake.output.find("Layout " + layout), std::string::npos) << bake.output;
        const CliRun info = runCli("info " + out);
        ASSERT_EQ(info.status, 0) << info.output;
        EXPECT_NE(info.output.find("refined_L0"), std::string::npos) << info.output;
        EXPECT_NE(info.output.find("active nodes"), std::string::npos) << info.output;
        const CliRun json = runCli("info --json " + out);
        EXPECT_NE(json.output.find("\"layout\": \"" + layout + "\""), std::string::npos) << json.output;
        const CliRun up = runCli("query " + out + " --at 0.278,0.1,0.28 --normal 0,1,0");
        ASSERT_EQ(up.status, 0) << up.output;
        EXPECT_GT(firstIrradiance(up.output), 0.5);  // under the ceiling light
    }
}

TEST(CliLayouts, BadLayoutOptionsFailCleanly) {
    test::TempDir dir;
    test::expectCleanFailuresWithOutput(dir, {
        {"bake --layout bilevel --refine 1", "--refine must be at least 2"},
        {"bake --layout adaptive --refine 0", "--refine must be at least 2"},
        {"bake --layout adaptive --levels 0", "--levels must be at least 1"},
        {"bake --layout adaptive --levels 1000", "absurd"},
        {"bake --layout adaptive --levels 14 --refine 8", "index range"},
        {"bake --layout adaptive --levels 4 --refine 8 --resolution 20", "MiB"},
        {"bake --layout octree", "unknown layout 'octree'"},
        {"bake --refine 3", "--refine needs --layout"},
        {"bake --layout bilevel --levels 3", "--levels needs --layout adaptive"}
    });
}
