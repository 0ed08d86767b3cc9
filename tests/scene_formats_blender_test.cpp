// Every format Blender 3.4 writes, through loadScene: files written by Blender's own exporters
// at test time (tests/blender_scene.h), in centimetres and in metres; skipped with a message
// where Blender is missing. The formats and variants Blender cannot write are read from
// hand-written files in scene_formats_handwritten_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "blender_scene.h"
#include "scene_formats_util.h"
#include "test_util.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectVec;
using vdblight::test::kPiD;
using vdblight::test::TempDir;

namespace {

const Material* findMaterial(const Scene& s, const std::string& name) {
    for (const Material& m : s.materials)
        if (m.name == name) return &m;
    return nullptr;
}

/// The Blender scene read +Y up in metres: 38 triangles in x [-1, 1], y [0, 0.9], z [-0.5, 0.5].
void expectReferenceGeometry(const Scene& s, const std::string& label) {
    EXPECT_EQ(s.triangleCount(), 38u) << label;
    const Bounds b = s.worldBounds();
    expectVec(b.lo, {-1, 0, -0.5}, 1e-4, label + " bounds lo");
    expectVec(b.hi, {1, 0.9, 0.5}, 1e-4, label + " bounds hi");
}

/// Blender's lights, converted as docs/scene.md states: power P (W) of a point or spot light
/// -> P / (4 pi) W/sr, sun W/m^2 as is; Blender Z up -> our Y up: (x, y, z) -> (x, z, -y).
void expectReferenceLights(const Scene& s, double innerSpotDegrees, const std::string& label) {
    const Vec3d colour(1.0, 0.9, 0.8);
    ASSERT_EQ(s.pointLights.size(), 1u) << label;
    ASSERT_EQ(s.spotLights.size(), 1u) << label;
    ASSERT_EQ(s.directionalLights.size(), 1u) << label;
    const PointLight& p = s.pointLights[0];
    expectVec(s.toWorld(p.position), {0.5, 1.5, 0.0}, 1e-4, label + " point position");
    expectVec(Vec3d(p.intensity), colour * (1000.0 / (4 * kPiD)), 1e-3, label + " point intensity");
    const DirectionalLight& d = s.directionalLights[0];
    const double t = 30 * kPiD / 180;
    expectVec(Vec3d(d.direction), {0, -std::cos(t), -std::sin(t)}, 1e-4, label + " sun direction");
    expectVec(Vec3d(d.irradiance), colour * 3.0, 1e-4, label + " sun irradiance");
    const SpotLight& sp = s.spotLights[0];
    const double u = 20 * kPiD / 180;
    expectVec(s.toWorld(sp.position), {0, 1.5, 0.8}, 1e-4, label + " spot position");
    expectVec(Vec3d(sp.direction), {0, -std::cos(u), -std::sin(u)}, 1e-4, label + " spot direction");
    expectVec(Vec3d(sp.intensity), colour * (500.0 / (4 * kPiD)), 1e-3, label + " spot intensity");
    EXPECT_NEAR(sp.outerConeAngle, 30 * kPiD / 180, 1e-4) << label;
    EXPECT_NEAR(sp.innerConeAngle, innerSpotDegrees * kPiD / 180, 1e-4) << label;
}

/// "Red" takes its colour from a texture: its albedo is the texture's mean.
void expectTexturedRed(const Scene& s, const std::string& label) {
    const Material* red = findMaterial(s, "Red");
    ASSERT_NE(red, nullptr) << label;
    expectVec(Vec3d(red->albedo), {0.75, 0.25, 0.5}, 1e-6, label + " texture mean");
}

/// Exports the Blender scene once per (unit, FBX scale option) for the whole suite.
class BlenderFormats : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (!test::haveBlender() || std::getenv("VDBLIGHT_SKIP_BLENDER")) return;
        centimetres_ = std::make_unique<TempDir>();
        metres_ = std::make_unique<TempDir>();
        error_ = test::exportBlenderScene(centimetres_->path().string(), 100.0, false);
        if (error_.empty()) error_ = test::exportBlenderScene(metres_->path().string(), 1.0, true);
    }
    static void TearDownTestSuite() { centimetres_.reset(); metres_.reset(); }

    void SetUp() override {
        if (std::getenv("VDBLIGHT_SKIP_BLENDER")) GTEST_SKIP() << "VDBLIGHT_SKIP_BLENDER is set";
        if (!test::haveBlender())
            GTEST_SKIP() << "blender not found on PATH: this test reads files written by Blender 3.4's own "
                            "exporters (scripts/setup.sh installs blender)";
        ASSERT_TRUE(error_.empty()) << error_;  // Blender present but the export failed: a failure
    }

    /// A file of the scene built with 1 Blender unit = 1 cm (Blender's FBX default export).
    static std::string cm(const std::string& name) { return centimetres_->file(name); }
    /// The scene built in metres, FBX exported with FBX_SCALE_UNITS (UnitScaleFactor 100).
    static std::string m(const std::string& name) { return metres_->file(name); }

    static std::unique_ptr<TempDir> centimetres_, metres_;
    static std::string error_;
};
std::unique_ptr<TempDir> BlenderFormats::centimetres_, BlenderFormats::metres_;
std::string BlenderFormats::error_;

}  // namespace

TEST_F(BlenderFormats, FbxInCentimetres) {
    SceneLoadReport r;
    const Scene s = loadScene(cm("scene.fbx"), {}, &r);
    expectReferenceGeometry(s, "fbx (cm)");
    EXPECT_EQ(r.format, "FBX (binary)");
    EXPECT_NEAR(r.metresPerUnit, 0.01, 1e-9) << r.units;
    EXPECT_EQ(r.meshes, 3u);         // Box, Panel, and the cube SmallA and SmallB share
    EXPECT_EQ(r.meshInstances, 4u);
    EXPECT_FALSE(r.defaultAlbedoOnly);
    const Material* glow = findMaterial(s, "Glow");
    ASSERT_NE(glow, nullptr);
    expectVec(Vec3d(glow->emission), {3.0, 1.5, 0.75}, 1e-5, "EmissiveColor x EmissiveFactor");
    const Material* blue = findMaterial(s, "Blue");
    ASSERT_NE(blue, nullptr);
    expectVec(Vec3d(blue->albedo), {0.2, 0.4, 0.6}, 1e-5, "DiffuseColor");
    expectReferenceLights(s, 22.5, "fbx (cm)");  // inner = 60 deg x (1 - blend 0.25) / 2
    expectTexturedRed(s, "fbx");
}

TEST_F(BlenderFormats, FbxUnitScaleFactor100) {
    SceneLoadReport r;
    const Scene s = loadScene(m("scene.fbx"), {}, &r);
    EXPECT_NE(r.units.find("UnitScaleFactor 100"), std::string::npos) << r.units;
    expectReferenceGeometry(s, "fbx (UnitScaleFactor 100)");
    expectReferenceLights(s, 22.5, "fbx (UnitScaleFactor 100)");
}

// Blender's own glTF exporter (its "standard" mode: W / 4 pi for point and spot lights, W/m^2
// for suns) and the FBX and COLLADA readings agree light for light.
TEST_F(BlenderFormats, LightsAgreeWithBlendersGltfExport) {
    SceneLoadOptions o;
    o.scale = 0.01;  // Blender's glTF exporter writes Blender units (here centimetres)
    const Scene gltf = loadScene(cm("scene.glb"), o);
    expectReferenceLights(gltf, 22.5, "glb");
    expectTexturedRed(gltf, "glb (embedded PNG, base colour factor 1)");
}

TEST_F(BlenderFormats, Collada) {
    SceneLoadReport r;
    const Scene s = loadScene(cm("scene.dae"), {}, &r);
    expectReferenceGeometry(s, "dae");
    EXPECT_EQ(r.format, "COLLADA");
    EXPECT_NEAR(r.metresPerUnit, 0.01, 1e-6) << r.units;
    EXPECT_EQ(r.up, "Z (COLLADA <up_axis>)");
    EXPECT_EQ(r.meshes, 3u);
    EXPECT_EQ(r.meshInstances, 4u);
    const Material* glow = findMaterial(s, "Glow");
    ASSERT_NE(glow, nullptr);
    // Blender's COLLADA exporter writes the emission colour without its strength.
    expectVec(Vec3d(glow->emission), {1.0, 0.5, 0.25}, 1e-5, "<emission>");
    expectReferenceLights(s, 30.0, "dae");  // COLLADA has one falloff angle: a hard cone
    expectTexturedRed(s, "dae");
}

TEST_F(BlenderFormats, ColladaOverrides) {
    // --up y: the file's Z-up coordinates kept as they are; --scale 0.02: twice the metres.
    SceneLoadOptions o;
    o.up = UpAxis::Y;
    o.scale = 0.02;
    SceneLoadReport r;
    const Scene s = loadScene(cm("scene.dae"), o, &r);
    const Bounds b = s.worldBounds();
    expectVec(b.lo, {-2, -1, 0}, 1e-4, "dae --up y --scale 0.02 lo");
    expectVec(b.hi, {2, 1, 1.8}, 1e-4, "dae --up y --scale 0.02 hi");
    EXPECT_EQ(r.up, "Y (--up)");
}

TEST_F(BlenderFormats, StlAsciiAndBinaryNeedScaleAndUp) {
    SceneLoadOptions o;
    o.scale = 0.01;
    o.up = UpAxis::Z;
    for (const char* name : {"scene_ascii.stl", "scene_bin.stl"}) {
        SceneLoadReport r;
        const Scene s = loadScene(cm(name), o, &r);
        expectReferenceGeometry(s, name);
        EXPECT_EQ(r.format, std::string(name) == "scene_bin.stl" ? "STL (binary)" : "STL (ascii)");
        EXPECT_TRUE(r.defaultAlbedoOnly) << name;
        for (const Material& mat : s.materials) expectVec(Vec3d(mat.albedo), {0.8, 0.8, 0.8}, 1e-6, name);
    }
    // Without the options the file's numbers are kept: Blender units, Z up.
    const Bounds raw = loadScene(cm("scene_bin.stl")).worldBounds();
    expectVec(raw.hi, {100, 50, 90}, 1e-3, "stl as stored");
}

TEST_F(BlenderFormats, PlyAndObjFromBlender) {
    SceneLoadOptions o;
    o.scale = 0.01;
    o.up = UpAxis::Z;  // Blender's PLY exporter writes Z up
    SceneLoadReport r;
    expectReferenceGeometry(loadScene(cm("scene.ply"), o, &r), "ply");
    EXPECT_EQ(r.format, "PLY (binary little-endian)");
    EXPECT_TRUE(r.defaultAlbedoOnly);
    o.up = UpAxis::FromFile;  // Blender's OBJ exporter writes Y up
    const Scene obj = loadScene(cm("scene.obj"), o, &r);
    expectReferenceGeometry(obj, "obj");
    const Material* glow = findMaterial(obj, "Glow");
    ASSERT_NE(glow, nullptr);
    expectVec(Vec3d(glow->emission), {3.0, 1.5, 0.75}, 1e-5, "OBJ Ke");
    expectTexturedRed(obj, "obj");
}
