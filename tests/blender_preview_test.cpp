// Inspection of a bake: the vdb-preview grids (checked with pyopenvdb against `vdblight
// query`) and scripts/blender/preview.py run headless with Debian's Blender on the default
// Cornell box. The rendered image (decoded by scripts/check_png.py) must not be black, and
// the side near the red wall (x ~ 0.55, on the right when looking along -z) must be redder
// than the side near the green wall (x = 0).
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "test_util.h"

namespace fs = std::filesystem;
using vdblight::test::runCommand;
using vdblight::test::TempDir;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;
const std::string kSource = VDBLIGHT_SOURCE_DIR;
}  // namespace

TEST(BlenderPreview, PreviewGridsMatchQueryAndTheRenderShowsTheRedWall) {
    TempDir dir;
    const std::string vol = dir.file("cornell.vdb");
    std::string log;
    ASSERT_EQ(runCommand(kCli + " bake -q -o " + vol + " --resolution 7 --rays 64 --bounces 2", &log), 0) << log;
    ASSERT_EQ(runCommand(kCli + " export " + vol + " -o " + dir.file("p") + " --format vdb-preview", &log), 0) << log;
    EXPECT_NE(log.find("preview.vdb"), std::string::npos) << log;
    EXPECT_EQ(runCommand("/usr/bin/python3 " + kSource + "/scripts/check_preview.py --cli " + kCli + " --volume " + vol +
                             " --preview " + dir.file("p/preview.vdb") + " 2>/dev/null", &log),
              0)
        << log;

    if (std::getenv("VDBLIGHT_SKIP_BLENDER")) GTEST_SKIP() << "VDBLIGHT_SKIP_BLENDER is set";
    // The raw bake: the script converts it through `vdblight export --format vdb-preview`.
    const std::string png = dir.file("preview.png");
    ASSERT_EQ(runCommand("blender -b --factory-startup --python " + kSource + "/scripts/blender/preview.py -- " + vol +
                             " " + png + " --cli " + kCli + " --size 48 --samples 4", &log),
              0)
        << log;
    ASSERT_TRUE(fs::exists(png)) << log;
    ASSERT_EQ(runCommand("/usr/bin/python3 " + kSource + "/scripts/check_png.py " + png + " --left-right", &log), 0) << log;
    std::stringstream s(log);
    int w = 0, h = 0;
    double r = 0, g = 0, b = 0, left = 0, right = 0;
    std::string label;
    s >> w >> h >> r >> g >> b >> label >> left >> label >> right;
    EXPECT_EQ(w, 48) << log;
    EXPECT_EQ(h, 48) << log;
    EXPECT_GT(r + g + b, 60.0) << "the render is (nearly) black: " << log;
    EXPECT_GT(right, left + 5.0) << "the red-wall side is not redder than the green-wall side: " << log;

    // The preview file itself renders too (no conversion), and bad input fails cleanly.
    ASSERT_EQ(runCommand("blender -b --factory-startup --python " + kSource + "/scripts/blender/preview.py -- " +
                             dir.file("p/preview.vdb") + " " + dir.file("direct.png") + " --size 16 --samples 1", &log),
              0)
        << log;
    EXPECT_TRUE(fs::exists(dir.file("direct.png")));
    EXPECT_NE(runCommand("blender -b --factory-startup --python " + kSource + "/scripts/blender/preview.py -- " +
                             dir.file("missing.vdb") + " " + dir.file("bad.png"), &log),
              0);
    EXPECT_NE(log.find("vdblight preview: error: no such file"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir.file("bad.png")));
}
