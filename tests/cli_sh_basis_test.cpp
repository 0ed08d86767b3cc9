// End-to-end: `vdblight bake --basis sh:3` -> .vdb -> `info`, `query` (= the library lookup on
// the file), `export --layout basis` (the node values in the raw textures), and bad sh:N
// specs refused with one line, a non-zero exit and no file. The default bake (sh:4 on a
// uniform grid): the point gather with the default preset (rays, probe pass, depth moments,
// direct light with visibility), whose SH order-2 export layouts hold its bands 0..2, as
// `query --sh-order 2` does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cli_util.h"
#include "manifest_util.h"
#include "test_util.h"
#include "vdblight/basis/basis.h"
#include "volume/sh_truncate.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
using test::CliRun;
using test::runCli;

namespace {
std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
}  // namespace

TEST(CliShBasis, BakeInfoQueryAndExportOfShThree) {
    test::TempDir dir;
    const std::string file = dir.file("sh3.vdb");
    CliRun r = runCli("bake -o " + file + " --resolution 4 --rays 128 --bounces 2 --basis sh:3");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("basis sh:3: radiance SH coefficients, bands 0..3, 16 Vec3f grids"), std::string::npos) << r.output;
    const Volume v = readVolume(file);
    EXPECT_EQ(v.basis.kind, "sh:3");
    ASSERT_EQ(v.basis.channelCount(), 16);
    EXPECT_EQ(v.basis.channelNames[9], "sh_l3m_neg3");
    EXPECT_EQ(metaNumber(v.meta, "rays_per_node", 0), 128);  // the point gather (uniform grid): as given

    r = runCli("info " + file);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("sh:3 (16 RGB channels: radiance SH coefficients, bands 0..3)"), std::string::npos) << r.output;

    const IrradianceQuery q(v);
    const Vec3f x(0.1f, 0.3f, -0.05f), n = normalize(Vec3f(0.3f, 1.0f, -0.2f));
    const Rgb want = q.irradiance(x, n);
    ASSERT_GT(want.x, 0.01f);
    r = runCli("query " + file + " --at 0.1,0.3,-0.05 --normal 0.3,1,-0.2 --raw");
    ASSERT_EQ(r.status, 0) << r.output;
    const Rgbd got = test::firstIrradianceRgb(r.output);
    EXPECT_NEAR(got.x, want.x, 1e-6 * (1 + want.x));
    EXPECT_NEAR(got.z, want.z, 1e-6 * (1 + want.z));

    // export --layout basis: one texture per channel at the nodes; texel = the node's values.
    const std::string out = dir.file("tex");
    r = runCli("export " + file + " -o " + out + " --format raw --float --layout basis");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json manifest = test::readManifest(out);
    EXPECT_EQ(manifest["basis"], "sh:3") << manifest;
    EXPECT_NE(manifest.value("irradiance", "").find("l = 0..3"), std::string::npos) << manifest;
    const GridSpec& g = v.levels[0].grid;
    std::ifstream t(out + "/sh_l2m1.raw", std::ios::binary);
    std::vector<float> texels(g.nodeCount() * 4);
    t.read(reinterpret_cast<char*>(texels.data()), std::streamsize(texels.size() * sizeof(float)));
    ASSERT_TRUE(t);
    for (std::size_t node = 0; node < g.nodeCount(); ++node)
        for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(texels[4 * node + c], v.levels[0].nodeData(node, 16)[3 * 7 + c]);
    // Order 3 holds SH order 2 (its bands 0..2): the default SH order-2 layout fits. Order 1
    // does not; the refusal names the layout that does.
    r = runCli("export " + file + " -o " + dir.file("tex2") + " --format raw");
    EXPECT_EQ(r.status, 0) << r.output;
    const std::string sh1 = dir.file("sh1.vdb");
    r = runCli("bake -q -o " + sh1 + " --resolution 3 --rays 32 --bounces 1 --basis sh:1");
    ASSERT_EQ(r.status, 0) << r.output;
    r = runCli("export " + sh1 + " -o " + dir.file("tex3") + " --format raw");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("use --layout basis"), std::string::npos) << r.output;
}

// The default bake stores SH order 4 (no --basis): the point gather with the default preset.
TEST(CliShBasis, ShFourTakesThePointGatherWithTheDefaultPresetAndExportsItsBandsZeroToTwo) {
    test::TempDir dir;
    const std::string file = dir.file("sh4.vdb");
    CliRun r = runCli("bake -o " + file + " --resolution 4");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("1024 rays per node (+ 1 probe-to-probe pass)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("Direct light (occlusion)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("basis sh:4: radiance SH coefficients, bands 0..4, 25 Vec3f grids"), std::string::npos) << r.output;
    const Volume v = readVolume(file);
    EXPECT_EQ(v.basis.kind, "sh:4");
    EXPECT_EQ(v.direct.mode, DirectMode::Occlusion);
    EXPECT_TRUE(v.direct.hasVisibility());
    EXPECT_FALSE(v.levels[0].depth.empty());
    EXPECT_EQ(metaNumber(v.meta, "rays_per_node", 0), 1024);
    EXPECT_EQ(metaNumber(v.meta, "probe_passes", 0), 1);

    // query = the library lookup (the SH part plus the listed light's exact irradiance times its visibility).
    const IrradianceQuery q(v);
    const Rgb want = q.irradiance(Vec3f(0.2f, 0.3f, 0.25f), normalize(Vec3f(0.3f, 1.0f, -0.2f)));
    ASSERT_GT(want.x, 0.01f);
    r = runCli("query " + file + " --at 0.2,0.3,0.25 --normal 0.3,1,-0.2 --raw");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NEAR(test::firstIrradianceRgb(r.output).x, want.x, 1e-6 * (1 + want.x));

    // export --layout sh2: the texel at each node is the node's first nine channels.
    const std::string out = dir.file("tex");
    r = runCli("export " + file + " -o " + out + " --format raw --float --layout sh2");
    ASSERT_EQ(r.status, 0) << r.output;
    const GridSpec& g = v.levels[0].grid;
    const char* names[9] = {"l0m0", "l1m_neg1", "l1m0", "l1m1", "l2m_neg2", "l2m_neg1", "l2m0", "l2m1", "l2m2"};
    for (int j = 0; j < 9; ++j) {
        std::ifstream t(out + "/sh2_sh_" + names[j] + ".raw", std::ios::binary);
        std::vector<float> texels(g.nodeCount() * 4);
        t.read(reinterpret_cast<char*>(texels.data()), std::streamsize(texels.size() * sizeof(float)));
        ASSERT_TRUE(t) << names[j];
        for (std::size_t node = 0; node < g.nodeCount(); ++node)
            for (int c = 0; c < 3; ++c)
                ASSERT_FLOAT_EQ(texels[4 * node + c], v.levels[0].nodeData(node, 25)[3 * j + c]) << names[j] << " node " << node;
    }
    // The default engine layout (sh2-packed) fits too; its manifest says it holds bands 0..2.
    r = runCli("export " + file + " -o " + dir.file("packed"));
    EXPECT_EQ(r.status, 0) << r.output;
    const nlohmann::json packed = test::readManifest(dir.file("packed"));
    EXPECT_EQ(packed["truncated_from"]["basis"], "sh:4") << packed;

    // query --sh-order 2 answers with those bands (truncateSh), which differ from all five.
    const Volume l2 = truncateSh(v, 2);
    EXPECT_EQ(l2.basis.kind, "sh2");
    const Rgb band2 = IrradianceQuery(l2).irradiance(Vec3f(0.2f, 0.3f, 0.25f), normalize(Vec3f(0.3f, 1.0f, -0.2f)));
    r = runCli("query " + file + " --at 0.2,0.3,0.25 --normal 0.3,1,-0.2 --raw --sh-order 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NEAR(test::firstIrradianceRgb(r.output).x, band2.x, 1e-6 * (1 + band2.x));
    EXPECT_GT(std::fabs(band2.x - want.x), 1e-4 * want.x);
    for (const char* bad : {"--sh-order 5", "--sh-order 0", "--sh-order 2 --stream on"}) {
        r = runCli("query " + file + " --at 0.2,0.3,0.25 " + bad);
        EXPECT_NE(r.status, 0) << bad;
        EXPECT_EQ(test::countLines(r.output), 1) << bad << ": " << r.output;
    }
}

TEST(CliShBasis, ShFourPointGatherTilesInStagesMergeToTheSingleBake) {
    // The default preset's probe pass makes two stages; every tile of each, merged, then the
    // next stage from the merged first: the same bytes as the single bake (visibility and
    // depth moments included).
    test::TempDir dir;
    const std::string args = " --resolution 12 --rays 32 --basis sh:4";  // 2 x 2 x 2 leaves over 3 tiles
    const std::string whole = dir.file("whole.vdb");
    CliRun r = runCli("bake -q -o " + whole + " --threads 2" + args);
    ASSERT_EQ(r.status, 0) << r.output;
    std::string stage0 = "merge -q -o " + dir.file("s0.vdb"), stage1 = "merge -q -o " + dir.file("merged.vdb");
    for (int t = 0; t < 3; ++t) {
        const std::string tile = " --tiles 3 --tile " + std::to_string(t) + " --threads " + std::to_string(1 + t % 2);
        r = runCli("bake -q -o " + dir.file("a" + std::to_string(t) + ".vdb") + tile + " --stage 0" + args);
        ASSERT_EQ(r.status, 0) << r.output;
        stage0 += " " + dir.file("a" + std::to_string(t) + ".vdb");
    }
    r = runCli(stage0);
    ASSERT_EQ(r.status, 0) << r.output;
    for (int t = 2; t >= 0; --t) {
        const std::string tile = " --tiles 3 --tile " + std::to_string(t);
        r = runCli("bake -q -o " + dir.file("b" + std::to_string(t) + ".vdb") + tile + " --stage 1 --stage-input " +
                   dir.file("s0.vdb") + args);
        ASSERT_EQ(r.status, 0) << r.output;
        stage1 += " " + dir.file("b" + std::to_string(t) + ".vdb");
    }
    r = runCli(stage1);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(fileBytes(whole), fileBytes(dir.file("merged.vdb")));
    EXPECT_EQ(readVolume(dir.file("merged.vdb")).basis.kind, "sh:4");
}

TEST(CliShBasis, BadOrdersAreRefusedWithOneLineAndNoFile) {
    test::TempDir dir;
    const std::string base = "bake --resolution 3 --rays 8";
    test::expectCleanFailuresWithOutput(dir, {{base + " --basis sh:0", "'sh:0': the SH order must be 1, 2, 3 or 4"},
                                              {base + " --basis sh:5", "'sh:5': the SH order must be 1, 2, 3 or 4"},
                                              {base + " --basis sh:x", "'sh:x': the SH order must be 1, 2, 3 or 4"},
                                              {base + " --basis sh:3 --method photons", "--basis sh:3 works with --method gather"},
                                              {base + " --basis sh:4 --sh-window", "--sh-window applies to --basis sh2 only"}});
}

TEST(CliShBasis, TilesMergeToTheSingleBakeBilevelWithDepthMoments) {
    // The generic gather honours tiles like the other point gathers (its node mask), on a
    // bilevel layout; depth moments come from the separate depth pass; the lookup weights by them.
    test::TempDir dir;
    const std::string args = " --resolution 4 --rays 32 --bounces 1 --basis sh:2 --layout bilevel --refine 2 --depth-moments";
    const std::string whole = dir.file("whole.vdb"), merged = dir.file("merged.vdb");
    CliRun r = runCli("bake -q -o " + whole + " --threads 2" + args);
    ASSERT_EQ(r.status, 0) << r.output;
    for (int t = 0; t < 2; ++t) {
        r = runCli("bake -q -o " + dir.file("t" + std::to_string(t) + ".vdb") + " --threads " + std::to_string(1 + t) +
                   " --tiles 2 --tile " + std::to_string(t) + args);
        ASSERT_EQ(r.status, 0) << r.output;
    }
    r = runCli("merge " + dir.file("t1.vdb") + " " + dir.file("t0.vdb") + " -o " + merged);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string a = fileBytes(whole), b = fileBytes(merged);
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << a.size() << " vs " << b.size() << " bytes";
    const Volume v = readVolume(whole);
    EXPECT_EQ(v.levels.size(), 2u);
    EXPECT_TRUE(v.hasDepth());
    EXPECT_TRUE(IrradianceQuery(v).depthWeighted());
}
