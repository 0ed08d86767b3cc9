// `vdblight export --format three` end to end: the files three.js's LightProbeGridWebGL reads
// (their values in three.js are checked by web_page_test in Chromium) and clean refusals: one
// line, non-zero exit, nothing written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_baked_suite.h"
#include "export_file_checks.h"

namespace fs = std::filesystem;
using namespace vdblight::test;

namespace {
class CliExportThree : public BakedSuite<CliExportThree> {
public:
    static std::vector<SuiteBake> bakes() {
        return {{"baked.vdb", "--resolution 6 --rays 48 --direct baked"}, {"occlusion.vdb", "--resolution 6 --rays 48"}};
    }
};

std::string readText(const std::string& path) {
    const std::vector<uint8_t> b = readFile(path);
    return std::string(b.begin(), b.end());
}
}  // namespace

// Half by default (8 B per texel), --float 16 B; the atlas is nx x ny x 7 (nz + 2) texels.
TEST_F(CliExportThree, WritesTheAtlasAndItsJson) {
    TempDir out;
    for (const char* precision : {"", " --float"}) {
        const std::string dir = out.file(*precision ? "float" : "half");
        std::string log;
        ASSERT_EQ(runCommand(cliPath() + " export " + file("baked.vdb") + " -o " + dir + " --format three" + precision, &log), 0)
            << log;
        EXPECT_NE(log.find("LightProbeGridWebGL"), std::string::npos) << log;
        const nlohmann::json json = nlohmann::json::parse(readText(dir + "/probe_grid.json"));
        const std::vector<uint64_t> n = json.at("resolution").get<std::vector<uint64_t>>();
        ASSERT_EQ(n.size(), 3u) << json;
        const uint64_t texel = *precision ? 16 : 8;
        EXPECT_EQ(fs::file_size(dir + "/probe_grid_sh.bin"), n[0] * n[1] * 7 * (n[2] + 2) * texel);
        EXPECT_EQ(json["texture"]["type"], *precision ? "float32" : "float16") << json;
        EXPECT_EQ(json["depth_moments"], true) << json;  // the default bake's
        EXPECT_EQ(filesIn(dir), 2u);
    }
}

// The default bake (--direct occlusion) keeps its main lights' direct light outside the SH;
// export folds it into the probes (export_fold_direct_test checks the values), says so on the
// console and names the lights in probe_grid.json.
TEST_F(CliExportThree, TheDefaultBakesDirectLightIsFoldedIntoTheProbes) {
    TempDir out;
    const std::string dir = out.file("web");
    std::string log;
    ASSERT_EQ(runCommand(cliPath() + " export " + file("occlusion.vdb") + " -o " + dir + " --format three", &log), 0) << log;
    EXPECT_NE(log.find("Folded the direct light of "), std::string::npos) << log;
    const nlohmann::json direct = nlohmann::json::parse(readText(dir + "/probe_grid.json"))["direct_light"];
    EXPECT_EQ(direct["folded_into_sh"], true) << direct;
    ASSERT_FALSE(direct["lights"].empty()) << direct;
    EXPECT_EQ(direct["lights"][0].get<std::string>().rfind("kind=", 0), 0u) << direct;
    EXPECT_EQ(filesIn(dir), 2u);
}

TEST_F(CliExportThree, BadInputFailsWithOneLineAndWritesNothing) {
    TempDir out;
    const struct {
        std::string volume, args, expected;
    } cases[] = {
        {"baked.vdb", "--cells 4", "--cells"},
        {"baked.vdb", "--resolution 1", "at least 2"},
        {"baked.vdb", "--half --float", "not both"},
    };
    for (const auto& c : cases)
        expectRefusal("export " + file(c.volume) + " -o " + out.file("x") + " --format three " + c.args, c.expected,
                      out.file("x"), c.volume + " " + c.args);
}
