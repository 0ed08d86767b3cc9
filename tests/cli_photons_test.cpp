// End-to-end tests of `vdblight bake --method photons` and `query --interp` / `--iv-blend`: a
// photon bake that info and query read, and bad input (one line, non-zero exit, no file).
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_util.h"
#include "test_util.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
using namespace vdblight::test;
namespace fs = std::filesystem;

namespace {
/// E_r of a one-point query's CSV row.
double firstIrradiance(const CliRun& q) {
    const std::string row = q.output.substr(q.output.find('\n') + 1);
    double vals[9] = {};
    EXPECT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &vals[0], &vals[1], &vals[2], &vals[3],
                          &vals[4], &vals[5], &vals[6], &vals[7], &vals[8]),
              9)
        << q.output;
    return vals[6];
}

// Under the ceiling light, facing up: lit; both interpolations answer.
void expectLitWithBothInterpolations(const std::string& volume) {
    for (const char* interp : {"trilinear", "tricubic"}) {
        const CliRun q = runCli("query " + volume + " --at 0.28,0.45,0.2 --normal 0,1,0 --interp " + interp);
        ASSERT_EQ(q.status, 0) << q.output;
        const std::string row = q.output.substr(q.output.find('\n') + 1);
        double vals[9];
        ASSERT_EQ(std::sscanf(row.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &vals[0], &vals[1], &vals[2], &vals[3],
                              &vals[4], &vals[5], &vals[6], &vals[7], &vals[8]),
                  9)
            << q.output;
        EXPECT_GT(vals[6], 0.5) << interp;
    }
}
}  // namespace

TEST(CliPhotons, BakeInfoQueryOnTheDefaultScene) {
    test::TempDir dir;
    const std::string out = dir.file("photons.vdb");
    const CliRun bake = runCli("bake --method photons --photons 100000 --resolution 6 -o " + out);
    ASSERT_EQ(bake.status, 0) << bake.output;
    EXPECT_NE(bake.output.find("photons/s"), std::string::npos) << bake.output;
    EXPECT_NE(bake.output.find("face crossings"), std::string::npos) << bake.output;
    EXPECT_NE(bake.output.find("Depth moments: "), std::string::npos) << bake.output;  // the default's
    const Volume v = readVolume(out);
    EXPECT_EQ(v.basis.kind, "irradiance_vectors");
    EXPECT_EQ(v.basis.channelCount(), 18);
    EXPECT_EQ(metaString(v.meta, "method"), "photons");
    EXPECT_EQ(metaNumber(v.meta, "photons", 0), 100000);

    const CliRun info = runCli("info " + out);
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("iv_ypos_r"), std::string::npos) << info.output;
    ASSERT_NO_FATAL_FAILURE(expectLitWithBothInterpolations(out));

    // --iv-blend: the default (quadratic) and the paper's n^2 blend agree for an axis normal;
    // for a diagonal one the paper's, a lower bound of E, reads less.
    const std::string at = "query " + out + " --at 0.28,0.3,0.25 ";
    const CliRun qAxis = runCli(at + "--normal 0,1,0"), pAxis = runCli(at + "--normal 0,1,0 --iv-blend paper");
    const CliRun qDiag = runCli(at + "--normal 1,1,1"), pDiag = runCli(at + "--normal 1,1,1 --iv-blend paper");
    ASSERT_EQ(qAxis.status + pAxis.status + qDiag.status + pDiag.status, 0) << pDiag.output;
    EXPECT_NEAR(firstIrradiance(pAxis), firstIrradiance(qAxis), 1e-5 * firstIrradiance(qAxis));
    EXPECT_LT(firstIrradiance(pDiag), 0.95 * firstIrradiance(qDiag));
}

TEST(CliPhotons, CompactBakeIsSmallerAndReadable) {
    test::TempDir dir;
    const std::string full = dir.file("full.vdb"), compact = dir.file("compact.vdb");
    // Resolution 16: enough nodes that the grids' data, not their headers, make the file.
    ASSERT_EQ(runCli("bake --method photons --photons 50000 --resolution 16 -q -o " + full).status, 0);
    const CliRun bake = runCli("bake --method photons --photons 50000 --resolution 16 --compact -o " + compact);
    ASSERT_EQ(bake.status, 0) << bake.output;
    EXPECT_NE(bake.output.find("compact"), std::string::npos) << bake.output;
    const Volume v = readVolume(compact);
    EXPECT_EQ(v.basis.kind, "irradiance_vectors_compact");
    EXPECT_EQ(v.basis.channelCount(), 12);
    EXPECT_LT(fs::file_size(compact) * 2, fs::file_size(full));  // 72 vs 216 bytes per node, plus headers
    const CliRun info = runCli("info " + compact);
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("ivc_ypos_rgb"), std::string::npos) << info.output;
    ASSERT_NO_FATAL_FAILURE(expectLitWithBothInterpolations(compact));
    expectCleanFailure(dir, "bake --compact --resolution 3 --rays 8 -o " + dir.file("sh.vdb"),
                       "--compact applies to --method photons only");
}

TEST(CliPhotons, BadInputFailsCleanly) {
    test::TempDir dir;
    const std::string out = dir.file("bad.vdb");
    expectCleanFailure(dir, "bake --method photons --photons 0 -o " + out, "photon count must be at least 1");
    expectCleanFailure(dir, "bake --method photons --photons 900000000000000 -o " + out, "hours");
    expectCleanFailure(dir, "bake --method fotons -o " + out, "--method must be gather or photons");
    // A scene without light (a tetrahedron, no emitters, black sky), even with --allow-dark.
    const std::string obj = dir.file("dark.obj");
    test::writeTextFile(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    expectCleanFailure(dir, "bake --method photons --allow-dark --photons 1000 " + obj + " -o " + out, "no light");
    // An invalid interpolation name, and tricubic on an SH volume.
    const std::string sh = dir.file("sh.vdb");
    ASSERT_EQ(runCli("bake --resolution 3 --rays 8 -q -o " + sh).status, 0);
    expectCleanFailure(dir, "query " + sh + " --at 0.3,0.3,0.3 --interp cubic", "--interp must be trilinear or tricubic");
    expectCleanFailure(dir, "query " + sh + " --at 0.3,0.3,0.3 --interp tricubic", "needs an irradiance-vector volume");
    expectCleanFailure(dir, "query " + sh + " --at 0.3,0.3,0.3 --iv-blend paper", "needs an irradiance-vector volume");
    expectCleanFailure(dir, "query " + sh + " --at 0.3,0.3,0.3 --iv-blend cubic", "--iv-blend");
}
