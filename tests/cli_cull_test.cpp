// End-to-end: `vdblight bake --cull-solids` (solid_cull.h) and `--refine-distance`: the
// summary, `info` and `query` of a culled volume (a point inside a Cornell block reads 0
// with a warning, a free point reads light), and bad options refused cleanly.
#include <gtest/gtest.h>

#include "cli_util.h"
#include "test_util.h"

using namespace vdblight;

using test::CliRun;
using test::firstIrradiance;
using test::runCli;

TEST(CliCull, CulledBakeInfoAndQuery) {
    test::TempDir dir;
    const std::string out = dir.file("culled.vdb");
    const CliRun bake = runCli("bake -o " + out + " --resolution 12 --rays 16 --bounces 1 --layout bilevel --cull-solids");
    ASSERT_EQ(bake.status, 0) << bake.output;
    EXPECT_NE(bake.output.find("Solid culling: "), std::string::npos) << bake.output;
    EXPECT_EQ(bake.output.find("Solid culling: 0 of"), std::string::npos) << bake.output;
    const CliRun info = runCli("info " + out);
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("culled inside closed solids"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("culling = solid-regions"), std::string::npos) << info.output;
    const CliRun inside = runCli("query " + out + " --at 0.37,0.15,0.35 --normal 0,1,0");  // inside the tall block
    ASSERT_EQ(inside.status, 0) << inside.output;
    EXPECT_EQ(firstIrradiance(inside.output), 0.0);
    EXPECT_NE(inside.output.find("inside closed solids"), std::string::npos) << inside.output;
    const CliRun free = runCli("query " + out + " --at 0.278,0.4,0.28 --normal 0,1,0");
    ASSERT_EQ(free.status, 0) << free.output;
    EXPECT_GT(firstIrradiance(free.output), 0.5);
    EXPECT_EQ(free.output.find("inside closed solids"), std::string::npos) << free.output;
}

TEST(CliCull, BadOptionsFailCleanly) {
    test::TempDir dir;
    test::expectCleanFailuresWithOutput(dir, {
        {"bake --cull-solids", "--cull-solids needs --layout bilevel or adaptive"},
        {"bake --layout bilevel --basis bins:4 --cull-solids", "--basis sh2"},
        {"bake --layout adaptive --refine-distance -0.1", "--refine-distance must be"},
        {"bake --layout adaptive --refine-distance nan", "--refine-distance"},
        {"bake --refine-distance 0.1", "--refine-distance needs --layout"},
        // Refused at the first refinement's estimate (with --refine 8 --resolution 64 the
        // estimate came after placing level 0's 262 144 cells: 11 s under ASan).
        {"bake --layout adaptive --levels 3 --refine 16 --resolution 24 --refine-distance 5", "MiB"}
    });
}

TEST(CliCull, RefineDistanceRefinesMore) {
    test::TempDir dir;
    const CliRun plain = runCli("bake -o " + dir.file("a.vdb") + " --resolution 6 --rays 4 --bounces 0 --layout bilevel");
    const CliRun wide = runCli("bake -o " + dir.file("b.vdb") +
                               " --resolution 6 --rays 4 --bounces 0 --layout bilevel --refine-distance 0.05");
    ASSERT_EQ(plain.status, 0) << plain.output;
    ASSERT_EQ(wide.status, 0) << wide.output;
    const CliRun info = runCli("info " + dir.file("b.vdb"));
    EXPECT_NE(info.output.find("refine_distance = 0.05"), std::string::npos) << info.output;
    const auto nodes = [](const std::string& out) { return std::stoll(out.substr(out.find("Baked ") + 6)); };
    EXPECT_GT(nodes(wide.output), nodes(plain.output));
}
