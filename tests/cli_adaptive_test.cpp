// End-to-end: `vdblight bake --target-error` and `--sh-window`, summary and metadata, and bad options
// refused with one line, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_util.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;

int countLines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}
}  // namespace

TEST(CliAdaptive, BakesToTheTargetAndReportsIt) {
    test::TempDir dir;
    const std::string out = dir.file("a.vdb");
    std::string text;
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 4 --target-error 0.05 --max-rays 1024 -o " + out, &text))
        << text;
    EXPECT_NE(text.find("Error-targeted: relative standard error"), std::string::npos) << text;
    EXPECT_NE(text.find("saved against 1024 rays on every node"), std::string::npos) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_NE(text.find("target_error = 0.05"), std::string::npos) << text;
    EXPECT_NE(text.find("estimated_error_p95"), std::string::npos) << text;
    EXPECT_NE(text.find("samples_saved_vs_max"), std::string::npos) << text;
}

TEST(CliAdaptive, RefusesBadOptions) {
    test::TempDir dir;
    const std::string out = dir.file("bad.vdb");
    for (const std::string args : {"--target-error 0", "--target-error 2", "--rays 64 --max-rays 100",
                                   "--quality preview --min-rays 16", "--quality best", "--target-error 0.1 --rays 64",
                                   "--rays 16 --probe-passes 1 --sampling antialiased",
                                   "--target-error 0.1 --min-rays 1", "--target-error 0.1 --min-rays 128 --max-rays 64",
                                   "--target-error 0.1 --sampling antialiased", "--target-error 0.1 --layout bilevel",
                                   "--target-error 0.1 --method photons"}) {
        std::string text;
        const int status = test::runCommand(kCli + " bake --resolution 2 " + args + " -o " + out, &text);
        EXPECT_NE(status, 0) << args;
        EXPECT_LT(status, 128) << "crashed: " << args;
        EXPECT_EQ(countLines(text), 1) << args << "\n" << text;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

// Issue 15: the default bake is 1024 rays + one probe-to-probe pass with depth moments and SH order 4,
// --quality preview the fixed 256 rays of full paths, high is error-targeted with two probe
// passes; every point gather prints and stores its per-node noise; the default transport has no bounce cap in effect.
TEST(CliQuality, PresetsAndNoiseSummary) {
    test::TempDir dir;
    const std::string out = dir.file("q.vdb");
    std::string text;
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 3 -o " + out, &text)) << text;
    // The default (issue 15, docs/methods.md "The default bake"): 1024 rays + a probe pass,
    // depth moments and SH order 4 (--resolution here replaces its node budget).
    EXPECT_NE(text.find("with 1024 rays per node (+ 1 probe-to-probe pass) and all bounces (Russian roulette)"),
              std::string::npos) << text;
    EXPECT_NE(text.find("(basis sh:4: radiance SH coefficients, bands 0..4, 25 Vec3f grids)"), std::string::npos) << text;
    EXPECT_NE(text.find("Depth moments: from the gather's own first hits"), std::string::npos) << text;
    EXPECT_NE(text.find("Noise per node"), std::string::npos) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_NE(text.find("rays_per_node = 1024"), std::string::npos) << text;
    EXPECT_NE(text.find("probe_passes = 1"), std::string::npos) << text;
    EXPECT_NE(text.find("estimated_error_worst_nodes"), std::string::npos) << text;
    EXPECT_NE(text.find("bounces = 1024"), std::string::npos) << text;

    // preview (issue 32): 64 rays + the probe pass, SH order 4, one pass of the node filter, more
    // paths for the surface cache where pass 0 is noisiest.
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 3 --quality preview -o " + out, &text)) << text;
    EXPECT_NE(text.find("with 64 rays per node (+ 1 probe-to-probe pass) and all bounces"), std::string::npos) << text;
    EXPECT_NE(text.find("(basis sh:4: radiance SH coefficients, bands 0..4, 25 Vec3f grids)"), std::string::npos) << text;
    EXPECT_NE(text.find("Noise per node"), std::string::npos) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_NE(text.find("rays_per_node = 64"), std::string::npos) << text;
    EXPECT_NE(text.find("estimated_error_p95"), std::string::npos) << text;
    EXPECT_NE(text.find("node_filter_passes = 1"), std::string::npos) << text;
    EXPECT_NE(text.find("extra_cache_paths = 256 more paths"), std::string::npos) << text;
    EXPECT_NE(text.find("first_pass_rays = 16 rays at every node"), std::string::npos) << text;
    // The default has no node filter.
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 2 --rays 8 -q -o " + out, &text)) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_EQ(text.find("node_filter"), std::string::npos) << text;

    // high: the default with twice the rays (SH order 4, one probe pass).
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 2 --quality high -o " + out, &text)) << text;
    EXPECT_NE(text.find("with 2048 rays per node (+ 1 probe-to-probe pass)"), std::string::npos) << text;
    EXPECT_NE(text.find("basis sh:4"), std::string::npos) << text;
    // An error target (SH order 2, the adaptive pass) is an option of any preset.
    ASSERT_EQ(0, test::runCommand(kCli + " bake --resolution 2 --target-error 0.03 --max-rays 256 -o " + out, &text)) << text;
    EXPECT_NE(text.find("Error-targeted: relative standard error"), std::string::npos) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_NE(text.find("target_error = 0.03"), std::string::npos) << text;
    EXPECT_NE(text.find("probe_passes = 1"), std::string::npos) << text;
    EXPECT_NE(text.find("basis: sh2"), std::string::npos) << text;
}

TEST(CliShWindow, RecordsTheWindowAndRefusesPhotons) {
    test::TempDir dir;
    const std::string out = dir.file("w.vdb");
    std::string text;
    ASSERT_EQ(0, test::runCommand(kCli + " bake -q --resolution 3 --rays 16 --sh-window -o " + out, &text)) << text;
    ASSERT_EQ(0, test::runCommand(kCli + " info " + out, &text)) << text;
    EXPECT_NE(text.find("sh_window = non-negative spline window"), std::string::npos) << text;
    const std::string bad = dir.file("bad.vdb");
    EXPECT_NE(0, test::runCommand(kCli + " bake --method photons --sh-window -o " + bad, &text));
    EXPECT_EQ(countLines(text), 1) << text;
    EXPECT_FALSE(fs::exists(bad));
}
