// A material's diffuse texture, through loadScene: its mean (in linear RGB) becomes the
// albedo (OBJ map_Kd, glTF baseColorTexture), and a texture that cannot be read leaves a
// warning. The PNGs are written here through libpng's write API, one of every kind the
// reader takes (palette, grey, grey + alpha, RGB, RGBA; 1- to 16-bit; Adam7-interlaced), and
// each must give the mean of the pixels it was written with.
#include <gtest/gtest.h>

#include <png.h>

#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "../libvdblight/src/scene/texture_mean.h"  // internal: the reader itself, for every PNG kind
#include "scene_formats_util.h"
#include "test_util.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectVec;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

/// A PNG image as libpng writes it: rows of bytes as PNG stores them (samples packed below 8
/// bits, 16-bit samples big-endian).
struct PngSpec {
    png_uint_32 width = 0, height = 0;
    int depth = 8, colourType = PNG_COLOR_TYPE_RGB;
    bool interlaced = false;
    std::vector<png_color> palette;
    std::vector<png_byte> paletteAlpha;  ///< tRNS of a palette image
    std::vector<std::vector<uint8_t>> rows;
};

void appendBytes(png_structp png, png_bytep data, std::size_t n) {
    static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), n);
}

/// Encodes `s` into `out`; false if libpng refused it.
bool encodePng(const PngSpec& s, std::vector<png_bytep>& rowPointers, std::string* out) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, out, appendBytes, nullptr);
    png_set_IHDR(png, info, s.width, s.height, s.depth, s.colourType,
                 s.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (!s.palette.empty()) png_set_PLTE(png, info, s.palette.data(), int(s.palette.size()));
    if (!s.paletteAlpha.empty()) png_set_tRNS(png, info, s.paletteAlpha.data(), int(s.paletteAlpha.size()), nullptr);
    png_write_info(png, info);
    png_write_image(png, rowPointers.data());  // all seven passes of an interlaced image
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

std::string pngBytes(PngSpec s) {
    std::vector<png_bytep> rowPointers;
    for (auto& r : s.rows) rowPointers.push_back(r.data());
    std::string out;
    EXPECT_TRUE(encodePng(s, rowPointers, &out)) << "libpng refused the test image";
    return out;
}

/// An 8-bit RGB PNG of `rows` (each 3 * width bytes).
std::string rgbPng(const std::vector<std::vector<uint8_t>>& rows) {
    PngSpec s;
    s.width = png_uint_32(rows[0].size() / 3);
    s.height = png_uint_32(rows.size());
    s.rows = rows;
    return pngBytes(s);
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

namespace {

double srgbToLinearUnit(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

/// One kind of PNG: colour type, bit depth, size, interlacing.
struct PngKind {
    const char* name;
    int colourType, depth;
    png_uint_32 width, height;
    bool interlaced;
};

/// Sample `index` of a row of `depth`-bit samples, as PNG packs them (first sample in the
/// high bits of a byte, 16-bit samples big-endian).
void putSample(std::vector<uint8_t>& row, std::size_t index, int depth, unsigned v) {
    if (depth == 16) {
        row[2 * index] = uint8_t(v >> 8);
        row[2 * index + 1] = uint8_t(v & 0xff);
    } else {
        const std::size_t bit = index * std::size_t(depth);
        row[bit / 8] = uint8_t(row[bit / 8] | v << (8 - depth - int(bit % 8)));
    }
}

/// An image of `kind` with varied samples, and the mean linear RGB of its pixels (alpha
/// ignored; palette entries and samples are sRGB).
PngSpec makeImage(const PngKind& kind, Vec3d& mean) {
    PngSpec s;
    s.width = kind.width;
    s.height = kind.height;
    s.depth = kind.depth;
    s.colourType = kind.colourType;
    s.interlaced = kind.interlaced;
    const bool palette = kind.colourType == PNG_COLOR_TYPE_PALETTE;
    const int channels = kind.colourType == PNG_COLOR_TYPE_GRAY || palette ? 1
                         : kind.colourType == PNG_COLOR_TYPE_GRAY_ALPHA    ? 2
                         : kind.colourType == PNG_COLOR_TYPE_RGB           ? 3
                                                                           : 4;
    const unsigned maxSample = (1u << kind.depth) - 1;
    if (palette) {
        for (int i = 0; i < std::min(7, int(maxSample) + 1); ++i) {
            s.palette.push_back(png_color{png_byte((53 * i + 11) % 256), png_byte((97 * i + 200) % 256),
                                          png_byte((29 * i * i + 3) % 256)});
            s.paletteAlpha.push_back(png_byte(255 - 40 * i));  // ignored by the mean
        }
    }
    Vec3d sum(0, 0, 0);
    for (png_uint_32 y = 0; y < kind.height; ++y) {
        std::vector<uint8_t> row((std::size_t(kind.width) * channels * kind.depth + 7) / 8, 0);
        for (png_uint_32 x = 0; x < kind.width; ++x) {
            unsigned v[4];
            for (int c = 0; c < channels; ++c) {
                const unsigned pattern = 131 * x + 71 * y + 37 * unsigned(c) + 13 * x * y + 4099 * x * x;
                v[c] = palette ? pattern % unsigned(s.palette.size()) : pattern % (maxSample + 1);
                putSample(row, std::size_t(x) * channels + c, kind.depth, v[c]);
            }
            if (palette) {
                const png_color& e = s.palette[v[0]];
                sum += Vec3d(srgbToLinearUnit(e.red / 255.0), srgbToLinearUnit(e.green / 255.0), srgbToLinearUnit(e.blue / 255.0));
            } else if (channels <= 2) {
                const double g = srgbToLinearUnit(double(v[0]) / maxSample);
                sum += Vec3d(g, g, g);
            } else {
                sum += Vec3d(srgbToLinearUnit(double(v[0]) / maxSample), srgbToLinearUnit(double(v[1]) / maxSample),
                             srgbToLinearUnit(double(v[2]) / maxSample));
            }
        }
        s.rows.push_back(std::move(row));
    }
    mean = sum / (double(kind.width) * kind.height);
    return s;
}

}  // namespace

// Every kind of PNG gives the mean of the pixels it was written with: palettes (with a tRNS
// chunk, and 4-bit packed), grey from 1 to 16 bits, grey + alpha, RGB and RGBA in 8 and 16
// bits, and Adam7-interlaced images, whose passes hold each pixel once (the 1 x 1 and 3 x 2
// ones have empty passes).
TEST(SceneFormats, EveryPngKindGivesTheMeanOfItsPixels) {
    const PngKind kinds[] = {
        {"palette 8-bit with tRNS", PNG_COLOR_TYPE_PALETTE, 8, 5, 4, false},
        {"palette 4-bit", PNG_COLOR_TYPE_PALETTE, 4, 5, 3, false},
        {"grey 1-bit", PNG_COLOR_TYPE_GRAY, 1, 10, 3, false},
        {"grey 8-bit", PNG_COLOR_TYPE_GRAY, 8, 7, 2, false},
        {"grey 16-bit", PNG_COLOR_TYPE_GRAY, 16, 4, 3, false},
        {"grey + alpha 8-bit", PNG_COLOR_TYPE_GRAY_ALPHA, 8, 6, 5, false},
        {"grey + alpha 16-bit", PNG_COLOR_TYPE_GRAY_ALPHA, 16, 3, 3, false},
        {"RGB 16-bit", PNG_COLOR_TYPE_RGB, 16, 3, 2, false},
        {"RGBA 8-bit", PNG_COLOR_TYPE_RGB_ALPHA, 8, 4, 4, false},
        {"RGBA 16-bit", PNG_COLOR_TYPE_RGB_ALPHA, 16, 3, 4, false},
        {"RGB 8-bit interlaced", PNG_COLOR_TYPE_RGB, 8, 9, 7, true},
        {"RGBA 16-bit interlaced", PNG_COLOR_TYPE_RGB_ALPHA, 16, 5, 6, true},
        {"palette interlaced 1 x 1", PNG_COLOR_TYPE_PALETTE, 8, 1, 1, true},
        {"grey + alpha interlaced 3 x 2", PNG_COLOR_TYPE_GRAY_ALPHA, 8, 3, 2, true},
    };
    for (const PngKind& kind : kinds) {
        Vec3d want;
        const std::string png = pngBytes(makeImage(kind, want));
        Rgb mean(-1, -1, -1);
        std::string why;
        ASSERT_TRUE(pngMeanLinear(reinterpret_cast<const uint8_t*>(png.data()), png.size(), mean, why)) << kind.name << ": " << why;
        expectVec(Vec3d(mean), want, 1e-6, kind.name);
    }
}

// A PNG that ends early or whose image data is damaged is refused with libpng's reason, not
// read as far as it goes.
TEST(SceneFormats, DamagedPngIsRefusedWithAReason) {
    Vec3d want;
    const std::string png = pngBytes(makeImage({"RGB", PNG_COLOR_TYPE_RGB, 8, 16, 16, false}, want));
    Rgb mean;
    std::string why;
    const std::string cut = png.substr(0, png.size() / 2);
    EXPECT_FALSE(pngMeanLinear(reinterpret_cast<const uint8_t*>(cut.data()), cut.size(), mean, why));
    EXPECT_NE(why.find("ends early"), std::string::npos) << why;
    std::string damaged = png;
    damaged[damaged.find("IDAT") + 10] ^= 0x5a;  // the CRC no longer matches
    why.clear();
    EXPECT_FALSE(pngMeanLinear(reinterpret_cast<const uint8_t*>(damaged.data()), damaged.size(), mean, why));
    EXPECT_FALSE(why.empty());
    EXPECT_FALSE(pngMeanLinear(reinterpret_cast<const uint8_t*>("GIF89a.."), 8, mean, why));
    EXPECT_EQ(why, "not a PNG file");
}
