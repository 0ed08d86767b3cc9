// vdblight check-scene end to end: an OBJ room with one wall's triangles flipped.
#include <gtest/gtest.h>

#include <string>

#include "test_util.h"

using vdblight::test::runCommand;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;

/// A closed cube room [-1,1]^3 with front faces inwards, except the two "floor" triangles
/// (material "floor", triangles 0 and 1) when `flipFloor`.
std::string roomObj(bool flipFloor) {
    std::string s = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n";
    s += "usemtl floor\n";
    s += flipFloor ? "f 1 2 6\nf 1 6 5\n" : "f 1 6 2\nf 1 5 6\n";
    s += "usemtl walls\nf 1 3 4\nf 1 2 3\nf 5 7 6\nf 5 8 7\nf 1 8 5\nf 1 4 8\nf 2 7 3\nf 2 6 7\nf 4 7 8\nf 4 3 7\n";
    return s;
}
}  // namespace

TEST(CliCheckScene, ListsTheFlippedFloorAndNothingWhenFixed) {
    TempDir dir;
    const std::string good = dir.file("good.obj"), bad = dir.file("bad.obj");
    writeTextFile(good, roomObj(false));
    writeTextFile(bad, roomObj(true));
    std::string out;
    ASSERT_EQ(runCommand(kCli + " check-scene " + good + " --resolution 8 --rays 64", &out), 0) << out;
    EXPECT_NE(out.find("No face is seen from behind"), std::string::npos) << out;
    ASSERT_EQ(runCommand(kCli + " check-scene -q " + bad + " --resolution 8 --rays 64", &out), 0) << out;
    // Header, then the two floor triangles (index, material, hits), nothing else.
    std::size_t lines = 0;
    for (char c : out) lines += c == '\n';
    EXPECT_EQ(lines, 3u) << out;
    EXPECT_EQ(out.rfind("triangle,material,backface_hits\n", 0), 0u) << out;
    EXPECT_NE(out.find("\n0,floor,"), std::string::npos) << out;
    EXPECT_NE(out.find("\n1,floor,"), std::string::npos) << out;
    EXPECT_NE(runCommand(kCli + " check-scene " + good + " --max-backface 1.5", &out), 0);
    EXPECT_NE(runCommand(kCli + " check-scene " + dir.file("missing.obj"), &out), 0);
}
