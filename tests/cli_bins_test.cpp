// End-to-end: `vdblight bake --basis bins:N|moment:N`, `info` and `query` (with --view for
// moments) on the result, and bad bases refused with one line, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "cli_util.h"
#include "test_util.h"
#include "vdblight/basis/bins.h"
#include "query/bins_lookup.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

using test::CliRun;
using test::firstIrradiance;
using test::runCli;

TEST(CliBins, BinsAndMomentBakeInfoAndQuery) {
    test::TempDir dir;
    const std::string bins = dir.file("bins.vdb"), moment = dir.file("moment.vdb");
    CliRun r = runCli("bake -q -o " + bins + " --resolution 4 --rays 64 --bounces 1 --basis bins:4 --layout bilevel --refine 2");
    ASSERT_EQ(r.status, 0) << r.output;
    r = runCli("info " + bins);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("bins:4 (32 RGB channels"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("bin_h1_u3_v2"), std::string::npos) << r.output;

    // query = the library lookup on the file (the CLI adds nothing but I/O).
    const Volume v = readVolume(bins);
    const BinsLookup lookup(v, OutsidePolicy::Clamp);
    r = runCli("query " + bins + " --at 0.25,0.2,0.3 --normal 0.2,1,0.1");
    ASSERT_EQ(r.status, 0) << r.output;
    const double expected = lookup.irradiance(Vec3f(0.25f, 0.2f, 0.3f), normalize(Vec3f(0.2f, 1, 0.1f))).x;
    EXPECT_NEAR(firstIrradiance(r.output), expected, 1e-6 * (1 + expected));
    EXPECT_NE(runCli("query " + bins + " --at 0.25,0.2,0.3 --view 0,1,0").status, 0);  // --view needs a moment volume

    r = runCli("bake -q -o " + moment + " --resolution 3 --rays 32 --bounces 1 --basis moment:4:4");
    ASSERT_EQ(r.status, 0) << r.output;
    const Volume m = readVolume(moment);
    EXPECT_EQ(m.basis.kind, "moment:4");
    const BinsLookup ml(m, OutsidePolicy::Clamp);
    const Vec3f n = normalize(Vec3f(0, 1, 0.3f)), view = normalize(Vec3f(0.5f, 1, 0));
    const Vec3f reflected = normalize(bins::reflectView(view, n));
    r = runCli("query " + moment + " --at 0.3,0.25,0.2 --normal 0,1,0.3 --view 0.5,1,0");
    ASSERT_EQ(r.status, 0) << r.output;
    const double e = ml.irradiance(Vec3f(0.3f, 0.25f, 0.2f), reflected).x;
    EXPECT_NEAR(firstIrradiance(r.output), e, 1e-6 * (1 + e));
    r = runCli("query " + moment + " --at 0.3,0.25,0.2 --normal 0,1,0");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("needs --view"), std::string::npos) << r.output;
}

TEST(CliBins, BadBasesAreRefusedWithOneLineAndNoFile) {
    test::TempDir dir;
    const std::string base = "bake --resolution 3 --rays 8";
    test::expectCleanFailureWithOutput(dir, base + " --basis bins:0", "at least 1");
    test::expectCleanFailureWithOutput(dir, base + " --basis bins:x", "positive integer");
    test::expectCleanFailureWithOutput(dir, base + " --basis wavelets", "--basis must be sh2, sh:N, bins:N or moment:N");
    test::expectCleanFailureWithOutput(dir, base + " --basis moment:0", "at least 1");
    test::expectCleanFailureWithOutput(dir, base + " --basis bins:4 --method photons", "--basis bins/moment works with --method gather");
    test::expectCleanFailureWithOutput(dir, base + " --basis bins:4 --sampling antialiased", "--basis bins/moment works with");
}
