// `vdblight export` end to end, checked by readers we did not write: the round-trip script
// (Python + numpy, only manifest.json and docs/engines.md) against `vdblight query`, and the
// npm package ktx-parse for KTX2. Bad input: one line, non-zero exit, nothing written.
#include <gtest/gtest.h>

#include <fstream>

#include "test_util.h"

namespace fs = std::filesystem;
using vdblight::test::runCommand;
using vdblight::test::TempDir;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;
const std::string kSource = VDBLIGHT_SOURCE_DIR;

// One small bake of the default Cornell box, shared by the tests of this file.
class CliExport : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir();
        std::string out;
        ASSERT_EQ(runCommand(kCli + " bake -q -o " + volume() + " --resolution 6 --rays 48", &out), 0) << out;
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::string volume() { return dir_->file("cornell.vdb"); }
    static TempDir* dir_;
};
TempDir* CliExport::dir_ = nullptr;

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST_F(CliExport, RoundTripThroughTheManifestMatchesQuery) {
    TempDir out;
    for (const char* format : {"ktx2", "dds", "raw"})
        for (const char* layout : {"sh2", "sh2-packed", "sh1"})
            for (const char* precision : {"--half", "--float"}) {
                const std::string where = out.file(std::string(format) + layout + precision);
                std::string log;
                ASSERT_EQ(runCommand(kCli + " export " + volume() + " -o " + where + " --format " + format +
                                         " --layout " + layout + " " + precision, &log), 0) << log;
                EXPECT_NE(log.find("Exported"), std::string::npos) << log;
                ASSERT_TRUE(fs::exists(where + "/manifest.json"));
                const int status = runCommand("/usr/bin/python3 " + kSource + "/scripts/check_export.py --cli " + kCli +
                                                  " --volume " + volume() + " --export " + where + " --points 300",
                                              &log);
                EXPECT_EQ(status, 0) << format << " " << layout << " " << precision << ": " << log;
            }
}

TEST_F(CliExport, KtxParseReadsAndRewritesEveryFileByteForByte) {
    ASSERT_TRUE(fs::exists(kSource + "/scripts/ktx/node_modules/ktx-parse"))
        << "ktx-parse is not installed: run scripts/setup.sh (npm ci in scripts/ktx)";
    TempDir out;
    for (const char* layout : {"sh2", "sh2-packed", "sh1"})
        for (const char* precision : {"--half", "--float"}) {
            const std::string where = out.file(std::string(layout) + precision);
            std::string log;
            ASSERT_EQ(runCommand(kCli + " export -q " + volume() + " -o " + where + " --format ktx2 --layout " + layout +
                                     " " + precision, &log), 0) << log;
            EXPECT_EQ(runCommand("node " + kSource + "/scripts/ktx/check_ktx2.mjs " + where, &log), 0) << log;
            EXPECT_NE(log.find("pass"), std::string::npos) << log;
        }
}

TEST_F(CliExport, ExrAtlasIsWrittenWithItsManifest) {
    TempDir out;
    std::string log;
    ASSERT_EQ(runCommand(kCli + " export " + volume() + " -o " + out.file("e") + " --format exr-atlas --layout sh1", &log), 0)
        << log;
    for (const char* f : {"shAr.exr", "shAg.exr", "shAb.exr", "manifest.json"}) EXPECT_TRUE(fs::exists(out.file("e/") + f)) << f;
    std::ifstream m(out.file("e/manifest.json"));
    const std::string json((std::istreambuf_iterator<char>(m)), {});
    for (const char* key : {"\"columns\": 3", "\"rows\": 2", "\"slices\": 6", "uvw_scale", "uvw_bias"})
        EXPECT_NE(json.find(key), std::string::npos) << key;
}

TEST_F(CliExport, BadInputFailsWithOneLineAndWritesNothing) {
    TempDir out;
    vdblight::test::writeTextFile(out.file("plain"), "not a directory");
    const struct {
        std::string args, expected;
    } cases[] = {
        {"--format png", "unknown export format 'png'"},
        {"--layout bogus", "unknown export layout 'bogus'"},
        {"--layout vectors", "does not fit volume kind"},
        {"--format dds --resolution 3000", "2048"},
        {"--format raw --resolution 1200", "GiB"},
        {"--half --float", "not both"},
    };
    for (const auto& c : cases) {
        std::string log;
        const int status = runCommand(kCli + " export " + volume() + " -o " + out.file("x") + " " + c.args, &log);
        EXPECT_NE(status, 0) << c.args;
        EXPECT_EQ(lines(log), 1) << c.args << ": " << log;
        EXPECT_NE(log.find(c.expected), std::string::npos) << c.args << ": " << log;
        EXPECT_FALSE(fs::exists(out.file("x"))) << c.args;
    }
    std::string log;
    EXPECT_NE(runCommand(kCli + " export " + volume() + " -o " + out.file("plain/sub"), &log), 0);
    EXPECT_EQ(lines(log), 1) << log;
    EXPECT_NE(log.find("not a directory"), std::string::npos) << log;
    EXPECT_EQ(runCommand(kCli + " export " + out.file("missing.vdb") + " -o " + out.file("x"), &log) == 0, false);
    EXPECT_FALSE(fs::exists(out.file("x")));
}
