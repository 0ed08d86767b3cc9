// Engine presets (export_engines.h): each preset's manifest states its engine's axes, units
// and files, and the textures evaluated in the engine's frame (point and normal converted by
// the manifest's rule, independently of the code under test) give the library's query.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <random>

#include "export_file_checks.h"
#include "manifest_util.h"
#include "occlusion_volumes.h"
#include "cli_util.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {

// E_c from the 7 sh2-packed texels (docs/engine_layouts.md), n in the frame the texels are in.
Vec3d evalPacked(const std::vector<const float*>& t, const Vec3d& n) {
    Vec3d e;
    for (int c = 0; c < 3; ++c) {
        const float* A = t[c];
        const float* B = t[3 + c];
        e[c] = A[0] * n.x + A[1] * n.y + A[2] * n.z + A[3] + B[0] * n.x * n.y + B[1] * n.y * n.z + B[2] * n.z * n.z +
               B[3] * n.z * n.x + t[6][c] * (n.x * n.x - n.y * n.y);
    }
    return e;
}

// The engine frames as the manifests and docs/engines.md state them, written out by hand:
// engine = scale * (sign * volume[axis]).
struct Frame {
    int axis[3], sign[3];
    double scale;
    Vec3d toVolumeDir(const Vec3d& e) const {
        Vec3d v;
        for (int a = 0; a < 3; ++a) v[axis[a]] = sign[a] * e[a];
        return v;
    }
    Vec3d toVolumePoint(const Vec3d& e) const { return toVolumeDir(e) * (1.0 / scale); }
};
const Frame kUnity{{0, 1, 2}, {-1, 1, 1}, 1.0};
const Frame kGodot{{0, 1, 2}, {1, 1, 1}, 1.0};
const Frame kUnreal{{2, 0, 1}, {1, -1, 1}, 100.0};

void expectManifestFrame(const nlohmann::json& manifest, const Frame& f) {
    EXPECT_EQ(manifest["axis"], nlohmann::json::array({f.axis[0], f.axis[1], f.axis[2]})) << manifest;
    EXPECT_EQ(manifest["sign"], nlohmann::json::array({f.sign[0], f.sign[1], f.sign[2]})) << manifest;
    EXPECT_EQ(manifest["units_per_metre"], f.scale) << manifest;
}

// Each engine texel, evaluated for random engine normals, against the query at the volume point.
void expectEngineTexelsMatchQuery(const Volume& v, const PresetSummary& s, const Frame& f,
                                  const std::vector<std::vector<float>>& textures) {
    const IrradianceQuery q(v);
    std::mt19937 rng(1);
    std::normal_distribution<double> g;
    const TextureLattice& e = s.lattice;
    std::size_t texel = 0;
    for (int k = 0; k < e.dims[2]; ++k)
        for (int j = 0; j < e.dims[1]; ++j)
            for (int i = 0; i < e.dims[0]; ++i, ++texel) {
                std::vector<const float*> t;
                for (const auto& tex : textures) t.push_back(tex.data() + 4 * texel);
                const Vec3d n = normalize(Vec3d(g(rng), g(rng), g(rng)));
                const Vec3d got = evalPacked(t, n);
                const Rgb want = q.irradianceWorld(f.toVolumePoint(e.point(i, j, k)), Vec3f(f.toVolumeDir(n)));
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], want[c], 4e-3 * (1 + std::fabs(want[c])))
                        << "engine texel " << i << "," << j << "," << k << " channel " << c;
            }
}

// The EXR atlases of an export, as texel arrays x fastest (slice z at column z % columns, row z / columns).
std::vector<std::vector<float>> readAtlases(const test::TempDir& dir, const TextureLattice& e, const std::string& sub = "") {
    std::vector<std::vector<float>> out;
    for (const char* name : {"shAr", "shAg", "shAb", "shBr", "shBg", "shBb", "shC"}) {
        Imf::InputFile file(dir.file(sub + name + ".exr").c_str());
        const std::vector<float> px = test::readExrRgba(file);
        const int width = file.header().dataWindow().max.x + 1;
        const int columns = width / e.dims[0];
        std::vector<float> t(e.texelCount() * 4);
        for (int k = 0; k < e.dims[2]; ++k)
            for (int j = 0; j < e.dims[1]; ++j)
                for (int i = 0; i < e.dims[0]; ++i) {
                    const std::size_t x = std::size_t(k % columns) * e.dims[0] + i, y = std::size_t(k / columns) * e.dims[1] + j;
                    std::copy_n(&px[4 * (y * width + x)], 4, &t[4 * (i + e.dims[0] * (j + std::size_t(e.dims[1]) * k))]);
                }
        out.push_back(t);
    }
    return out;
}

}  // namespace

TEST(ExportPresets, UnityAndGodotAtlasesHoldTheQueryInTheirEnginesAxes) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 21);
    for (const auto& [preset, frame] : {std::pair{EnginePreset::Unity, kUnity}, std::pair{EnginePreset::Godot, kGodot}}) {
        test::TempDir dir;
        const PresetSummary s = exportPreset(v, dir.path().string(), preset);
        ASSERT_EQ(s.files.size(), 8u) << "7 atlases + manifest.json";
        const nlohmann::json manifest = test::readManifest(dir.path().string());
        expectManifestFrame(manifest, frame);
        EXPECT_TRUE(manifest.contains("exr_atlas")) << manifest;
        EXPECT_EQ(manifest["preset"], presetName(preset));
        expectEngineTexelsMatchQuery(v, s, frame, readAtlases(dir, s.lattice));
    }
}

TEST(ExportPresets, UnrealSparseVolumeTexturesHoldAtMostTwoRgbaAttributesPerFileInCentimetresZUp) {
    openvdb::initialize();
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 22);
    test::TempDir dir;
    const PresetSummary s = exportPreset(v, dir.path().string(), EnginePreset::Unreal);
    ASSERT_EQ(s.files.size(), 5u) << "L2's 28 channels in 4 files of at most 8, + manifest.json";
    const nlohmann::json manifest = test::readManifest(dir.path().string());
    expectManifestFrame(manifest, kUnreal);
    EXPECT_EQ(s.lattice.dims[0], 5);  // Unreal x = volume z
    EXPECT_EQ(s.lattice.dims[1], 4);  // Unreal y = -volume x
    EXPECT_EQ(s.lattice.dims[2], 3);  // Unreal z = volume y (up)
    std::map<std::string, openvdb::GridBase::Ptr> grids;
    for (int f = 0; f < 4; ++f) {
        const std::string name = "svt_" + std::to_string(f) + ".vdb";
        bool listed = false;
        for (const nlohmann::json& entry : manifest["svt_files"]) listed |= entry["file"] == name;
        EXPECT_TRUE(listed) << name << " listed in the manifest";
        openvdb::io::File file(dir.file(name));
        file.open();
        int channels = 0;
        for (auto it = file.beginName(); it != file.endName(); ++it) {
            openvdb::GridBase::Ptr g = file.readGrid(it.gridName());
            EXPECT_TRUE(g->saveFloatAsHalf()) << it.gridName();
            const int components = g->isType<openvdb::Vec3SGrid>() ? 3 : (g->isType<openvdb::FloatGrid>() ? 1 : 0);
            EXPECT_GE(components, 1) << it.gridName();
            channels += components;
            grids[it.gridName()] = g;
        }
        EXPECT_LE(channels, 8) << name;
        EXPECT_GE(channels, 3) << name;
    }
    // Every texture's value at each voxel, evaluated at the voxel's world position (cm, Z up)
    // with Unreal-axis normals, is the query's.
    const IrradianceQuery q(v);
    std::mt19937 rng(2);
    std::normal_distribution<double> g;
    const char* names[7] = {"shAr", "shAg", "shAb", "shBr", "shBg", "shBb", "shC"};
    const TextureLattice& e = s.lattice;
    for (int k = 0; k < e.dims[2]; ++k)
        for (int j = 0; j < e.dims[1]; ++j)
            for (int i = 0; i < e.dims[0]; ++i) {
                float texel[7][4];
                openvdb::Vec3d world;
                for (int t = 0; t < 7; ++t) {
                    auto rgb = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids.at(std::string(names[t]) + "_rgb"));
                    const openvdb::Vec3s c = rgb->tree().getValue(openvdb::Coord(i, j, k));
                    world = rgb->transform().indexToWorld(openvdb::Coord(i, j, k));
                    texel[t][0] = c[0], texel[t][1] = c[1], texel[t][2] = c[2], texel[t][3] = 0;
                    if (grids.count(std::string(names[t]) + "_a"))
                        texel[t][3] = openvdb::gridPtrCast<openvdb::FloatGrid>(grids.at(std::string(names[t]) + "_a"))
                                          ->tree().getValue(openvdb::Coord(i, j, k));
                }
                const Vec3d n = normalize(Vec3d(g(rng), g(rng), g(rng)));
                std::vector<const float*> t;
                for (auto& x : texel) t.push_back(x);
                const Vec3d got = evalPacked(t, n);
                const Vec3d p = kUnreal.toVolumePoint(Vec3d(world.x(), world.y(), world.z()));
                const Rgb want = q.irradianceWorld(p, Vec3f(kUnreal.toVolumeDir(n)));
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], want[c], 4e-3 * (1 + std::fabs(want[c]))) << "voxel " << i << "," << j << "," << k;
            }
}

TEST(ExportPresets, BevyManifestStatesUnitsAndTheCubesTransform) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 23);
    test::TempDir dir;
    exportPreset(v, dir.path().string(), EnginePreset::Bevy);
    const nlohmann::json manifest = test::readManifest(dir.path().string());
    EXPECT_EQ(manifest["units"], "W/(m^2 sr)") << manifest;
    // node box (-0.5, 0.25, 1) .. (1, 1.25, 3): centre and R * spacing per axis
    EXPECT_EQ(manifest["transform"]["translation"], nlohmann::json::array({0.25, 0.75, 2})) << manifest;
    EXPECT_EQ(manifest["transform"]["scale"], nlohmann::json::array({2, 1.5, 2.5})) << manifest;
    EXPECT_TRUE(fs::exists(dir.file("irradiance_volume.ktx2")));
}

TEST(ExportPresets, APresetTheVolumeCannotTakeIsRefusedWithoutOutput) {
    Volume iv = test::randomUniformVolume(iv::basis(), 3, 3, 3, 0.5, 4);
    test::TempDir dir;
    for (EnginePreset p : {EnginePreset::Unity, EnginePreset::Unreal, EnginePreset::Godot, EnginePreset::Three}) {
        const std::string out = dir.file(presetName(p));
        EXPECT_THROW(exportPreset(iv, out, p), FormatError) << presetName(p);
        EXPECT_FALSE(fs::exists(out)) << presetName(p);
    }
    EXPECT_THROW(parseEnginePreset("unity5"), ValueError);
}

// An occlusion volume's listed lights are folded into the SH (fold_direct.h): Godot's texels
// (its frame is the volume's) give the query's full answer, direct light included, up to SH
// order 2's truncation of a point light (3/32 of its peak irradiance x visibility) and half
// rounding, the manifest names the lights; a runtime volume's lights are still refused.
TEST(ExportPresets, ShPresetsFoldOcclusionLightsAndRefuseRuntimeLights) {
    const Volume v = test::occlusionVolume(5);
    test::TempDir dir;
    const PresetSummary s = exportPreset(v, dir.file("godot"), EnginePreset::Godot);
    EXPECT_EQ(s.foldedLights, 2);
    const nlohmann::json direct = test::readManifest(dir.file("godot"))["direct_light"];
    EXPECT_EQ(direct["folded_into_sh"], true) << direct;
    EXPECT_EQ(direct["lights"], nlohmann::json::array({formatDirectLight(v.direct.lights[0]), formatDirectLight(v.direct.lights[1])}))
        << direct;
    const std::vector<std::vector<float>> textures = readAtlases(dir, s.lattice, "godot/");
    const IrradianceQuery q(v);
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    const TextureLattice& e = s.lattice;
    double sumErr2 = 0;
    std::size_t texel = 0;
    for (int k = 0; k < e.dims[2]; ++k)
        for (int j = 0; j < e.dims[1]; ++j)
            for (int i = 0; i < e.dims[0]; ++i, ++texel) {
                std::vector<const float*> t;
                for (const auto& tex : textures) t.push_back(tex.data() + 4 * texel);
                const Vec3d n = normalize(Vec3d(g(rng), g(rng), g(rng)));
                const Vec3d x = e.point(i, j, k);
                const Vec3d got = evalPacked(t, n);
                const Rgb want = q.irradianceWorld(x, Vec3f(n));
                const Vec3d peak = test::peakDirect(v, x);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(got[c], want[c], test::kL2PointLightWorstError * peak[c] + 4e-3 * (1 + std::fabs(want[c])))
                        << "texel " << i << "," << j << "," << k << " channel " << c;
                    sumErr2 += (got[c] - want[c]) * (got[c] - want[c]);
                }
            }
    EXPECT_GT(sumErr2, 0.0);  // the truncation is real: the texels are not the query's answer
    Volume runtime = test::randomShVolume(3, 3, 3, 0.5, 5);
    runtime.direct.mode = DirectMode::Runtime;
    runtime.direct.lights.push_back(DirectLight{});
    try {
        exportPreset(runtime, dir.file("unity"), EnginePreset::Unity);
        ADD_FAILURE() << "not refused";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("--direct runtime"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir.file("unity")));
}

TEST(ExportPresets, CliRefusalsAreOneLineAndLeaveNothing) {
    test::TempDir dir;
    const std::string iv = dir.file("iv.vdb"), sh = dir.file("sh.vdb");
    writeVolume(test::randomUniformVolume(iv::basis(), 3, 3, 3, 0.5, 6), iv);
    writeVolume(test::randomShVolume(3, 3, 3, 0.5, 7), sh);
    test::expectRefusal("export " + iv + " -o " + dir.file("u") + " --preset unreal", "needs an SH volume", dir.file("u"),
                        "unreal from irradiance vectors");
    test::expectRefusal("export " + iv + " -o " + dir.file("t") + " --preset three", "--format three writes SH order-2",
                        dir.file("t"), "three from irradiance vectors");
    test::expectRefusal("export " + sh + " -o " + dir.file("x") + " --preset cryengine", "unity, unreal, godot, three or bevy",
                        dir.file("x"), "unknown preset");
    std::string log;
    EXPECT_EQ(test::runCommand(test::cliPath() + " export " + sh + " -o " + dir.file("g") + " --preset godot", &log), 0) << log;
    EXPECT_NE(log.find("Exported preset godot: 7 files"), std::string::npos) << log;
    // three: what export --format three writes (export_three_test checks its contents).
    EXPECT_EQ(test::runCommand(test::cliPath() + " export " + sh + " -o " + dir.file("th") + " --preset three", &log), 0) << log;
    EXPECT_TRUE(fs::exists(dir.file("th") + "/probe_grid.json")) << log;
    EXPECT_TRUE(fs::exists(dir.file("th") + "/probe_grid_sh.bin")) << log;
}
