// `vdblight export` end to end, checked by readers we did not write: the round-trip script
// (Python + numpy, only manifest.json and docs/engine*.md) against `vdblight query`, and the
// npm package ktx-parse for KTX2. Bad input: one line, non-zero exit, nothing written.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_baked_suite.h"
#include "export_readers.h"

namespace fs = std::filesystem;
using namespace vdblight::test;

namespace {
// One small bake of the default Cornell box, shared by the tests of this file.
class CliExport : public BakedSuite<CliExport> {
public:
    static std::vector<SuiteBake> bakes() { return {{"cornell.vdb", "--resolution 6 --rays 48"}}; }

protected:
    static std::string volume() { return file("cornell.vdb"); }
};
}  // namespace

// Every pair of (format, layout), (format, precision) and (layout, precision) once: nine
// exports instead of the eighteen of every triple (the writers do not depend on each other;
// KtxParseReadsAndRewritesEveryFileByteForByte reads all six KTX2 layouts and precisions).
TEST_F(CliExport, RoundTripThroughTheManifestMatchesQuery) {
    TempDir out;
    const char* formats[] = {"ktx2", "dds", "raw"};
    const char* layouts[] = {"sh2", "sh2-packed", "sh1"};
    for (int f = 0; f < 3; ++f)
        for (int l = 0; l < 3; ++l) {
            const char* format = formats[f];
            const char* layout = layouts[l];
            const char* precision = (f + l) % 2 ? "--float" : "--half";
            const std::string where = out.file(std::string(format) + layout + precision);
            std::string log;
            ASSERT_EQ(runCommand(cliPath() + " export " + volume() + " -o " + where + " --format " + format + " --layout " +
                                     layout + " " + precision, &log), 0) << log;
            EXPECT_NE(log.find("Exported"), std::string::npos) << log;
            ASSERT_TRUE(fs::exists(where + "/manifest.json"));
            const int status = checkExport(volume(), where, &log);
            EXPECT_EQ(status, 0) << format << " " << layout << " " << precision << ": " << log;
        }
}

TEST_F(CliExport, KtxParseReadsAndRewritesEveryFileByteForByte) {
    ASSERT_TRUE(fs::exists(ktxParseDir()))
        << "ktx-parse is not installed: run scripts/setup.sh (npm ci in scripts/ktx)";
    TempDir out;
    for (const char* layout : {"sh2", "sh2-packed", "sh1"})
        for (const char* precision : {"--half", "--float"}) {
            const std::string where = out.file(std::string(layout) + precision);
            std::string log;
            ASSERT_EQ(runCommand(cliPath() + " export -q " + volume() + " -o " + where + " --format ktx2 --layout " + layout +
                                     " " + precision, &log), 0) << log;
            EXPECT_EQ(checkKtx2(where, &log), 0) << log;
            EXPECT_NE(log.find("pass"), std::string::npos) << log;
        }
}

TEST_F(CliExport, ExrAtlasIsWrittenWithItsManifest) {
    TempDir out;
    std::string log;
    ASSERT_EQ(runCommand(cliPath() + " export " + volume() + " -o " + out.file("e") + " --format exr-atlas --layout sh1", &log), 0)
        << log;
    for (const char* f : {"shAr.exr", "shAg.exr", "shAb.exr", "manifest.json"}) EXPECT_TRUE(fs::exists(out.file("e/") + f)) << f;
    std::ifstream m(out.file("e/manifest.json"));
    const std::string json((std::istreambuf_iterator<char>(m)), {});
    for (const char* key : {"\"columns\": 3", "\"rows\": 2", "\"slices\": 6", "uvw_scale", "uvw_bias"})
        EXPECT_NE(json.find(key), std::string::npos) << key;
}

TEST_F(CliExport, BadInputFailsWithOneLineAndWritesNothing) {
    TempDir out;
    writeTextFile(out.file("plain"), "not a directory");
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
    for (const auto& c : cases)
        expectRefusal("export " + volume() + " -o " + out.file("x") + " " + c.args, c.expected, out.file("x"), c.args);
    std::string log;
    EXPECT_NE(runCommand(cliPath() + " export " + volume() + " -o " + out.file("plain/sub"), &log), 0);
    EXPECT_EQ(countLines(log), 1) << log;
    EXPECT_NE(log.find("not a directory"), std::string::npos) << log;
    EXPECT_EQ(runCommand(cliPath() + " export " + out.file("missing.vdb") + " -o " + out.file("x"), &log) == 0, false);
    EXPECT_FALSE(fs::exists(out.file("x")));
}
