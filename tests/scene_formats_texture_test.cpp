// A material's diffuse texture, through loadScene: its mean (in linear RGB) becomes the
// albedo (OBJ map_Kd, glTF baseColorTexture), and a texture that cannot be read leaves a
// warning. The PNGs are written here (zlib), each row with another PNG filter, so that the
// reader's every filter is checked against a known mean.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <zlib.h>

#include "scene_formats_util.h"
#include "test_util.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectVec;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

void putBe32(std::string& s, uint32_t v) { for (int k = 3; k >= 0; --k) s += char((v >> (8 * k)) & 0xff); }

std::string pngChunk(const char* type, const std::string& body) {
    std::string s;
    putBe32(s, uint32_t(body.size()));
    const std::string typed = std::string(type, 4) + body;
    s += typed;
    putBe32(s, uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typed.data()), uInt(typed.size()))));
    return s;
}

int paethPredictor(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/// An 8-bit RGB PNG of `rows` (each 3 * width bytes); row r is stored with filter r % 5, so
/// that every PNG filter is exercised.
std::string rgbPng(const std::vector<std::vector<uint8_t>>& rows) {
    const uint32_t width = uint32_t(rows[0].size() / 3), height = uint32_t(rows.size());
    std::string raw;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        const int filter = int(r % 5);
        raw += char(filter);
        for (std::size_t i = 0; i < rows[r].size(); ++i) {
            const int a = i >= 3 ? rows[r][i - 3] : 0, b = r > 0 ? rows[r - 1][i] : 0,
                      c = (r > 0 && i >= 3) ? rows[r - 1][i - 3] : 0;
            const int pred = filter == 1 ? a : filter == 2 ? b : filter == 3 ? (a + b) / 2 : filter == 4 ? paethPredictor(a, b, c) : 0;
            raw += char(uint8_t(rows[r][i] - pred));
        }
    }
    uLongf size = compressBound(uLong(raw.size()));
    std::string z(size, '\0');
    compress(reinterpret_cast<Bytef*>(&z[0]), &size, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()));
    z.resize(size);
    std::string ihdr;
    putBe32(ihdr, width);
    putBe32(ihdr, height);
    ihdr += std::string("\x08\x02\x00\x00\x00", 5);
    return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", z) + pngChunk("IEND", "");
}

double srgbToLinearD(int v) { const double c = v / 255.0; return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

// A material whose colour is a texture gets the texture's mean (in linear RGB) as its albedo:
// OBJ map_Kd replaces Kd, glTF's baseColorTexture multiplies baseColorFactor.
TEST(SceneFormats, DiffuseTextureMeanIsTheAlbedo) {
    TempDir dir;
    std::vector<std::vector<uint8_t>> rows;
    Vec3d sum(0, 0, 0);
    for (int r = 0; r < 7; ++r) {
        std::vector<uint8_t> row;
        for (int x = 0; x < 3; ++x) {
            const int v[3] = {(37 * r + 91 * x) % 256, (200 - 13 * r * x) & 255, (17 * x + 5 * r * r) % 256};
            for (int k = 0; k < 3; ++k) row.push_back(uint8_t(v[k]));
            sum += Vec3d(srgbToLinearD(v[0]), srgbToLinearD(v[1]), srgbToLinearD(v[2]));
        }
        rows.push_back(row);
    }
    const Vec3d mean = sum / 21.0;
    {
        std::ofstream f(dir.file("wood.png"), std::ios::binary);
        const std::string png = rgbPng(rows);
        f.write(png.data(), std::streamsize(png.size()));
    }
    writeTextFile(dir.file("tex.mtl"), "newmtl Wood\nKd 1 1 1\nmap_Kd wood.png\n");
    writeTextFile(dir.file("tex.obj"), "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Wood\nf 1 2 3\n");
    SceneLoadReport r;
    const Scene obj = loadScene(dir.file("tex.obj"), {}, &r);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
    expectVec(Vec3d(obj.material(0).albedo), mean, 1e-6, "OBJ map_Kd mean");

    writeTextFile(dir.file("tex.gltf"), R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.25,1,1],"baseColorTexture":{"index":0}}}],
"textures":[{"source":0}],"images":[{"uri":"wood.png"}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
"bufferViews":[{"buffer":0,"byteLength":36}],
"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})");
    const Scene gltf = loadScene(dir.file("tex.gltf"), {}, &r);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
    expectVec(Vec3d(gltf.material(0).albedo), Vec3d(mean.x * 0.5, mean.y * 0.25, mean.z), 1e-6, "glTF factor x mean");

    // A texture that is not a PNG is not read: the diffuse colour stays, with a warning.
    writeTextFile(dir.file("wood.png"), "not an image");
    const Scene bad = loadScene(dir.file("tex.obj"), {}, &r);
    expectVec(Vec3d(bad.material(0).albedo), {0.999, 0.999, 0.999}, 1e-6, "Kd 1 (clamped)");
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("1 diffuse texture(s) not read (first: '" + dir.file("wood.png") +
                                 "': not a PNG file (only PNG is read))"), std::string::npos) << r.warnings[0];
}
