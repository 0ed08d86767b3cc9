// The glTF probe view (export_gltf.h): the Khronos glTF-Validator (npm gltf-validator, pinned
// in scripts/gltf) finds 0 errors and 0 warnings, Blender imports it headless, the spheres are
// the chosen nodes, each vertex's colour is the query for its normal, and a volume of too many
// nodes without --every / --slice is refused in one line naming them, leaving nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
const std::string kSource = VDBLIGHT_SOURCE_DIR;
constexpr int kVerticesPerSphere = 34;

std::string validate(const std::string& glb, int* status) {
    std::string log;
    *status = test::runCommand("node " + kSource + "/scripts/gltf/check_gltf.mjs " + glb, &log);
    return log;
}

struct Glb {
    std::string json;
    std::vector<uint8_t> bin;
};
Glb readGlb(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    const std::vector<uint8_t> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto u32 = [&](std::size_t at) { return uint32_t(b[at]) | b[at + 1] << 8 | b[at + 2] << 16 | uint32_t(b[at + 3]) << 24; };
    Glb g;
    EXPECT_EQ(u32(0), 0x46546C67u);
    EXPECT_EQ(u32(8), b.size());
    const uint32_t jsonLength = u32(12);
    g.json.assign(b.begin() + 20, b.begin() + 20 + jsonLength);
    g.bin.assign(b.begin() + 20 + jsonLength + 8, b.end());
    return g;
}
std::vector<uint32_t> viewOffsets(const nlohmann::json& gltf) {
    std::vector<uint32_t> out;
    for (const nlohmann::json& view : gltf.at("bufferViews")) out.push_back(view.at("byteOffset").get<uint32_t>());
    return out;
}
float floatAt(const Glb& g, std::size_t at) {
    float v;
    std::memcpy(&v, g.bin.data() + at, 4);
    return v;
}
}  // namespace

TEST(ExportGltf, ValidatesWithKhronosAndColoursEachVertexByTheQueryForItsNormal) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 31);
    const IrradianceQuery q(v);
    test::TempDir dir;
    const std::string glb = dir.file("probes.glb");
    const GltfProbeSummary s = exportGltfProbes(v, glb, {});
    EXPECT_EQ(s.spheres, 60u);
    int status = 0;
    const std::string log = validate(glb, &status);
    EXPECT_EQ(status, 0) << log;
    EXPECT_NE(log.find(": 0 errors, 0 warnings"), std::string::npos) << log;

    const Glb g = readGlb(glb);
    const nlohmann::json gltf = nlohmann::json::parse(g.json);
    const std::vector<uint32_t> views = viewOffsets(gltf);
    ASSERT_EQ(views.size(), 6u) << g.json;
    const double k = gltf.at("scenes").at(0).at("extras").at("vdblight").at("colour_scale").get<double>();
    EXPECT_EQ(k, s.colourScale);  // every digit: it reads back as the same double
    int checked = 0;
    for (std::size_t vert = 0; vert < 60 * kVerticesPerSphere; vert += 7) {
        Vec3d p, n, c;
        for (int a = 0; a < 3; ++a) {
            p[a] = floatAt(g, views[0] + 12 * vert + 4 * a);
            n[a] = floatAt(g, views[1] + 12 * vert + 4 * a);
            c[a] = floatAt(g, views[2] + 12 * vert + 4 * a);
        }
        const Vec3d centre = p - n * 0.1;  // radius 0.2 spacings of 0.5
        const Rgb e = q.irradianceWorld(centre, Vec3f(n));
        for (int a = 0; a < 3; ++a)
            ASSERT_NEAR(c[a], std::clamp(k * e[a] / M_PI, 0.0, 1.0), 1e-5) << "vertex " << vert;
        ++checked;
    }
    EXPECT_GT(checked, 200);
}

TEST(ExportGltf, EveryKthNodeOrTheNodesOfASlice) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 32);  // nodes at (-0.5, 0.25, 1) + 0.5 (i, j, k)
    test::TempDir dir;
    GltfProbeOptions o;
    o.every = 2;
    EXPECT_EQ(exportGltfProbes(v, dir.file("every.glb"), o).spheres, 2u * 2u * 3u);
    o.every = 0;
    o.sliceAxis = 1;
    o.sliceAt = 0.8;  // nearest plane j = 1 (y = 0.75)
    EXPECT_EQ(exportGltfProbes(v, dir.file("slice.glb"), o).spheres, 4u * 5u);
    int status = 0;
    const std::string log = validate(dir.file("every.glb") + " " + dir.file("slice.glb"), &status);
    EXPECT_EQ(status, 0) << log;
}

TEST(ExportGltf, MillionsOfNodesWithoutDecimationAreRefusedNamingTheOption) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 33);
    test::TempDir dir;
    GltfProbeOptions o;
    o.maxSpheresWithoutDecimation = 59;  // the rule, on a volume of 60 nodes
    try {
        exportGltfProbes(v, dir.file("big.glb"), o);
        ADD_FAILURE() << "not refused";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("--every K or --slice AXIS=VALUE"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir.file("big.glb")));
}

TEST(ExportGltf, CliRefusesALargeVolumeThenBlenderImportsTheDecimatedView) {
    test::TempDir dir;
    const std::string vol = dir.file("big.vdb");
    writeVolume(test::randomShVolume(48, 48, 48, 0.1, 34), vol);  // 110 592 nodes, over the 100 000 default
    test::expectRefusal("export " + vol + " -o " + dir.file("view") + " --format gltf", "--every K", dir.file("view"),
                        "gltf without decimation");
    std::string log;
    ASSERT_EQ(test::runCommand(test::cliPath() + " export " + vol + " -o " + dir.file("view") + " --format gltf --every 6", &log), 0)
        << log;
    const std::string glb = dir.file("view/probes.glb");
    int status = 0;
    log = validate(glb, &status);
    EXPECT_EQ(status, 0) << log;

    if (std::getenv("VDBLIGHT_SKIP_BLENDER")) GTEST_SKIP() << "VDBLIGHT_SKIP_BLENDER is set";
    // Debian 12's Blender 3.4 glTF importer still calls numpy.bool, which numpy 1.24 removed
    // ("module 'numpy' has no attribute 'bool'" in set_poly_smoothing): the alias is put back
    // first, as a user of that Blender would (docs/engines.md).
    const std::string script =
        "import numpy; numpy.bool = bool; import bpy; bpy.ops.import_scene.gltf(filepath='" + glb + "'); "
        "m = bpy.data.objects['probes'].data; "
        "print('VDBLIGHT', len(m.vertices), len(m.polygons), len(m.color_attributes), "
        "len(bpy.data.objects['volume_box'].data.edges))";
    ASSERT_EQ(test::runCommand("blender -b --factory-startup --python-expr \"" + script + "\" 2>&1", &log), 0) << log;
    const std::size_t at = log.find("VDBLIGHT ");
    ASSERT_NE(at, std::string::npos) << log;
    std::istringstream s(log.substr(at + 9));
    std::size_t vertices = 0, polygons = 0, colours = 0, edges = 0;
    s >> vertices >> polygons >> colours >> edges;
    EXPECT_EQ(vertices, 512u * kVerticesPerSphere) << log;  // 8^3 spheres
    EXPECT_EQ(polygons, 512u * 64u) << log;
    EXPECT_GE(colours, 1u) << log;
    EXPECT_EQ(edges, 12u) << log;
}
