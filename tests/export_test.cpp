// Export: the files are checked by readers written here from the specifications (KTX 2.0,
// Khronos Data Format, Microsoft DDS), by OpenEXR, and the texel values against the volume
// (node values exactly; the packed layouts against the SH irradiance formula).
#include <gtest/gtest.h>

#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfChannelList.h>
#include <half.h>

#include <cfloat>
#include <cstring>
#include <fstream>
#include <iterator>

#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/errors.h"
#include "vdblight/export.h"
#include "vdblight/query.h"
#include "vdblight/sampling.h"
#include "vdblight/sh.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
Volume makeVolume(int nx, int ny, int nz, uint64_t seed) { return test::randomShVolume(nx, ny, nz, 0.3, seed); }

std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}
uint32_t u32(const std::vector<uint8_t>& b, std::size_t at) {
    return uint32_t(b.at(at)) | uint32_t(b.at(at + 1)) << 8 | uint32_t(b.at(at + 2)) << 16 | uint32_t(b.at(at + 3)) << 24;
}
uint64_t u64(const std::vector<uint8_t>& b, std::size_t at) { return u32(b, at) | uint64_t(u32(b, at + 4)) << 32; }
float f32(const std::vector<uint8_t>& b, std::size_t at) {
    const uint32_t bits = u32(b, at);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}
float f16(const std::vector<uint8_t>& b, std::size_t at) {
    Imath::half h;
    h.setBits(uint16_t(b.at(at) | b.at(at + 1) << 8));
    return float(h);
}

ExportOptions options(TextureFormat f, ExportLayout l, bool half) {
    ExportOptions o;
    o.format = f;
    o.layout = l;
    o.halfFloat = half;
    return o;
}

// The texels of texture `name` in the raw export of `dir`.
std::vector<float> rawTexels(const std::string& dir, const std::string& name, bool half) {
    const std::vector<uint8_t> b = readFile(dir + "/" + name + ".raw");
    std::vector<float> out;
    for (std::size_t at = 0; at < b.size(); at += half ? 2 : 4) out.push_back(half ? f16(b, at) : f32(b, at));
    return out;
}

// KTX 2.0 checker, field by field (KTX 2.0 spec sections "File Structure", "Index", "Level
// Index", "Data Format Descriptor", "Key/Value Data", "KTXorientation"). Returns the
// level-0 data offset.
uint64_t checkKtx2(const std::vector<uint8_t>& b, uint32_t vkFormat, int nx, int ny, int nz) {
    const uint8_t id[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    EXPECT_EQ(std::memcmp(b.data(), id, 12), 0);
    const uint32_t typeSize = vkFormat == 97 ? 2 : 4, texelSize = 4 * typeSize;
    EXPECT_EQ(u32(b, 12), vkFormat);
    EXPECT_EQ(u32(b, 16), typeSize);
    EXPECT_EQ(u32(b, 20), uint32_t(nx));
    EXPECT_EQ(u32(b, 24), uint32_t(ny));
    EXPECT_EQ(u32(b, 28), uint32_t(nz));  // pixelDepth > 0: 3-D
    EXPECT_EQ(u32(b, 32), 0u);            // layerCount
    EXPECT_EQ(u32(b, 36), 1u);            // faceCount
    EXPECT_EQ(u32(b, 40), 1u);            // levelCount
    EXPECT_EQ(u32(b, 44), 0u);            // supercompressionScheme
    const uint32_t dfdOffset = u32(b, 48), dfdLength = u32(b, 52), kvdOffset = u32(b, 56), kvdLength = u32(b, 60);
    EXPECT_EQ(u64(b, 64), 0u);  // sgdByteOffset
    EXPECT_EQ(u64(b, 72), 0u);  // sgdByteLength
    const uint64_t levelOffset = u64(b, 80), levelLength = u64(b, 88), uncompressed = u64(b, 96);
    EXPECT_EQ(dfdOffset, 104u);  // right after the one-entry level index
    // DFD: total size, then one basic block with four samples.
    EXPECT_EQ(u32(b, dfdOffset), dfdLength);
    EXPECT_EQ(dfdLength, 4u + 24u + 4u * 16u);
    EXPECT_EQ(kvdOffset, dfdOffset + dfdLength);  // dfdTotalSize == kvdByteOffset - dfdByteOffset
    const std::size_t blk = dfdOffset + 4;
    EXPECT_EQ(u32(b, blk) & 0x1FFFFu, 0u);       // vendorId KHRONOS
    EXPECT_EQ(u32(b, blk) >> 17, 0u);            // descriptorType BASICFORMAT
    EXPECT_EQ(u32(b, blk + 4) & 0xFFFFu, 2u);    // versionNumber
    EXPECT_EQ(u32(b, blk + 4) >> 16, 88u);       // descriptorBlockSize
    EXPECT_EQ(b[blk + 8], 1);                    // colorModel RGBSDA
    EXPECT_EQ(b[blk + 9], 1);                    // colorPrimaries BT709
    EXPECT_EQ(b[blk + 10], 1);                   // transferFunction LINEAR
    EXPECT_EQ(b[blk + 11], 0);                   // flags ALPHA_STRAIGHT
    EXPECT_EQ(u32(b, blk + 12), 0u);             // texelBlockDimension0..3: 1x1x1x1
    EXPECT_EQ(b[blk + 16], texelSize);           // bytesPlane0
    for (int p = 1; p < 8; ++p) EXPECT_EQ(b[blk + 16 + p], 0) << p;
    const int channel[4] = {0, 1, 2, 15};
    for (int s = 0; s < 4; ++s) {
        const std::size_t at = blk + 24 + 16 * s;
        EXPECT_EQ(u32(b, at) & 0xFFFFu, uint32_t(s) * typeSize * 8) << "bitOffset of sample " << s;
        EXPECT_EQ((u32(b, at) >> 16) & 0xFFu, typeSize * 8 - 1) << "bitLength of sample " << s;
        EXPECT_EQ(b[at + 3] & 0x0F, channel[s]) << "channelType of sample " << s;
        EXPECT_EQ(b[at + 3] & 0xF0, 0x80 | 0x40) << "qualifiers FLOAT|SIGNED of sample " << s;
        EXPECT_EQ(u32(b, at + 4), 0u);  // samplePosition
        EXPECT_EQ(f32(b, at + 8), -1.0f);
        EXPECT_EQ(f32(b, at + 12), 1.0f);
    }
    // Key/value data: sorted keys, each entry padded to 4, lengths adding up to kvdByteLength.
    std::size_t at = kvdOffset;
    std::vector<std::string> keys;
    std::string orientation;
    while (at < kvdOffset + kvdLength) {
        const uint32_t len = u32(b, at);
        const std::string kv(reinterpret_cast<const char*>(&b[at + 4]), len);
        const std::string key = kv.substr(0, kv.find('\0'));
        if (key == "KTXorientation") orientation = kv.substr(key.size() + 1);
        keys.push_back(key);
        at += 4 + (len + 3) / 4 * 4;
    }
    EXPECT_EQ(at, std::size_t(kvdOffset) + kvdLength);
    EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
    EXPECT_EQ(orientation, std::string("ruo", 4));  // NUL-terminated, matches /^[rl][du][oi]$/
    // Level data: aligned to lcm(texel size, 4), zero padding before it, exact length, at the end.
    EXPECT_EQ(levelOffset % texelSize, 0u);
    EXPECT_GE(levelOffset, uint64_t(at));
    EXPECT_LT(levelOffset - at, texelSize);
    for (uint64_t p = at; p < levelOffset; ++p) EXPECT_EQ(b[p], 0);
    EXPECT_EQ(levelLength, uint64_t(nx) * ny * nz * texelSize);
    EXPECT_EQ(uncompressed, levelLength);
    EXPECT_EQ(b.size(), levelOffset + levelLength);
    return levelOffset;
}

// DDS checker (Microsoft: DDS_HEADER, DDS_PIXELFORMAT, DDS_HEADER_DXT10). Returns the data offset.
uint64_t checkDds(const std::vector<uint8_t>& b, uint32_t dxgi, int nx, int ny, int nz) {
    EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "DDS ");
    EXPECT_EQ(u32(b, 4), 124u);  // dwSize
    const uint32_t flags = u32(b, 8);
    for (uint32_t required : {0x1u, 0x2u, 0x4u, 0x1000u, 0x800000u})  // CAPS HEIGHT WIDTH PIXELFORMAT DEPTH
        EXPECT_EQ(flags & required, required) << std::hex << required;
    EXPECT_EQ(u32(b, 12), uint32_t(ny));
    EXPECT_EQ(u32(b, 16), uint32_t(nx));
    const uint32_t texelSize = dxgi == 10 ? 8 : 16;
    if (flags & 0x8) {
        EXPECT_EQ(u32(b, 20), uint32_t(nx) * texelSize);  // pitch
    }
    EXPECT_EQ(u32(b, 24), uint32_t(nz));
    EXPECT_LE(u32(b, 28), 1u);  // mip count 0 or 1
    EXPECT_EQ(u32(b, 76), 32u);  // ddspf.dwSize
    EXPECT_EQ(u32(b, 80) & 0x4u, 0x4u);  // DDPF_FOURCC
    EXPECT_EQ(std::string(b.begin() + 84, b.begin() + 88), "DX10");
    EXPECT_EQ(u32(b, 108) & 0x1000u, 0x1000u);  // DDSCAPS_TEXTURE
    EXPECT_EQ(u32(b, 112) & 0x200000u, 0x200000u);  // DDSCAPS2_VOLUME
    EXPECT_EQ(u32(b, 128), dxgi);
    EXPECT_EQ(u32(b, 132), 4u);  // D3D10_RESOURCE_DIMENSION_TEXTURE3D
    EXPECT_EQ(u32(b, 136) & 0x4u, 0u);  // not a cube map
    EXPECT_EQ(u32(b, 140), 1u);  // arraySize
    EXPECT_EQ(b.size(), 148u + uint64_t(nx) * ny * nz * texelSize);
    return 148;
}
}  // namespace

TEST(Export, UniformVolumeExportsItsNodesExactly) {
    const Volume v = makeVolume(5, 4, 3, 1);
    test::TempDir dir;
    const ExportSummary s = exportTextures(v, dir.file("raw"), options(TextureFormat::Raw, ExportLayout::Sh2, false));
    EXPECT_EQ(s.lattice.dims[0], 5);
    EXPECT_EQ(s.lattice.dims[1], 4);
    EXPECT_EQ(s.lattice.dims[2], 3);
    const GridSpec& g = v.levels[0].grid;
    for (int j = 0; j < 9; ++j) {
        const std::vector<float> t = rawTexels(dir.file("raw"), std::string("sh2_") + sh::gridName(j), false);
        ASSERT_EQ(t.size(), g.nodeCount() * 4);
        for (std::size_t n = 0; n < g.nodeCount(); ++n)
            for (int c = 0; c < 3; ++c) {
                const float want = v.levels[0].data[(n * 9 + j) * 3 + c];
                // Equal up to one rounding of the query's folded A_l constants (zeros stay zero).
                EXPECT_LE(std::fabs(t[n * 4 + c] - want), std::fabs(want) * FLT_EPSILON) << "node " << n << " coeff " << j;
            }
    }
}

TEST(Export, PackedLayoutsEvaluateTheShIrradiance) {
    const Volume v = makeVolume(3, 3, 3, 2);
    test::TempDir dir;
    exportTextures(v, dir.file("p"), options(TextureFormat::Raw, ExportLayout::Sh2Packed, false));
    exportTextures(v, dir.file("s1"), options(TextureFormat::Raw, ExportLayout::Sh1, false));
    const char* names[7] = {"shAr", "shAg", "shAb", "shBr", "shBg", "shBb", "shC"};
    std::vector<std::vector<float>> p, s1;
    for (const char* n : names) p.push_back(rawTexels(dir.file("p"), n, false));
    for (int i = 0; i < 3; ++i) s1.push_back(rawTexels(dir.file("s1"), names[i], false));
    Rng rng(3);
    for (std::size_t node = 0; node < 27; ++node)
        for (int trial = 0; trial < 5; ++trial) {
            const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
            const float* L = v.levels[0].nodeData(node, 9);
            double y[9];
            sh::evalGeneric(2, Vec3d(n), y);
            for (int c = 0; c < 3; ++c) {
                double want = 0, want1 = 0;
                for (int j = 0; j < 9; ++j) {
                    const double term = sh::kCosineLobe[sh::bandOf(j)] * L[3 * j + c] * y[j];
                    want += term;
                    if (j < 4) want1 += term;
                }
                const float* a = &p[c][node * 4];
                const float* b = &p[3 + c][node * 4];
                const double got = a[0] * n.x + a[1] * n.y + a[2] * n.z + a[3] +
                                   b[0] * n.x * n.y + b[1] * n.y * n.z + b[2] * n.z * n.z + b[3] * n.z * n.x +
                                   p[6][node * 4 + c] * (n.x * n.x - n.y * n.y);
                EXPECT_NEAR(got, want, 1e-5);
                const float* a1 = &s1[c][node * 4];
                EXPECT_NEAR(a1[0] * n.x + a1[1] * n.y + a1[2] * n.z + a1[3], want1, 1e-5);
            }
        }
}

TEST(Export, Ktx2HeaderDfdAndDataFollowTheSpecification) {
    const Volume v = makeVolume(5, 4, 3, 4);
    test::TempDir dir;
    for (bool half : {true, false}) {
        const std::string out = dir.file(half ? "h" : "f"), raw = dir.file(half ? "hr" : "fr");
        exportTextures(v, out, options(TextureFormat::Ktx2, ExportLayout::Sh2Packed, half));
        exportTextures(v, raw, options(TextureFormat::Raw, ExportLayout::Sh2Packed, half));
        for (const char* name : {"shAr", "shBg", "shC"}) {
            const std::vector<uint8_t> b = readFile(out + "/" + name + ".ktx2");
            const uint64_t offset = checkKtx2(b, half ? 97 : 109, 5, 4, 3);
            const std::vector<uint8_t> r = readFile(raw + "/" + name + ".raw");
            EXPECT_TRUE(std::equal(r.begin(), r.end(), b.begin() + std::ptrdiff_t(offset))) << name;
        }
    }
}

TEST(Export, DdsHeaderFollowsTheSpecification) {
    const Volume v = makeVolume(5, 4, 3, 5);
    test::TempDir dir;
    for (bool half : {true, false}) {
        const std::string out = dir.file(half ? "h" : "f"), raw = dir.file(half ? "hr" : "fr");
        exportTextures(v, out, options(TextureFormat::Dds, ExportLayout::Sh1, half));
        exportTextures(v, raw, options(TextureFormat::Raw, ExportLayout::Sh1, half));
        for (const char* name : {"shAr", "shAg", "shAb"}) {
            const std::vector<uint8_t> b = readFile(out + "/" + name + ".dds");
            const uint64_t offset = checkDds(b, half ? 10 : 2, 5, 4, 3);
            const std::vector<uint8_t> r = readFile(raw + "/" + name + ".raw");
            EXPECT_TRUE(std::equal(r.begin(), r.end(), b.begin() + std::ptrdiff_t(offset))) << name;
        }
    }
}

TEST(Export, ExrAtlasReadsBackThroughOpenExr) {
    const Volume v = makeVolume(4, 3, 7, 6);  // 7 slices: 3 columns x 3 rows, two empty tiles
    test::TempDir dir;
    exportTextures(v, dir.file("e"), options(TextureFormat::ExrAtlas, ExportLayout::Sh2, true));
    exportTextures(v, dir.file("r"), options(TextureFormat::Raw, ExportLayout::Sh2, true));
    const std::vector<float> raw = rawTexels(dir.file("r"), "sh2_sh_l1m0", true);
    Imf::InputFile file(dir.file("e/sh2_sh_l1m0.exr").c_str());
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    const int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    EXPECT_EQ(width, 3 * 4);
    EXPECT_EQ(height, 3 * 3);
    ASSERT_NE(h.findTypedAttribute<Imf::IntAttribute>("vdblightAtlasColumns"), nullptr);
    ASSERT_NE(h.findTypedAttribute<Imf::IntAttribute>("vdblightAtlasRows"), nullptr);
    EXPECT_EQ(h.findTypedAttribute<Imf::IntAttribute>("vdblightAtlasColumns")->value(), 3);
    EXPECT_EQ(h.findTypedAttribute<Imf::IntAttribute>("vdblightAtlasRows")->value(), 3);
    EXPECT_EQ(h.findTypedAttribute<Imf::IntAttribute>("vdblightSlices")->value(), 7);
    for (const char* c : {"R", "G", "B", "A"}) {
        ASSERT_NE(h.channels().findChannel(c), nullptr) << c;
        EXPECT_EQ(h.channels().findChannel(c)->type, Imf::HALF);
    }
    std::vector<float> px(std::size_t(width) * height * 4);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data() + c), 16, 16 * std::size_t(width)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (int k = 0; k < 7; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i)
                for (int c = 0; c < 4; ++c) {
                    const int x = (k % 3) * 4 + i, y = (k / 3) * 3 + j;  // z = 0 top left, row-major tiles
                    EXPECT_EQ(px[(std::size_t(y) * width + x) * 4 + c], raw[((std::size_t(k) * 3 + j) * 4 + i) * 4 + c]);
                }
}

TEST(Export, ResolutionResamplesAlongTheLongestAxis) {
    const Volume v = makeVolume(5, 3, 2, 7);  // node box 1.2 x 0.6 x 0.3
    test::TempDir dir;
    ExportOptions o = options(TextureFormat::Raw, ExportLayout::Sh1, false);
    o.resolution = 9;
    const ExportSummary s = exportTextures(v, dir.file("r"), o);
    EXPECT_EQ(s.lattice.dims[0], 9);
    EXPECT_EQ(s.lattice.dims[1], 5);
    EXPECT_EQ(s.lattice.dims[2], 3);
}

TEST(Export, BadRequestsFailBeforeWritingAnything) {
    const Volume v = makeVolume(3, 3, 3, 8);
    test::TempDir dir;
    EXPECT_THROW(parseTextureFormat("png"), ValueError);
    EXPECT_THROW(parseExportLayout("bogus"), ValueError);
    EXPECT_THROW(exportTextures(v, dir.file("a"), options(TextureFormat::Raw, ExportLayout::Vectors, true)), FormatError);
    ExportOptions huge = options(TextureFormat::Dds, ExportLayout::Sh2, true);
    huge.resolution = 3000;
    EXPECT_THROW(exportTextures(v, dir.file("a"), huge), ValueError);
    huge.format = TextureFormat::Raw;
    huge.resolution = 600;
    huge.maxBytes = 1 << 20;
    try {
        exportTextures(v, dir.file("a"), huge);
        ADD_FAILURE() << "no memory refusal";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("GiB"), std::string::npos) << e.what();
    }
    Volume bright = v;
    bright.levels[0].data[0] = 1e6f;
    EXPECT_THROW(exportTextures(bright, dir.file("a"), options(TextureFormat::Raw, ExportLayout::Sh2, true)), ValueError);
    test::writeTextFile(dir.file("file"), "x");
    EXPECT_THROW(exportTextures(v, dir.file("file/sub"), options(TextureFormat::Raw, ExportLayout::Sh2, true)), IoError);
    EXPECT_FALSE(fs::exists(dir.file("a")));
    const auto entries = std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator());
    EXPECT_EQ(entries, 1);  // only "file"
}

TEST(Export, TheDefaultShHookRefusesOtherBases) {
    struct OtherKind : VolumeLookup {
        Rgb irradiance(const Vec3f&, const Vec3f&) const override { return {}; }
        Bounds bounds() const override { return {}; }
    } other;
    Rgb out[9];
    EXPECT_THROW(other.shRadiance(Vec3d(0, 0, 0), out), FormatError);
}
