// The sky map (scene.h, loadSkyMap): the equirectangular convention texel by texel, and
// missing or corrupt files refused with an IoError naming the file. Every input file is
// written by the test into a TempDir.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include "expect_throw.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectThrowWith;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

/// Direction at the centre of texel (col, row) under SkyMap's documented convention.
Vec3f texelCentreDirection(int col, int row, int width, int height) {
    const double theta = kPi * (row + 0.5) / height;
    const double phi = 2 * kPi * ((col + 0.5) / width - 0.5);  // 0 at +X, +pi/2 at +Z
    return Vec3f(Vec3d{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
}

/// An EXR whose texel (col, row) holds (col, row, 1): a lookup tells which texel it hit.
void writeIndexExr(const std::string& path, int width, int height) {
    std::vector<float> r(width * height), g(width * height), b(width * height, 1.0f);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) { r[y * width + x] = float(x); g[y * width + x] = float(y); }
    Imf::Header header(width, height);
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float), ys = sizeof(float) * width;
    fb.insert("R", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(r.data()), xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(g.data()), xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(b.data()), xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(height);
}

}  // namespace

TEST(SkyMap, EquirectangularConvention) {
    TempDir dir;
    const int w = 8, h = 4;
    writeIndexExr(dir.file("sky.exr"), w, h);
    const auto map = loadSkyMap(dir.file("sky.exr"));
    ASSERT_EQ(map->width, w);
    ASSERT_EQ(map->height, h);
    EXPECT_EQ(map->path, dir.file("sky.exr"));

    EXPECT_EQ(map->lookup({0, 1, 0}).y, 0.0f);       // zenith: top row
    EXPECT_EQ(map->lookup({0, -1, 0}).y, h - 1.0f);  // nadir: bottom row
    // +X is the centre of the image (Blender/Cycles, three.js): just to the +Z side is column
    // w/2, to the -Z side w/2 - 1.
    const Rgb ahead = map->lookup(normalize(Vec3f{1, 0, 0.01f}));
    EXPECT_EQ(ahead.x, w / 2.0f);
    EXPECT_EQ(ahead.y, h / 2.0f);
    EXPECT_EQ(map->lookup(normalize(Vec3f{1, 0, -0.01f})).x, w / 2.0f - 1);
    // +Z at u = 3/4 and -Z at u = 1/4: turning from either towards +X moves towards the centre.
    EXPECT_EQ(map->lookup(normalize(Vec3f{0.01f, 0.01f, 1})).x, 3 * w / 4.0f - 1);
    EXPECT_EQ(map->lookup(normalize(Vec3f{0.01f, 0.01f, -1})).x, w / 4.0f);
    // -X at u = 0: the seam, with +Z's side in the last column and -Z's side in the first.
    EXPECT_EQ(map->lookup(normalize(Vec3f{-1, 0.01f, 0.01f})).x, w - 1.0f);
    EXPECT_EQ(map->lookup(normalize(Vec3f{-1, 0.01f, -0.01f})).x, 0.0f);
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            const Rgb t = map->lookup(texelCentreDirection(col, row, w, h));
            EXPECT_EQ(t.x, float(col)) << col << "," << row;
            EXPECT_EQ(t.y, float(row)) << col << "," << row;
        }
    Scene s;
    s.sky.map = map;
    EXPECT_FALSE(s.sky.isBlack());
    EXPECT_EQ(s.sky.radiance({0, 1, 0}).z, 1.0f);
}

TEST(SkyMap, MissingOrCorruptFileIsIoError) {
    TempDir dir;
    expectThrowWith<IoError>([&] { loadSkyMap(dir.file("none.exr")); }, "none.exr");
    writeTextFile(dir.file("bad.exr"), "this is not an EXR file at all\n");
    expectThrowWith<IoError>([&] { loadSkyMap(dir.file("bad.exr")); }, "bad.exr");
    // A valid header followed by truncated pixel data.
    writeIndexExr(dir.file("full.exr"), 64, 32);
    std::ifstream in(dir.file("full.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    writeTextFile(dir.file("cut.exr"), bytes.substr(0, bytes.size() / 2));
    expectThrowWith<IoError>([&] { loadSkyMap(dir.file("cut.exr")); }, "cut.exr");
}
