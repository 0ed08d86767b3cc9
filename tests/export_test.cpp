// Export: the files are checked by readers written here from the specifications (KTX 2.0,
// Khronos Data Format, Microsoft DDS; export_file_checks.h), by OpenEXR, and the texel values
// against the volume (node values exactly; the packed layouts against the SH irradiance formula).
#include <gtest/gtest.h>

#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfChannelList.h>
#include <half.h>

#include <cfloat>

#include "export_file_checks.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/export.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"

using namespace vdblight;
using namespace vdblight::test;
namespace fs = std::filesystem;

namespace {
Volume makeVolume(int nx, int ny, int nz, uint64_t seed) { return test::randomShVolume(nx, ny, nz, 0.3, seed); }

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
    const std::vector<float> px = readExrRgba(file);
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
