// `vdblight export --layout sh2-32 | sh1-16` end to end on a default-kind bake (SH order 4,
// depth moments, --direct occlusion): the files are read back by scripts/check_export.py
// (manifest.json and docs/engine*.md only) and must match `vdblight query --sh-order 2` within
// the bound that 8-bit rounding explains; ktx-parse reads the KTX2 files. A volume whose basis
// cannot take these layouts gets one line and no output.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_baked_suite.h"
#include "export_readers.h"
#include "manifest_util.h"

namespace fs = std::filesystem;
using namespace vdblight::test;

namespace {
class CliExportCompact : public BakedSuite<CliExportCompact> {
public:
    static std::vector<SuiteBake> bakes() {
        return {{"cornell.vdb", "--resolution 6 --rays 48"},
                {"plain.vdb", "--resolution 5 --rays 32 --no-depth-moments"},
                {"photons.vdb", "--method photons --photons 20000 --resolution 4"}};
    }

protected:
    static std::string volume() { return file("cornell.vdb"); }
};

}  // namespace

TEST_F(CliExportCompact, RoundTripMatchesQueryWithinTheEightBitBound) {
    TempDir out;
    // The default kind (depth weights on 8 decoded corners) and one without depth moments
    // (trilinear, as hardware filtering of decoded texels).
    const struct {
        const char *layout, *format, *volume;
    } cases[] = {
        {"sh2-32", "ktx2", "cornell.vdb"}, {"sh2-32", "raw", "plain.vdb"}, {"sh2-32", "dds", "cornell.vdb"},
        {"sh1-16", "raw", "cornell.vdb"},  {"sh1-16", "dds", "plain.vdb"},
    };
    for (const auto& c : cases) {
        const std::string label = std::string(c.layout) + " " + c.format + " " + c.volume;
        const std::string where = out.file(std::string(c.layout) + c.format + c.volume);
        std::string log;
        ASSERT_EQ(runCommand(cliPath() + " export -q " + file(c.volume) + " -o " + where + " --format " + c.format +
                                 " --layout " + c.layout, &log), 0) << label << ": " << log;
        const nlohmann::json manifest = readManifest(where);
        EXPECT_TRUE(manifest.contains("compact_sh")) << label;
        // 8 B of L0_L1Rx + 4 B for each other lighting texture: 16 or 32 B per probe.
        const std::string extension = c.format[0] == 'k' ? ".ktx2" : c.format[0] == 'd' ? ".dds" : ".raw";
        auto texture = [&](const std::string& name) {
            for (const nlohmann::json& t : manifest["textures"])
                if (t["name"] == name) return t;
            ADD_FAILURE() << label << ": no texture " << name << " in the manifest";
            return nlohmann::json::object();
        };
        const nlohmann::json l0 = texture("L0_L1Rx"), l1g = texture("L1G_L1Ry"), vis = texture("light_visibility_0_0");
        EXPECT_EQ(l0.value("file", ""), "L0_L1Rx" + extension) << label;
        EXPECT_EQ(l0.value("format", ""), "rgba16_sfloat") << label;
        EXPECT_EQ(l0.value("bytes_per_texel", 0), 8) << label;
        EXPECT_EQ(l1g.value("file", ""), "L1G_L1Ry" + extension) << label;
        EXPECT_EQ(l1g.value("format", ""), "rgba8_unorm") << label;
        EXPECT_EQ(l1g.value("bytes_per_texel", 0), 4) << label;
        EXPECT_EQ(vis.value("file", ""), "light_visibility_0_0" + extension) << label;
        EXPECT_EQ(vis.value("format", ""), "rgba8_unorm") << label << ": the visibility in 8 bits";
        // The default bake's shadow edges: distance and width in half, no ramp texture (the
        // shader computes each corner's ramp; check_export.py does the same).
        if (std::string(c.volume) == "cornell.vdb") {
            const nlohmann::json expected = {"light_edge_distance_0_0", "light_edge_width_0_0"};
            EXPECT_EQ(manifest.value("/direct/shadow_edges/textures"_json_pointer, nlohmann::json()), expected) << label;
            EXPECT_EQ(texture("light_edge_distance_0_0").value("format", ""), "rgba16_sfloat") << label;
        }
        const int status = checkExport(file(c.volume), where, &log);
        EXPECT_EQ(status, 0) << label << ": " << log;
        EXPECT_NE(log.find("8-bit bound"), std::string::npos) << label << ": " << log;
        if (std::string(c.format) == "raw") {
            EXPECT_EQ(fs::file_size(where + "/L1G_L1Ry.raw") * 2, fs::file_size(where + "/L0_L1Rx.raw")) << label;
        }
    }
}

TEST_F(CliExportCompact, KtxParseReadsTheEightBitTextures) {
    ASSERT_TRUE(fs::exists(ktxParseDir())) << "ktx-parse is not installed: run scripts/setup.sh (npm ci in scripts/ktx)";
    TempDir out;
    std::string log;
    ASSERT_EQ(runCommand(cliPath() + " export -q " + volume() + " -o " + out.file("k") + " --format ktx2 --layout sh2-32", &log), 0)
        << log;
    EXPECT_EQ(checkKtx2(out.file("k"), &log), 0) << log;
    EXPECT_NE(log.find("pass"), std::string::npos) << log;
}

TEST_F(CliExportCompact, LayoutTheBasisCannotTakeGetsOneLineAndNoOutput) {
    TempDir out;
    for (const char* layout : {"sh2-32", "sh1-16"}) {
        expectRefusal("export " + file("photons.vdb") + " -o " + out.file("x") + " --layout " + layout,
                      "does not fit volume kind", out.file("x"), layout);
        expectRefusal("export " + volume() + " -o " + out.file("x") + " --layout " + layout + " --cells 2",
                      "--cells exports the SH layouts", out.file("x"), std::string(layout) + " --cells");
    }
}
