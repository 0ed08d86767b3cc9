// End-to-end tests of `vdblight bake --sampling/--domain/--fit/--invalidate-backface`: the
// options bake, store validity and query; bad values give one line, a non-zero exit and no file.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_util.h"
#include "test_util.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
int run(const std::string& args, std::string* out) { return test::runCommand(test::cliPath() + " " + args, out); }
using test::countLines;
using test::filesIn;
}  // namespace

TEST(CliAntialiased, EverySamplingBakesStoresAndQueries) {
    test::TempDir dir;
    const std::string variants[] = {"--sampling antialiased", "--sampling antialiased --domain all",
                                    "--sampling antialiased --fit least-squares",
                                    "--sampling point --invalidate-backface 0.1", "--sampling point"};
    for (const std::string& v : variants) {
        const std::string out = dir.file("v.vdb");
        std::string text;
        ASSERT_EQ(run("bake -q -o " + out + " --resolution 5 --rays 32 " + v, &text), 0) << v << "\n" << text;
        const Volume vol = readVolume(out);
        EXPECT_EQ(vol.levels[0].validity.empty(), v == "--sampling point") << v;
        EXPECT_EQ(metaString(vol.meta, "sampling"), v.find("antialiased") != std::string::npos ? "antialiased" : "point");
        if (v == "--sampling antialiased") {
            EXPECT_EQ(metaString(vol.meta, "domain"), "interior");  // the default
            EXPECT_EQ(metaString(vol.meta, "fit"), "projection (eq. 6)");  // the default
        }
        if (v.find("least-squares") != std::string::npos) {
            EXPECT_EQ(metaString(vol.meta, "fit"), "least-squares (Tikhonov towards eq. 6)");
        }
        ASSERT_EQ(run("query " + out + " --at 0,1,0 --normal 0,1,0", &text), 0) << text;
        ASSERT_EQ(run("info " + out, &text), 0) << text;
        if (!vol.levels[0].validity.empty()) {
            EXPECT_NE(text.find("validity"), std::string::npos) << text;
        }
    }
}

TEST(CliAntialiased, BadOptionsGiveOneLineAndNoFile) {
    test::TempDir dir;
    const std::string out = dir.file("bad.vdb");
    const std::pair<std::string, std::string> cases[] = {
        {"--sampling trilinear", "--sampling must be point or antialiased"},
        {"--sampling antialiased --domain outside", "--domain must be all or interior"},
        {"--domain interior", "--domain needs --sampling antialiased"},
        {"--invalidate-backface 1.5", "--invalidate-backface must be in [0, 1]"},
        {"--invalidate-backface -0.1", "--invalidate-backface must be in [0, 1]"},
        {"--sampling antialiased --invalidate-backface 0.2", "applies to --sampling point only"},
        {"--sampling antialiased --fit cubic", "--fit must be projection or least-squares"},
        {"--fit least-squares", "--fit needs --sampling antialiased"},
    };
    for (const auto& [args, expected] : cases) {
        std::string text;
        const int status = run("bake -o " + out + " --resolution 4 " + args, &text);
        EXPECT_NE(status, 0) << args;
        EXPECT_LT(status, 128) << args;
        EXPECT_EQ(countLines(text), 1) << args << "\n" << text;
        EXPECT_NE(text.find(expected), std::string::npos) << args << "\n" << text;
        EXPECT_EQ(filesIn(dir.path()), 0u) << args;
    }
}
