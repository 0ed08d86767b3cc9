// Export of depth moments (depth_moments.h): the textures depth_x, depth_y, depth_z are RGBA8
// unorm in KTX2, DDS and raw whatever --half / --float says for the lighting textures, every
// byte / 255 is the node's stored value exactly, and the manifest states each texture's format.
// The EXR atlas has no 8-bit type and keeps half or float.
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <half.h>

#include <cmath>
#include <set>

#include "export_file_checks.h"
#include "manifest_util.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/export/export.h"
#include "vdblight/layout/layout.h"
#include "vdblight/sampling/sampling.h"

#include "thin_wall_util.h"

using namespace vdblight;
using namespace vdblight::test;

namespace {

constexpr int kNx = 4, kNy = 3, kNz = 5;
const char* const kAxes[3] = {"depth_x", "depth_y", "depth_z"};

// A single-level volume whose depth values run through every k/255 (value i is (37 i mod 256)
// / 255: 720 values, each of the 256 at least twice), stored as depth::quantize stores them.
Volume depthVolume() {
    Volume v = randomShVolume(kNx, kNy, kNz, 0.3, 12);
    VolumeLevel& level = v.levels[0];
    level.depth.resize(level.storedNodes() * depth::kFloatsPerNode);
    for (std::size_t i = 0; i < level.depth.size(); ++i) level.depth[i] = depth::quantize(double(i * 37 % 256) / 255.0);
    v.validate();
    return v;
}

// The value that component c (RGBA = mean +a, mean -a, sigma +a, sigma -a) of texel n of
// depth texture a holds, from a level's depth values (depth::kFloatsPerNode per node).
float depthValue(const std::vector<float>& values, std::size_t n, int a, int c) {
    const int channel[4] = {depth::kMeanPositive, depth::kMeanNegative, depth::kSigmaPositive, depth::kSigmaNegative};
    return values.at(n * depth::kFloatsPerNode + std::size_t(channel[c]) * 3 + std::size_t(a));
}

ExportOptions options(TextureFormat format, bool half) {
    ExportOptions o;
    o.format = format;
    o.layout = ExportLayout::Sh2Packed;
    o.halfFloat = half;
    return o;
}

// Reads the header of a KTX2 / DDS file (raw: none) for `vk` / `dxgi`; returns the data offset.
uint64_t checkHeader(TextureFormat format, const std::vector<uint8_t>& b, uint32_t vk, uint32_t dxgi) {
    if (format == TextureFormat::Ktx2) return checkKtx2(b, vk, kNx, kNy, kNz);
    if (format == TextureFormat::Dds) return checkDds(b, dxgi, kNx, kNy, kNz);
    return 0;
}

}  // namespace

TEST(ExportDepth, Rgba8UnormInKtx2DdsAndRawWhateverTheLightingPrecision) {
    const Volume v = depthVolume();
    const std::size_t nodes = v.levels[0].grid.nodeCount();
    test::TempDir dir;
    const struct {
        TextureFormat format;
        const char *ext, *formatKey;
    } containers[] = {{TextureFormat::Ktx2, ".ktx2", "vkFormat"},
                      {TextureFormat::Dds, ".dds", "dxgiFormat"},
                      {TextureFormat::Raw, ".raw", ""}};
    for (const auto& c : containers)
        for (bool half : {true, false}) {
            const std::string out = dir.file(std::string(c.ext + 1) + (half ? "_half" : "_float"));
            exportTextures(v, out, options(c.format, half));
            std::set<int> bytesSeen;
            for (int a = 0; a < 3; ++a) {
                const std::vector<uint8_t> b = readFile(out + "/" + kAxes[a] + c.ext);
                const uint64_t offset = checkHeader(c.format, b, kVkRgba8Unorm, kDxgiRgba8Unorm);
                ASSERT_EQ(b.size(), offset + nodes * 4) << kAxes[a] << c.ext;  // 4 B per texel: 12 B per node
                for (std::size_t n = 0; n < nodes; ++n)
                    for (int comp = 0; comp < 4; ++comp) {
                        const int byte = b[offset + n * 4 + std::size_t(comp)];
                        const float value = depthValue(v.levels[0].depth, n, a, comp);
                        // Exact: the byte is the value times 255, and reads back as the value itself.
                        EXPECT_EQ(double(byte), std::nearbyint(double(value) * 255.0)) << kAxes[a] << " node " << n;
                        EXPECT_EQ(float(byte / 255.0), value) << kAxes[a] << " node " << n << " component " << comp;
                        bytesSeen.insert(byte);
                    }
            }
            EXPECT_EQ(bytesSeen.size(), 256u);  // every k in 0..255 went through
            // The lighting textures keep --half / --float.
            const std::vector<uint8_t> light = readFile(out + "/shAr" + c.ext);
            const uint64_t offset = checkHeader(c.format, light, half ? kVkRgba16Sfloat : kVkRgba32Sfloat,
                                                half ? kDxgiRgba16Float : kDxgiRgba32Float);
            EXPECT_EQ(light.size(), offset + nodes * (half ? 8 : 16));
            // The manifest states each texture's format and size per texel.
            const nlohmann::json manifest = test::readManifest(out);
            const uint32_t lightCode = c.format == TextureFormat::Ktx2 ? (half ? kVkRgba16Sfloat : kVkRgba32Sfloat)
                                                                      : (half ? kDxgiRgba16Float : kDxgiRgba32Float);
            const uint32_t depthCode = c.format == TextureFormat::Ktx2 ? kVkRgba8Unorm : kDxgiRgba8Unorm;
            const struct {
                const char* name;
                const char* format;
                int bytes;
                uint32_t code;
            } expected[] = {{"shAr", half ? "rgba16_sfloat" : "rgba32_sfloat", half ? 8 : 16, lightCode},
                            {"depth_y", "rgba8_unorm", 4, depthCode}};
            for (const auto& e : expected) {
                nlohmann::json t;
                for (const nlohmann::json& each : manifest["textures"])
                    if (each["name"] == e.name) t = each;
                ASSERT_TRUE(t.is_object()) << e.name << " not in\n" << manifest;
                EXPECT_EQ(t["file"], e.name + std::string(c.ext)) << t;
                EXPECT_EQ(t["format"], e.format) << t;
                EXPECT_EQ(t["bytes_per_texel"], e.bytes) << t;
                if (c.format != TextureFormat::Raw) EXPECT_EQ(t[c.formatKey], e.code) << t;
                else EXPECT_FALSE(t.contains("vkFormat") || t.contains("dxgiFormat")) << t;
            }
            EXPECT_EQ(manifest["depth"]["format"], "rgba8_unorm");
            EXPECT_EQ(manifest["depth"]["bytes_per_node"], 12);
            EXPECT_EQ(manifest["vdblight_export_version"], 2);
        }
}

TEST(ExportDepth, ExrAtlasKeepsHalfOrFloat) {
    const Volume v = depthVolume();
    test::TempDir dir;
    for (bool half : {true, false}) {
        const std::string out = dir.file(half ? "half" : "float");
        exportTextures(v, out, options(TextureFormat::ExrAtlas, half));
        Imf::InputFile file((out + "/depth_z.exr").c_str());
        const Imf::Header& h = file.header();
        for (const char* name : {"R", "G", "B", "A"}) {
            ASSERT_NE(h.channels().findChannel(name), nullptr) << name;
            EXPECT_EQ(h.channels().findChannel(name)->type, half ? Imf::HALF : Imf::FLOAT);
        }
        const Imath::Box2i dw = h.dataWindow();
        const int width = dw.max.x - dw.min.x + 1;
        const std::vector<float> px = readExrRgba(file);
        const int columns = int(std::ceil(std::sqrt(double(kNz))));  // the manifest's exr_atlas.columns
        for (int k = 0; k < kNz; ++k)
            for (int j = 0; j < kNy; ++j)
                for (int i = 0; i < kNx; ++i)
                    for (int c = 0; c < 4; ++c) {
                        const int x = (k % columns) * kNx + i, y = (k / columns) * kNy + j;
                        const float value = depthValue(v.levels[0].depth, (std::size_t(k) * kNy + j) * kNx + i, 2, c);
                        EXPECT_EQ(px[(std::size_t(y) * width + x) * 4 + c], half ? float(Imath::half(value)) : value);
                    }
        const nlohmann::json depth = test::readManifest(out)["depth"];
        EXPECT_EQ(depth["format"], half ? "rgba16_sfloat" : "rgba32_sfloat") << depth;
        EXPECT_EQ(depth["bytes_per_node"], half ? 24 : 48) << depth;
    }
}

// A .vdb baked with --half holds k/255 rounded to half (by up to 2^-12, a sixteenth of a
// step of 1/255): the export's rounding gives back byte k.
TEST(ExportDepth, HalfStoredValuesGiveBackTheirByte) {
    Volume v = depthVolume();
    const std::vector<float> exact = v.levels[0].depth;
    for (float& d : v.levels[0].depth) d = float(Imath::half(d));
    test::TempDir dir;
    exportTextures(v, dir.file("out"), options(TextureFormat::Raw, true));
    int changed = 0;
    for (int a = 0; a < 3; ++a) {
        const std::vector<uint8_t> b = readFile(dir.file("out") + "/" + kAxes[a] + ".raw");
        ASSERT_EQ(b.size(), v.levels[0].grid.nodeCount() * 4);
        for (std::size_t n = 0; n < v.levels[0].grid.nodeCount(); ++n)
            for (int comp = 0; comp < 4; ++comp) {
                const float want = depthValue(exact, n, a, comp);
                changed += depthValue(v.levels[0].depth, n, a, comp) != want;
                EXPECT_EQ(float(b[n * 4 + std::size_t(comp)] / 255.0), want) << kAxes[a] << " node " << n;
            }
    }
    EXPECT_GT(changed, 0);  // half did round some values
}

TEST(ExportDepth, ResampledLatticeExportsNoDepth) {
    const Volume v = depthVolume();
    test::TempDir dir;
    ExportOptions o = options(TextureFormat::Raw, false);
    o.resolution = 9;
    exportTextures(v, dir.file("res"), o);
    EXPECT_EQ(test::readManifest(dir.file("res"))["depth"]["exported"], false);
    EXPECT_FALSE(std::ifstream(dir.file("res") + "/depth_x.raw").good());
}

// A bilevel / adaptive volume is exported on its finest lattice: a texel that is a node of the
// finest level carries that node's depth; any other texel lies in cells that were not refined,
// so hold no geometry, and carries "free for a whole cell" (mean 1, sigma 0) on every face.
TEST(ExportDepth, MultiLevelVolumesExportTheFinestNodesDepthAndFreeTexelsElsewhere) {
    const Volume v = randomAdaptiveVolume(thinWallScene(), 5, 6);
    v.validate();
    ASSERT_EQ(v.levels.size(), 3u);
    const VolumeLevel& finest = v.levels.back();
    ASSERT_TRUE(finest.sparse());
    test::TempDir dir;
    exportTextures(v, dir.file("ml"), options(TextureFormat::Raw, false));
    ASSERT_EQ(test::readManifest(dir.file("ml"))["depth"]["exported"], true);
    std::size_t nodes = 0, free = 0;
    for (int a = 0; a < 3; ++a) {
        const std::vector<uint8_t> b = readFile(dir.file("ml") + "/" + kAxes[a] + ".raw");
        ASSERT_EQ(b.size(), finest.grid.nodeCount() * 4) << kAxes[a];
        for (std::size_t n = 0; n < finest.grid.nodeCount(); ++n) {
            const int64_t at = findNode(finest, n);
            for (int c = 0; c < 4; ++c) {
                const float want = at >= 0 ? depthValue(finest.depth, std::size_t(at), a, c) : (c < 2 ? 1.0f : 0.0f);
                ASSERT_EQ(float(b[n * 4 + std::size_t(c)] / 255.0), want) << kAxes[a] << " texel " << n << " component " << c;
            }
            (at >= 0 ? nodes : free) += a == 0;
        }
    }
    EXPECT_GT(nodes, 0u);
    EXPECT_GT(free, 0u);
}
