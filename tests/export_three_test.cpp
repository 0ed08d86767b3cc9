// export --format three (export_three.h): the atlas is LightProbeGridWebGL's layout of the
// volume's SH bands 0..2 (seven sub-volumes along z with one padding slice at each end) with
// one border probe per side, the JSON places the grid's box 1.5 spacings outside the nodes,
// and volumes without SH order 2 (or with runtime lights) are refused with nothing written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "export_file_checks.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/basis/basis.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/basis/irradiance_vectors.h"

using namespace vdblight;
using namespace vdblight::test;
namespace fs = std::filesystem;

namespace {
// The atlas file's floats (half or float little-endian).
std::vector<float> atlasFloats(const std::string& dir, bool half) {
    const std::vector<uint8_t> b = readFile(dir + "/" + kThreeGridAtlasFile);
    std::vector<float> out;
    for (std::size_t at = 0; at < b.size(); at += half ? 2 : 4) out.push_back(half ? f16(b, at) : f32(b, at));
    return out;
}

std::string readText(const std::string& path) {
    const std::vector<uint8_t> b = readFile(path);
    return std::string(b.begin(), b.end());
}
}  // namespace

// Float atlas of an sh:4 volume: texel (1 + i, 1 + j, 2 + k) of sub-volume t (after its
// padding slice and the border probes) holds floats 4t..4t+3 of node (i, j, k)'s c0.rgb ..
// c8.rgb, its first nine coefficients (bands 0..2) exactly; a border probe holds the value of
// the nearest node (what query's clamping gives there).
TEST(ExportThree, AtlasHoldsBandsZeroToTwoInLightProbeGridOrder) {
    const Volume v = randomUniformVolume(makeBasis("sh:4")->desc(), 4, 3, 5, 0.25, 11);
    TempDir dir;
    ThreeGridOptions o;
    o.halfFloat = false;
    const ThreeGridSummary s = exportThreeGrid(v, dir.file("web"), o);
    const int nx = 4 + 2, ny = 3 + 2, nz = 5 + 2, padded = nz + 2;
    ASSERT_EQ(s.atlasDepth, 7 * padded);
    const std::vector<float> atlas = atlasFloats(dir.file("web"), false);
    ASSERT_EQ(atlas.size(), std::size_t(nx * ny * s.atlasDepth * 4));
    const GridSpec& g = v.levels[0].grid;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const std::size_t node = g.index(std::clamp(i - 1, 0, 3), std::clamp(j - 1, 0, 2), std::clamp(k - 1, 0, 4));
                for (int f = 0; f < 28; ++f) {
                    const int t = f / 4, slice = t * padded + 1 + k;
                    const float got = atlas[((std::size_t(slice) * ny + j) * nx + i) * 4 + f % 4];
                    const float want = f < 27 ? v.levels[0].data[(node * 25 + f / 3) * 3 + f % 3] : 0.0f;
                    ASSERT_EQ(got, want) << "probe " << i << "," << j << "," << k << " float " << f;
                }
            }
}

// The padding slices repeat their sub-volume's first and last data slice (so that filtering
// never blends two sub-volumes); in half, every value is the float rounded to half.
TEST(ExportThree, PaddingSlicesCopyTheEdgeSlicesAndHalfRounds) {
    const Volume v = randomShVolume(3, 4, 2, 0.5, 12);
    TempDir dir;
    ThreeGridOptions full, half;
    full.halfFloat = false;
    exportThreeGrid(v, dir.file("f"), full);
    exportThreeGrid(v, dir.file("h"), half);
    const std::vector<float> a = atlasFloats(dir.file("f"), false), b = atlasFloats(dir.file("h"), true);
    ASSERT_EQ(a.size(), b.size());
    const std::size_t slice = 5 * 6 * 4, padded = 4 + 2;  // 3 x 4 x 2 nodes and the border probes
    for (std::size_t t = 0; t < 7; ++t)
        for (std::size_t x = 0; x < slice; ++x) {
            const std::size_t base = t * padded * slice + x;
            EXPECT_EQ(a[base], a[base + slice]) << "sub-volume " << t << " leading padding";
            EXPECT_EQ(a[base + 5 * slice], a[base + 4 * slice]) << "sub-volume " << t << " trailing padding";
        }
    for (std::size_t n = 0; n < a.size(); ++n) ASSERT_LE(std::fabs(a[n] - b[n]), std::ldexp(std::fabs(a[n]), -11) + 1e-7f);
}

// probe_grid.json: the probes are the nodes and one border probe a spacing outside on each
// side, at cell centres of the grid's box: the node box grown by 1.5 spacings.
TEST(ExportThree, JsonPlacesTheGridOneAndAHalfSpacingsOutsideTheNodes) {
    const Volume v = randomShVolume(5, 3, 4, 0.25, 13);  // nodes from (-0.5, 0.25, 1.0) to (0.5, 0.75, 1.75)
    TempDir dir;
    const ThreeGridSummary s = exportThreeGrid(v, dir.file("web"), {});
    const nlohmann::json json = nlohmann::json::parse(readText(dir.file("web") + "/" + kThreeGridJsonFile));
    using Array = std::vector<double>;
    EXPECT_EQ(json["resolution"], nlohmann::json::array({7, 5, 6})) << json;
    EXPECT_EQ(json["bounds_min"].get<Array>(), Array({-0.875, -0.125, 0.625})) << json;
    EXPECT_EQ(json["bounds_max"].get<Array>(), Array({0.875, 1.125, 2.125})) << json;
    EXPECT_EQ(json["size"].get<Array>(), Array({1.75, 1.25, 1.5})) << json;
    EXPECT_EQ(json["probe_min"].get<Array>(), Array({-0.75, 0, 0.75})) << json;
    EXPECT_EQ(json["texture"]["type"], "float16") << json;
    EXPECT_EQ(json["texture"]["depth"], 56) << json;
    const uint64_t bytes = 7 * 5 * 56 * 8;
    EXPECT_EQ(json["texture"]["byte_length"], bytes) << json;
    EXPECT_EQ(fs::file_size(dir.file("web") + "/" + kThreeGridAtlasFile), bytes);
    EXPECT_EQ(s.files.size(), 2u);
}

// Volumes without SH bands 0..2 are refused in one line, and nothing is written.
TEST(ExportThree, RefusesVolumesWithoutShOrderTwo) {
    TempDir dir;
    const std::string out = dir.file("web");
    for (const char* kind : {"sh:1", "bins:3"}) {
        const Volume v = randomUniformVolume(makeBasis(kind)->desc(), 3, 3, 3, 0.5, 14);
        EXPECT_THROW(exportThreeGrid(v, out, {}), FormatError) << kind;
        EXPECT_FALSE(fs::exists(out)) << kind;
    }
    const Volume vectors = randomUniformVolume(iv::basis(), 3, 3, 3, 0.5, 15);
    EXPECT_THROW(exportThreeGrid(vectors, out, {}), FormatError);
    EXPECT_FALSE(fs::exists(out));
    // Runtime lights (shadowed by the scene at run time) have no place in three's grid:
    // exporting the SH alone would be silently dim. (Occlusion volumes' lights are folded into
    // the SH: export_fold_direct_test.)
    Volume runtime = randomShVolume(3, 3, 3, 0.5, 17);
    runtime.direct.mode = DirectMode::Runtime;
    EXPECT_THROW(exportThreeGrid(runtime, out, {}), FormatError);
    EXPECT_FALSE(fs::exists(out));
    const Volume flat = randomShVolume(4, 4, 1, 0.5, 16);
    EXPECT_THROW(exportThreeGrid(flat, out, {}), ValueError);
    EXPECT_FALSE(fs::exists(out));
}
