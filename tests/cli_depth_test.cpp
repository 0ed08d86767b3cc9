// End-to-end: `vdblight bake --depth-moments` (uniform, bilevel, anti-aliased), the depth grids
// in the file, `query` with and without `--no-depth-weights`, `export` writing the depth
// textures, and bad combinations refused with one line, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>

#include "cli_util.h"
#include "manifest_util.h"
#include "test_util.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;

using test::CliRun;
using test::runCli;

TEST(CliDepth, BakeWithDepthMomentsQueriesAndExports) {
    test::TempDir dir;
    for (const std::string extra : {"", "--layout bilevel --refine 2", "--sampling antialiased"}) {
        const std::string out = dir.file("d.vdb");
        const CliRun bake = runCli("bake -o " + out + " --resolution 6 --rays 32 --bounces 2 --depth-moments " + extra);
        ASSERT_EQ(bake.status, 0) << bake.output;
        EXPECT_NE(bake.output.find("Depth moments:"), std::string::npos) << bake.output;
        const Volume v = readVolume(out);
        EXPECT_TRUE(v.hasDepth()) << extra;
        const CliRun info = runCli("info " + out);
        EXPECT_NE(info.output.find("depth_mean_pos"), std::string::npos) << info.output;
        // Points near the tall box of the Cornell box, where some corners lie inside it.
        const std::string csv = dir.file("p.csv");
        {
            std::ofstream f(csv);
            f << "x,y,z,nx,ny,nz\n";
            for (int i = 0; i < 40; ++i) f << 0.05 + 0.012 * i << ",0.2," << 0.35 + 0.004 * i << ",0,1,0\n";
        }
        const CliRun weighted = runCli("query " + out + " --points " + csv);
        const CliRun plain = runCli("query " + out + " --points " + csv + " --no-depth-weights");
        ASSERT_EQ(weighted.status, 0) << weighted.output;
        ASSERT_EQ(plain.status, 0) << plain.output;
        EXPECT_NE(weighted.output, plain.output) << extra;  // the weights change some answers
        if (extra.rfind("--layout", 0) != 0) continue;
        // A bilevel volume exports its depth on the finest lattice, and an engine's weighted
        // blend of the texels (docs/engine_visibility.md) gives the query's answer: exactly wherever the
        // texel cells are the lookup's cells, within 2 % in the rare texel cells at the edge of
        // an unrefined cell next to geometry (docs/methods.md; without the depth textures the
        // plain blend was 30 % off near the walls).
        const std::string ex = dir.file("ex_levels");
        ASSERT_EQ(runCli("export -q --float " + out + " -o " + ex).status, 0);
        std::string log;
        EXPECT_EQ(test::runCommand("/usr/bin/python3 " + std::string(VDBLIGHT_SOURCE_DIR) + "/scripts/check_export.py --cli " +
                                       test::cliPath() + " --volume " + out + " --export " + ex + " --points 2000 --tolerance 0.02",
                                   &log),
                  0)
            << log;
    }
    const std::string uniform = dir.file("u.vdb");
    ASSERT_EQ(runCli("bake -o " + uniform + " --resolution 5 --rays 16 --bounces 1 --depth-moments -q").status, 0);
    const CliRun ex = runCli("export " + uniform + " -o " + dir.file("ex") + " --format raw");
    ASSERT_EQ(ex.status, 0) << ex.output;
    // The depth textures are RGBA8 unorm (the lighting ones half): every byte / 255 is the
    // bake's stored value exactly.
    const Volume baked = readVolume(uniform);
    const VolumeLevel& level = baked.levels.at(0);
    const int channel[4] = {depth::kMeanPositive, depth::kMeanNegative, depth::kSigmaPositive, depth::kSigmaNegative};
    for (int a = 0; a < 3; ++a) {
        const std::string name = std::string("depth_") + "xyz"[a];
        std::ifstream in(dir.file("ex") + "/" + name + ".raw", std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_EQ(bytes.size(), level.grid.nodeCount() * 4) << name;
        for (std::size_t n = 0; n < level.grid.nodeCount(); ++n)
            for (int c = 0; c < 4; ++c)
                EXPECT_EQ(float(uint8_t(bytes[n * 4 + std::size_t(c)]) / 255.0), level.nodeDepth(n)[channel[c] * 3 + a])
                    << name << " node " << n << " component " << c;
    }
    const nlohmann::json depth = test::readManifest(dir.file("ex"))["depth"];
    EXPECT_EQ(depth["format"], "rgba8_unorm") << depth;
    EXPECT_EQ(depth["bytes_per_node"], 12) << depth;
}

// Point gather and photon volumes (full and compact form) with depth moments open where users
// open them: pyopenvdb and Blender.
TEST(CliDepth, FileWithDepthOpensInPyopenvdbAndBlender) {
    test::TempDir dir;
    const std::string source = VDBLIGHT_SOURCE_DIR;
    const std::vector<std::string> bakes = {"--rays 16", "--method photons --photons 20000",
                                            "--method photons --photons 20000 --compact"};
    for (std::size_t b = 0; b < bakes.size(); ++b) {
        const std::string out = dir.file("depth" + std::to_string(b) + ".vdb");
        ASSERT_EQ(runCli("bake -q -o " + out + " --resolution 4 --depth-moments " + bakes[b]).status, 0) << bakes[b];
        std::string output;
        EXPECT_EQ(test::runCommand("/usr/bin/python3 " + source + "/scripts/check_pyopenvdb.py " + out + " --depth", &output), 0)
            << output;
        if (std::getenv("VDBLIGHT_SKIP_BLENDER")) continue;
        EXPECT_EQ(test::runCommand("blender -b --factory-startup --python " + source + "/scripts/check_blender.py -- " + out,
                                   &output),
                  0)
            << output;
    }
}

TEST(CliDepth, BadDepthOptionsFailCleanly) {
    test::TempDir dir;
    test::expectCleanFailuresWithOutput(dir, {
        // Depth moments are on by default (--quality default and preview), off with --no-depth-moments.
        {"bake --depth-rays 64 --no-depth-moments", "--depth-rays needs --depth-moments"},
        {"bake --depth-rays 64 --quality preview --no-depth-moments", "--depth-rays needs --depth-moments"},
        {"bake --depth-rays 64 --method photons --photons 20000 --no-depth-moments", "--depth-rays needs --depth-moments"},
    });
    const std::string plain = dir.file("plain.vdb");
    ASSERT_EQ(runCli("bake -o " + plain + " --resolution 3 --rays 8 --bounces 1 -q --no-depth-moments").status, 0);
    test::expectCleanFailure(dir, "query " + plain + " --at 0.2,0.2,0.2 --no-depth-weights", "has no depth moments");
}

// The default bake (issue 15) stores depth moments and its lookups are weighted by them, the
// photon pass's too; the point gather's --quality preview too since issue 32 (its node filter
// reads them), not the photon pass's preview; --no-depth-moments leaves them out.
TEST(CliDepth, OnByDefaultAndInThePreviewOffWithNoDepthMoments) {
    test::TempDir dir;
    const std::string common = " --resolution 4 --rays 16 --bounces 1 -q";
    const std::string byDefault = dir.file("default.vdb"), preview = dir.file("preview.vdb"), off = dir.file("off.vdb");
    ASSERT_EQ(runCli("bake -o " + byDefault + common).status, 0);
    ASSERT_EQ(runCli("bake -o " + preview + common + " --quality preview").status, 0);
    ASSERT_EQ(runCli("bake -o " + off + common + " --no-depth-moments").status, 0);
    EXPECT_TRUE(readVolume(byDefault).hasDepth());
    EXPECT_TRUE(readVolume(preview).hasDepth());
    EXPECT_FALSE(readVolume(off).hasDepth());
    // The photon pass takes the preset's depth moments (on with default and high, as its grid),
    // but not with preview or --no-depth-moments.
    const std::string photons = " --method photons --photons 20000 --resolution 4 -q";
    const std::string photonsPreview = dir.file("photons_preview.vdb"), photonsOff = dir.file("photons_off.vdb");
    ASSERT_EQ(runCli("bake -o " + photonsPreview + photons + " --quality preview").status, 0);
    ASSERT_EQ(runCli("bake -o " + photonsOff + photons + " --no-depth-moments").status, 0);
    EXPECT_FALSE(readVolume(photonsPreview).hasDepth());
    EXPECT_FALSE(readVolume(photonsOff).hasDepth());
    // By default (and with --quality high) the photon volume has them (full and compact), and
    // query weights by them.
    const std::string photonsHigh = dir.file("photons_high.vdb");
    ASSERT_EQ(runCli("bake -o " + photonsHigh + photons + " --quality high").status, 0);
    EXPECT_TRUE(readVolume(photonsHigh).hasDepth());
    for (const std::string form : {"", " --compact"}) {
        const std::string withDepth = dir.file("photons_depth.vdb");
        ASSERT_EQ(runCli("bake -o " + withDepth + photons + form).status, 0);
        EXPECT_TRUE(readVolume(withDepth).hasDepth()) << form;
        EXPECT_EQ(runCli("query " + withDepth + " --at 0.2,0.2,0.2 --no-depth-weights").status, 0) << form;
        if (!form.empty()) continue;
        // Exported with the depth textures, read back from the manifest alone with the
        // depth-weighted blend of docs/engine_visibility.md: the same irradiance as `query`.
        const std::string ex = dir.file("photons_ex");
        ASSERT_EQ(runCli("export -q " + withDepth + " -o " + ex + " --layout vectors").status, 0);
        EXPECT_EQ(test::readManifest(ex)["depth"]["exported"], true);
        std::string log;
        EXPECT_EQ(test::runCommand("/usr/bin/python3 " + std::string(VDBLIGHT_SOURCE_DIR) + "/scripts/check_export.py --cli " +
                                       test::cliPath() + " --volume " + withDepth + " --export " + ex,
                                   &log),
                  0)
            << log;
    }
}
