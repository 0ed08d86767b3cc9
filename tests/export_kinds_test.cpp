// Every volume kind exports: the export hooks of the multi-level SH lookup (shRadiance) and
// the irradiance-vector lookup (irradianceVectors) against the volumes' own node values and
// the simple reference lookups; the `vectors` and `compact` texels against hand-computed
// values (Pacanowski et al. section 4.2); slices against IrradianceQuery at pixel centres.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/export.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "basis/irradiance_vectors_compact.h"
#include "vdblight/layout/layout.h"
#include "query/query_levels.h"
#include "basis/sh.h"
#include "vdblight/export/slice.h"
#include "vdblight/query/query.h"
#include "volume/volume_compact.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
Volume levelsVolume(LayoutKind kind, int levels) {
    Volume v = test::randomLevelsVolume(kind, levels, BasisDesc::sh2(), 11, -0.5f, 1.5f);
    applySeamConstraints(v);  // as a bake leaves it: seam nodes continue the coarse side
    return v;
}

Volume vectorVolume(uint32_t seed) {
    Volume v;
    v.basis = iv::basis();
    v.levels.resize(1);
    VolumeLevel& l = v.levels[0];
    l.grid.origin = {1, 2, 3};
    l.grid.spacing = 0.5;
    l.grid.nx = 4, l.grid.ny = 3, l.grid.nz = 5;
    l.data.resize(l.grid.nodeCount() * iv::kFloatsPerNode);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& f : l.data) f = u(rng);
    return v;
}

Vec3d randomIn(const Bounds& b, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return Vec3d(b.lo.x + u(rng) * (b.hi.x - b.lo.x), b.lo.y + u(rng) * (b.hi.y - b.lo.y),
                 b.lo.z + u(rng) * (b.hi.z - b.lo.z));
}

Vec3d randomNormal(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return normalize(Vec3d(g(rng), g(rng), g(rng)));
}
}  // namespace

TEST(ExportKinds, LevelsShRadianceReturnsEveryNodeOfItsFinestCell) {
    for (const auto& [kind, levels] : {std::pair{LayoutKind::Bilevel, 2}, std::pair{LayoutKind::Adaptive, 3}}) {
        const Volume v = levelsVolume(kind, levels);
        ASSERT_GT(v.levels.size(), 1u);
        const ShLevelsLookup lookup(v, OutsidePolicy::Clamp);
        // The finest-level nodes: every active node of the last level is read back exactly
        // (up to the A_l fold and unfold in float).
        const VolumeLevel& fine = v.levels.back();
        ASSERT_GT(fine.storedNodes(), 0u);
        int checked = 0;
        for (std::size_t s = 0; s < fine.storedNodes(); ++s) {
            const uint64_t linear = fine.sparse() ? fine.activeNodes[s] : s;
            Rgb L[9];
            lookup.shRadiance(fine.grid.node(linear), L);
            const float* want = fine.nodeData(s, 9);
            for (int j = 0; j < 9; ++j)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(L[j][c], want[3 * j + c], 1e-6f * (1.0f + std::fabs(want[3 * j + c])))
                        << "level " << v.levels.size() - 1 << " node " << linear << " coefficient " << j;
            ++checked;
        }
        EXPECT_GT(checked, 8);
        // Anywhere: convolving the returned coefficients equals the reference lookup.
        std::mt19937 rng(3);
        for (int t = 0; t < 300; ++t) {
            const Vec3d x = randomIn(lookup.bounds(), rng), n = randomNormal(rng);
            Rgb L[9];
            lookup.shRadiance(x, L);
            double y[9];
            sh::evalGeneric(2, n, y);
            Rgbd e(0, 0, 0);
            for (int j = 0; j < 9; ++j) e += Rgbd(L[j]) * (sh::kCosineLobe[sh::bandOf(j)] * y[j]);
            const Rgbd want = referenceLevelsLookup(v, x, n);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], want[c], 1e-5 * (1.0 + std::fabs(want[c])));
        }
    }
}

TEST(ExportKinds, VectorHookReturnsNodesAndInterpolatesLikeTheReference) {
    const Volume v = vectorVolume(5);
    const VectorGridLookup lookup(v, OutsidePolicy::Clamp);
    const VolumeLevel& l = v.levels[0];
    for (std::size_t n = 0; n < l.grid.nodeCount(); ++n) {
        float out[54];
        lookup.irradianceVectors(l.grid.node(n), out);
        for (int f = 0; f < 54; ++f) ASSERT_EQ(out[f], l.data[n * 54 + f]) << "node " << n << " float " << f;
    }
    std::mt19937 rng(9);
    for (int t = 0; t < 300; ++t) {
        const Vec3d x = randomIn(lookup.bounds(), rng), n = randomNormal(rng);
        float vec[54];
        lookup.irradianceVectors(x, vec);
        const Rgb e = iv::irradiance(vec, Vec3f(n));
        const Rgbd want = referenceVectorLookup(v, x, n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], want[c], 1e-5 * (1.0 + std::fabs(want[c])));
    }
}

TEST(ExportKinds, CompactTexelsAreColourAndNormalisedSum) {
    // One node set by hand, copied to all nodes: direction +y holds I_R = (0, 3, 4) (|.| = 5),
    // I_G = (0, 0, 2), I_B = 0; sum (0, 3, 6) -> d = (0, 1, 2) / sqrt(5). Direction -z: all
    // zero -> colour 0 and d = 0.
    Volume v = vectorVolume(1);
    VolumeLevel& l = v.levels[0];
    for (std::size_t n = 0; n < l.grid.nodeCount(); ++n) {
        float* p = l.data.data() + n * 54;
        const int d = iv::direction(1, false), z = iv::direction(2, true);
        float* r = p + 3 * iv::channel(d, 0);
        float* g = p + 3 * iv::channel(d, 1);
        float* b = p + 3 * iv::channel(d, 2);
        r[0] = 0, r[1] = 3, r[2] = 4, g[0] = 0, g[1] = 0, g[2] = 2, b[0] = b[1] = b[2] = 0;
        for (int f = 0; f < 9; ++f) p[9 * z + f] = 0.0f;
    }
    test::TempDir dir;
    ExportOptions o;
    o.format = TextureFormat::Raw;
    o.layout = ExportLayout::Compact;
    o.halfFloat = false;
    const ExportSummary s = exportTextures(v, dir.file("c"), o);
    ASSERT_EQ(s.files.size(), 13u);  // 12 textures + manifest
    auto texel0 = [&](const std::string& name) {
        std::ifstream in(dir.file("c/" + name + ".raw"), std::ios::binary);
        float t[4];
        in.read(reinterpret_cast<char*>(t), sizeof t);
        return std::vector<float>(t, t + 4);
    };
    const std::vector<float> colour = texel0("ivc_ypos_colour"), d = texel0("ivc_ypos_dir");
    EXPECT_FLOAT_EQ(colour[0], 5.0f);
    EXPECT_FLOAT_EQ(colour[1], 2.0f);
    EXPECT_FLOAT_EQ(colour[2], 0.0f);
    EXPECT_FLOAT_EQ(d[0], 0.0f);
    EXPECT_FLOAT_EQ(d[1], float(1 / std::sqrt(5.0)));
    EXPECT_FLOAT_EQ(d[2], float(2 / std::sqrt(5.0)));
    const std::vector<float> zc = texel0("ivc_zneg_colour"), zd = texel0("ivc_zneg_dir");
    for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(zc[c], 0.0f);
        EXPECT_EQ(zd[c], 0.0f);
    }
    // The 18-texture `vectors` layout holds the vectors themselves.
    o.layout = ExportLayout::Vectors;
    const ExportSummary sv = exportTextures(v, dir.file("v"), o);
    EXPECT_EQ(sv.files.size(), 19u);
    std::ifstream in(dir.file("v/iv_ypos_r.raw"), std::ios::binary);
    float t[4];
    in.read(reinterpret_cast<char*>(t), sizeof t);
    EXPECT_EQ(t[0], 0.0f);
    EXPECT_EQ(t[1], 3.0f);
    EXPECT_EQ(t[2], 4.0f);
    EXPECT_EQ(t[3], 0.0f);
}

TEST(ExportKinds, LayoutsThatDoNotFitTheKindAreRefusedBeforeWriting) {
    test::TempDir dir;
    ExportOptions o;
    o.format = TextureFormat::Raw;
    o.layout = ExportLayout::Sh2Packed;
    EXPECT_THROW(exportTextures(vectorVolume(2), dir.file("a"), o), FormatError);
    o.layout = ExportLayout::Compact;
    EXPECT_THROW(exportTextures(levelsVolume(LayoutKind::Bilevel, 2), dir.file("a"), o), FormatError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
    EXPECT_THROW(parseExportLayout("vector"), ValueError);
    EXPECT_EQ(parseExportLayout("compact"), ExportLayout::Compact);
}

TEST(ExportKinds, CompactVolumesExportAsCompactExactlyAtTheNodes) {
    // Positive vectors so that every node has a well-defined direction of the colour sum.
    Volume full = vectorVolume(7);
    for (float& f : full.levels[0].data) f = std::abs(f) + 0.01f;
    const Volume packed = iv::compact(full);
    test::TempDir dir;
    ExportOptions o;
    o.format = TextureFormat::Raw;
    o.halfFloat = false;
    o.layout = ExportLayout::Vectors;
    EXPECT_THROW(exportTextures(packed, dir.file("v"), o), FormatError);
    EXPECT_FALSE(fs::exists(dir.file("v")));
    o.layout = ExportLayout::Compact;
    exportTextures(packed, dir.file("c"), o);
    // The default lattice is the node lattice: texel (i,j,k) of ivc_<d>_colour is the stored colour.
    std::ifstream in(dir.file("c") + "/ivc_xpos_colour.raw", std::ios::binary);
    ASSERT_TRUE(in.good());
    const GridSpec& g = packed.levels[0].grid;
    std::vector<float> texels(g.nodeCount() * 4);
    in.read(reinterpret_cast<char*>(texels.data()), std::streamsize(texels.size() * sizeof(float)));
    ASSERT_TRUE(in.good());
    for (std::size_t node = 0; node < g.nodeCount(); ++node)
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(texels[node * 4 + c], packed.levels[0].data[node * iv::kCompactFloatsPerNode + c], 1e-5f)
                << "node " << node;
}

TEST(ExportKinds, SlicePixelsAreTheQueryAtTheirCentres) {
    const Volume v = levelsVolume(LayoutKind::Adaptive, 3);
    const IrradianceQuery query(v);
    SliceOptions o;
    o.axis = 1;
    o.at = 0.4;
    o.normal = Vec3f(0.3f, -1.0f, 0.2f);
    o.size = 9;
    const SliceImage img = sliceVolume(v, o);
    EXPECT_EQ(img.width, 9);
    EXPECT_EQ(img.height, 9);
    EXPECT_EQ(img.uAxis, 0);
    EXPECT_EQ(img.vAxis, 2);
    const Bounds b = query.bounds();
    for (int r = 0; r < img.height; ++r)
        for (int c = 0; c < img.width; ++c) {
            // slice.h: u = lo_u + (c + 0.5) * size_u / width, v = hi_v - (r + 0.5) * size_v / height.
            const Vec3d p(b.lo.x + (c + 0.5) * (b.hi.x - b.lo.x) / 9, 0.4, b.hi.z - (r + 0.5) * (b.hi.z - b.lo.z) / 9);
            const Rgb want = query.irradiance(Vec3f(p), normalize(o.normal));
            for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(img.rgb[(std::size_t(r) * 9 + c) * 3 + ch], want[ch]) << r << "," << c;
        }
    SliceOptions bad = o;
    bad.at = 2.0;
    EXPECT_THROW(sliceVolume(v, bad), ValueError);
    bad = o;
    bad.normal = Vec3f(0, 0, 0);
    EXPECT_THROW(sliceVolume(v, bad), ValueError);
    test::TempDir dir;
    EXPECT_THROW(writeSlice(dir.file("s.jpg"), img, ToneMap{}), ValueError);
    EXPECT_THROW(writeSlice(dir.file("missing/s.png"), img, ToneMap{}), IoError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(ExportKinds, ToneMapIsReinhardOfExposedRadianceInSrgb) {
    SliceImage img;
    img.width = 2, img.height = 1;
    img.rgb = {0.0f, float(kPi), float(3 * kPi), 1e30f, -1.0f, float(kPi)};
    ToneMap fixed;
    fixed.autoExposure = false;
    const std::vector<uint8_t> px = toneMapSlice(img, fixed);
    // L = E / pi: 0 -> 0; 1 -> 1/2 -> sRGB 0.7354 -> 188; 3 -> 3/4 -> 0.8808 -> 225; huge -> 255; negative -> 0.
    EXPECT_EQ(px[0], 0);
    EXPECT_EQ(px[1], 188);
    EXPECT_EQ(px[2], 225);
    EXPECT_EQ(px[3], 255);
    EXPECT_EQ(px[4], 0);
    EXPECT_EQ(px[5], 188);
    fixed.exposure = 1.0;  // one stop: L = 2 -> 2/3 -> sRGB 0.8354 -> 213
    EXPECT_EQ(toneMapSlice(img, fixed)[1], 213);
}
