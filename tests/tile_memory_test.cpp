// Tile-local memory (issue 17; docs/scaling.md): a tile holds only the window of nodes it
// spans, not the whole volume. The real program is run in child processes and its peak
// resident memory read from getrusage (ru_maxrss via wait4): a tile's memory above the
// program's fixed part (the same bake on a 2^3 grid) must be a fraction of the whole bake's.
// Before tile-local allocation a stage-0 tile of 8 held 0.94 of the whole bake's (970 200 nodes).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "test_util.h"

namespace vdblight::test {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

/// Runs `vdblight ARGS` (split at spaces, no shell, so that the rusage is the program's own);
/// returns its peak resident bytes; fails the test on a non-zero exit.
double peakBytes(const std::string& args) {
    std::vector<std::string> words;
    std::istringstream in(args);
    for (std::string w; in >> w;) words.push_back(w);
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv{const_cast<char*>(cliPath().c_str())};
        for (auto& w : words) argv.push_back(w.data());
        argv.push_back(nullptr);
        if (!freopen("/dev/null", "w", stdout)) _exit(126);
        execv(cliPath().c_str(), argv.data());
        _exit(127);
    }
    int status = 0;
    rusage usage{};
    wait4(pid, &status, 0, &usage);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "vdblight " << args;
    return double(usage.ru_maxrss) * 1024.0;  // kilobytes on Linux
}

TEST(TileMemory, ATileOfTheDefaultBakeHoldsAFractionOfTheWholeVolume) {
#ifdef VDBLIGHT_SANITIZED
    // Peak RSS under ASan is mostly its shadow memory and quarantine (freed blocks kept back),
    // not the tile's arrays; the tile windows' code runs under ASan in the CLI tiles tests, and
    // this measurement in the normal suite (26 bakes: 56 s of the sanitizer stage's CTest).
    GTEST_SKIP() << "under AddressSanitizer: peak RSS measures its shadow memory and quarantine, not the tile";
#endif
    const TempDir dir;
    const std::string scene = std::string(VDBLIGHT_SOURCE_DIR) + "/data/cornell_box.obj";
    // The default bake (a probe pass: stages 0 and 1, --direct occlusion, depth moments) on
    // 64^3 nodes with 1 ray: memory, not tracing.
    const std::string opts = scene + " --seed 3 --rays 1 --threads 2 -q";
    const double base = peakBytes("bake " + opts + " --resolution 2 -o " + dir.file("base.vdb"));
    const double whole = peakBytes("bake " + opts + " --resolution 64 -o " + dir.file("whole.vdb"));
    std::vector<double> stage0, stage1;
    for (int t : {0, 3, 7})
        stage0.push_back(peakBytes("bake " + opts + " --resolution 64 --tiles 8 --tile " + std::to_string(t) +
                                   " --stage 0 -o " + dir.file("s0_" + std::to_string(t) + ".vdb")));
    // Stage 1 needs every node of stage 0 (its probe cache): the tiles made above plus the rest.
    std::string tiles;
    for (int t = 0; t < 8; ++t) {
        const std::string f = dir.file("s0_" + std::to_string(t) + ".vdb");
        peakBytes("bake " + opts + " --resolution 64 --tiles 8 --tile " + std::to_string(t) + " --stage 0 -o " + f);
        tiles += " " + f;
    }
    peakBytes("merge -q" + tiles + " -o " + dir.file("stage0.vdb"));
    for (int t : {0, 3, 7})
        stage1.push_back(peakBytes("bake " + opts + " --resolution 64 --tiles 8 --tile " + std::to_string(t) + " --stage 1 --stage-input " +
                                   dir.file("stage0.vdb") + " -o " + dir.file("s1_" + std::to_string(t) + ".vdb")));
    const double wholeExtra = whole - base;
    std::cout << "peak RSS: fixed part (2^3 nodes) " << base / kMiB << " MiB, whole bake (262 144 nodes) " << whole / kMiB
              << " MiB; tiles 0, 3, 7 of 8, stage 0:";
    for (double b : stage0) std::cout << ' ' << b / kMiB;
    std::cout << " MiB, stage 1:";
    for (double b : stage1) std::cout << ' ' << b / kMiB;
    std::cout << " MiB\n";
    ASSERT_GT(wholeExtra, 20 * kMiB);  // the volume must dominate for the ratios to mean anything
    // Since the default guides its probe pass and blends pass 0 in (issue 32, session 22), a
    // stage-0 tile also carries pass 0's direction map, values and errors (bake/stage_carry.h:
    // 1 452 B per node against the whole bake's ~375 B written), a few copies of it over its
    // window: measured 0.50-0.52 of the whole bake's (0.16 before; a tile that allocated the
    // whole volume would be at 1 or more).
    for (double b : stage0) EXPECT_LT(b - base, 0.6 * wholeExtra) << "a stage-0 tile holds most of the whole volume";
    // A later stage reads the stage input over its window and the guide's pooling reach only
    // (bake_volume.cpp, stageInputWindow): measured 0.25-0.28 of the whole bake's (0.96 when it
    // read every node's pass-0 carry; 0.60 before the carry, when it read every node's 124 B).
    for (double b : stage1) EXPECT_LT(b - base, 0.45 * wholeExtra) << "a stage-1 tile holds most of the whole volume";
}

}  // namespace
}  // namespace vdblight::test
