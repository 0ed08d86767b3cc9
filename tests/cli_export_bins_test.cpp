// `vdblight export --layout bins` end to end: a small bins:4 volume (uniform and bilevel) and
// a moment volume exported as ktx2 / dds / raw, read back by scripts/check_export.py from
// manifest.json alone (the documented four-bin blend) and compared with `vdblight query`.
// Layouts that do not fit the volume: one line, non-zero exit, nothing written.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_baked_suite.h"
#include "export_readers.h"
#include "manifest_util.h"

namespace fs = std::filesystem;
using namespace vdblight::test;

namespace {
class CliExportBins : public BakedSuite<CliExportBins> {
public:
    static std::vector<SuiteBake> bakes() {
        return {{"bins.vdb", "--resolution 4 --rays 48 --bounces 1 --basis bins:4"},
                {"bilevel.vdb", "--resolution 4 --rays 32 --bounces 1 --basis bins:4 --layout bilevel --refine 2"},
                {"moment.vdb", "--resolution 3 --rays 32 --bounces 1 --basis moment:4:4"},
                {"sh.vdb", "--resolution 3 --rays 16"}};
    }
};
}  // namespace

TEST_F(CliExportBins, RoundTripThroughTheManifestMatchesQuery) {
    TempDir out;
    for (const char* format : {"ktx2", "dds", "raw"})
        for (const char* precision : {"--half", "--float"}) {
            const std::string where = out.file(std::string(format) + precision);
            std::string log;
            ASSERT_EQ(runCommand(cliPath() + " export " + file("bins.vdb") + " -o " + where + " --format " + format +
                                     " --layout bins " + precision, &log), 0) << log;
            EXPECT_NE(log.find("Exported 32 "), std::string::npos) << log;  // 2 R^2 textures
            EXPECT_TRUE(fs::exists(where + "/bin_h1_u3_v2." + format));
            EXPECT_EQ(checkExport(file("bins.vdb"), where, &log), 0) << format << " " << precision << ": " << log;
        }
    const nlohmann::json manifest = readManifest(out.file("raw--float"));
    EXPECT_EQ(manifest["layout"], "bins");
    const nlohmann::json& bins = manifest["bins"];
    EXPECT_EQ(bins["resolution"], 4) << bins;
    EXPECT_EQ(bins["count"], 32) << bins;
    EXPECT_EQ(bins["basis"], "bins:4") << bins;
    EXPECT_TRUE(bins.contains("bin_of_direction")) << bins;
    // Texture c is bin (h, iu, iv) with c = h*R*R + iv*R + iu.
    ASSERT_EQ(bins["bin_of_texture"].size(), 32u) << bins;
    EXPECT_EQ(bins["bin_of_texture"][0], nlohmann::json::array({0, 0, 0}));
    EXPECT_EQ(bins["bin_of_texture"][1], nlohmann::json::array({0, 1, 0}));
    EXPECT_EQ(bins["bin_of_texture"][4], nlohmann::json::array({0, 0, 1}));
    EXPECT_EQ(bins["bin_of_texture"][31], nlohmann::json::array({1, 3, 3}));
}

TEST_F(CliExportBins, MultiLevelAndMomentVolumesRoundTrip) {
    TempDir out;
    for (const char* volume : {"bilevel.vdb", "moment.vdb"}) {
        const std::string where = out.file(volume);
        std::string log;
        // The default lattice is the finest level's spacing: texels on every level-1 node.
        ASSERT_EQ(runCommand(cliPath() + " export -q " + file(volume) + " -o " + where + " --format raw --layout bins --float",
                             &log), 0) << log;
        EXPECT_EQ(checkExport(file(volume), where, &log), 0) << volume << ": " << log;
        EXPECT_NE(log.find("bins float32"), std::string::npos) << log;
    }
}

TEST_F(CliExportBins, LayoutsThatDoNotFitAreRefused) {
    TempDir out;
    const struct {
        std::string volume, layout, expected;
    } cases[] = {
        {"bins.vdb", "sh2", "use --layout bins"},
        {"bins.vdb", "vectors", "use --layout bins"},
        {"sh.vdb", "bins", "stores no directional bins"},
    };
    for (const auto& c : cases)
        expectRefusal("export " + file(c.volume) + " -o " + out.file("x") + " --layout " + c.layout, c.expected, out.file("x"),
                      c.layout);
}
