// Every format Assimp reads, through loadScene: files written by Blender 3.4's own exporters
// at test time (tests/blender_scene.h; skipped with a message where Blender is missing), and
// small hand-written files for what Blender 3.4 cannot write (ASCII FBX, OFF, .x, 3DS).
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <zlib.h>

#include "blender_scene.h"
#include "test_util.h"
#include "vdblight/errors.h"
#include "vdblight/scene.h"
#include "vdblight/scene_load.h"

using namespace vdblight;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

constexpr double kPiD = 3.14159265358979323846;

void expectVec(const Vec3d& got, const Vec3d& want, double tol, const std::string& what) {
    EXPECT_NEAR(got.x, want.x, tol) << what;
    EXPECT_NEAR(got.y, want.y, tol) << what;
    EXPECT_NEAR(got.z, want.z, tol) << what;
}

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

// ---------------------------------------------------------------------------------------
// Hand-written files: formats and variants Blender 3.4 does not write.

namespace {

/// ASCII FBX 7.4, hand-written (Blender 3.4 writes binary FBX only): a 10 x 20 quad in 3ds
/// Max's axis system (Z up, front -Y) with inches as the unit (UnitScaleFactor 2.54), an
/// emissive material and a point light 40 inches above.
const char* kAsciiFbx = R"FBX(; FBX 7.4.0 project file
; Hand-written for vdblight's tests: Blender 3.4 writes binary FBX only.
FBXHeaderExtension:  {
	FBXHeaderVersion: 1003
	FBXVersion: 7400
	Creator: "vdblight test (hand-written)"
}
GlobalSettings:  {
	Version: 1000
	Properties70:  {
		P: "UpAxis", "int", "Integer", "",2
		P: "UpAxisSign", "int", "Integer", "",1
		P: "FrontAxis", "int", "Integer", "",1
		P: "FrontAxisSign", "int", "Integer", "",-1
		P: "CoordAxis", "int", "Integer", "",0
		P: "CoordAxisSign", "int", "Integer", "",1
		P: "UnitScaleFactor", "double", "Number", "",2.54
	}
}
Objects:  {
	Geometry: 1000, "Geometry::Quad", "Mesh" {
		Vertices: *12 {
			a: 0,0,0,10,0,0,10,20,0,0,20,0
		}
		PolygonVertexIndex: *4 {
			a: 0,1,2,-4
		}
		GeometryVersion: 124
		LayerElementMaterial: 0 {
			Version: 101
			Name: ""
			MappingInformationType: "AllSame"
			ReferenceInformationType: "IndexToDirect"
			Materials: *1 {
				a: 0
			}
		}
		Layer: 0 {
			Version: 100
			LayerElement:  {
				Type: "LayerElementMaterial"
				TypedIndex: 0
			}
		}
	}
	Model: 2000, "Model::Quad", "Mesh" {
		Version: 232
		Properties70:  {
			P: "Lcl Translation", "Lcl Translation", "", "A",0,0,5
		}
	}
	Material: 3000, "Material::Lamp", "" {
		Version: 102
		ShadingModel: "lambert"
		Properties70:  {
			P: "DiffuseColor", "Color", "", "A",0.25,0.5,0.75
			P: "EmissiveColor", "Color", "", "A",1,1,1
			P: "EmissiveFactor", "Number", "", "A",2
		}
	}
	NodeAttribute: 4000, "NodeAttribute::Bulb", "Light" {
		Properties70:  {
			P: "LightType", "enum", "", "",0
			P: "Color", "Color", "", "A",1,1,1
			P: "Intensity", "Number", "", "A",400
		}
		TypeFlags: "Light"
	}
	Model: 5000, "Model::Bulb", "Light" {
		Version: 232
		Properties70:  {
			P: "Lcl Translation", "Lcl Translation", "", "A",0,0,40
		}
	}
}
Connections:  {
	C: "OO",2000,0
	C: "OO",1000,2000
	C: "OO",3000,2000
	C: "OO",5000,0
	C: "OO",4000,5000
}
)FBX";

void put16(std::string& s, uint16_t v) { s += char(v & 0xff); s += char(v >> 8); }
void put32(std::string& s, uint32_t v) { for (int k = 0; k < 4; ++k) s += char((v >> (8 * k)) & 0xff); }
std::string chunk(uint16_t id, const std::string& body) {
    std::string s;
    put16(s, id);
    put32(s, uint32_t(6 + body.size()));
    return s + body;
}

/// A 3DS file (main 0x4D4D > editor 0x3D3D > object 0x4000 > trimesh 0x4100 with vertex
/// list 0x4110 and face list 0x4120): one 2 x 1 quad in the z = 0 plane of 3ds Max (Z up).
std::string quad3ds() {
    std::string verts;
    put16(verts, 4);
    const float p[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    for (const auto& v : p)
        for (float c : v) { uint32_t u; std::memcpy(&u, &c, 4); put32(verts, u); }
    std::string faces;
    put16(faces, 2);
    for (uint16_t f : {0, 1, 2, 0, 0, 2, 3, 0}) put16(faces, f);
    const std::string mesh = chunk(0x4100, chunk(0x4110, verts) + chunk(0x4120, faces));
    const std::string object = chunk(0x4000, std::string("Quad") + '\0' + mesh);
    return chunk(0x4D4D, chunk(0x3D3D, object));
}

}  // namespace

TEST(SceneFormats, AsciiFbxZUpInInches) {
    TempDir dir;
    writeTextFile(dir.file("quad.fbx"), kAsciiFbx);
    SceneLoadReport r;
    const Scene s = loadScene(dir.file("quad.fbx"), {}, &r);
    EXPECT_EQ(r.format, "FBX (ascii)");
    EXPECT_NEAR(r.metresPerUnit, 0.0254, 1e-9);
    EXPECT_EQ(r.up, "Z (FBX UpAxis)");
    ASSERT_EQ(s.triangleCount(), 2u);
    // File (x, y, z) inches, Z up, front -Y -> ours (x, z, -y) x 0.0254 m.
    const Bounds b = s.worldBounds();
    expectVec(b.lo, {0, 5 * 0.0254, -20 * 0.0254}, 1e-5, "ascii fbx lo");
    expectVec(b.hi, {10 * 0.0254, 5 * 0.0254, 0}, 1e-5, "ascii fbx hi");
    expectVec(Vec3d(s.material(0).albedo), {0.25, 0.5, 0.75}, 1e-6, "DiffuseColor");
    expectVec(Vec3d(s.material(0).emission), {2, 2, 2}, 1e-6, "EmissiveColor x EmissiveFactor");
    ASSERT_EQ(s.pointLights.size(), 1u);
    expectVec(s.toWorld(s.pointLights[0].position), {0, 40 * 0.0254, 0}, 1e-5, "light position");
    expectVec(Vec3d(s.pointLights[0].intensity), Vec3d(1, 1, 1) * (4.0 / (4 * kPiD)), 1e-6, "Intensity 400 = 4 W");

    // --scale and --up override the file: 1 unit = 1 m, Y up (coordinates kept).
    SceneLoadOptions o;
    o.scale = 1.0;
    o.up = UpAxis::Y;
    const Bounds kept = loadScene(dir.file("quad.fbx"), o, &r).worldBounds();
    expectVec(kept.lo, {0, 0, 5}, 1e-5, "fbx overridden lo");
    expectVec(kept.hi, {10, 20, 5}, 1e-5, "fbx overridden hi");
}

TEST(SceneFormats, OffXAnd3ds) {
    TempDir dir;
    // OFF: a unit cube's six quads.
    writeTextFile(dir.file("cube.off"),
                  "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                  "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n");
    SceneLoadReport r;
    Scene s = loadScene(dir.file("cube.off"), {}, &r);
    EXPECT_EQ(r.format, "OFF");
    EXPECT_EQ(s.triangleCount(), 12u);
    EXPECT_TRUE(r.defaultAlbedoOnly);
    expectVec(s.worldBounds().hi, {1, 1, 1}, 1e-6, "off");

    // DirectX .x (text): one quad at z = 1, with a material whose diffuse colour is (0.1, 0.2, 0.3).
    writeTextFile(dir.file("quad.x"),
                  "xof 0303txt 0032\n"
                  "Mesh Quad {\n 4;\n 0.0;0.0;1.0;,\n 2.0;0.0;1.0;,\n 2.0;1.0;1.0;,\n 0.0;1.0;1.0;;\n"
                  " 1;\n 4;0,1,2,3;;\n"
                  " MeshMaterialList {\n  1;\n  1;\n  0;;\n"
                  "  Material Paint {\n   0.1;0.2;0.3;1.0;;\n   10.0;\n   0.0;0.0;0.0;;\n   0.0;0.0;0.0;;\n  }\n }\n}\n");
    s = loadScene(dir.file("quad.x"), {}, &r);
    EXPECT_EQ(r.format, "DirectX .x");
    EXPECT_EQ(s.triangleCount(), 2u);
    expectVec(Vec3d(s.material(0).albedo), {0.1, 0.2, 0.3}, 1e-6, ".x material");
    const Bounds bx = s.worldBounds();
    EXPECT_NEAR(bx.hi.x - bx.lo.x, 2.0, 1e-6);
    EXPECT_NEAR(bx.hi.y - bx.lo.y, 1.0, 1e-6);
    EXPECT_NEAR(bx.lo.z, -1.0, 1e-6) << "DirectX is left-handed: Assimp negates z";

    // 3DS: Assimp turns 3ds Max's Z up into Y up.
    {
        std::ofstream f(dir.file("quad.3ds"), std::ios::binary);
        const std::string data = quad3ds();
        f.write(data.data(), std::streamsize(data.size()));
    }
    s = loadScene(dir.file("quad.3ds"), {}, &r);
    EXPECT_EQ(r.format, "3DS");
    EXPECT_EQ(s.triangleCount(), 2u);
    const Bounds b3 = s.worldBounds();
    EXPECT_NEAR(b3.hi.x - b3.lo.x, 2.0, 1e-6);
    EXPECT_NEAR(b3.hi.y - b3.lo.y, 0.0, 1e-6) << "the quad lies in 3ds Max's ground plane";
    EXPECT_NEAR(b3.hi.z - b3.lo.z, 1.0, 1e-6);
}

TEST(SceneFormats, UnsupportedExtensionListsEveryFormat) {
    TempDir dir;
    writeTextFile(dir.file("scene.xyz"), "1 2 3\n");
    try {
        loadScene(dir.file("scene.xyz"));
        FAIL() << "loaded an .xyz file";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos);
        for (const char* ext : {".fbx", ".dae", ".3ds", ".stl", ".off", ".x", ".gltf", ".glb", ".obj", ".ply"})
            EXPECT_NE(what.find(std::string(" ") + ext), std::string::npos) << ext << " missing in: " << what;
    }
    const std::vector<std::string> all = supportedSceneExtensions();
    EXPECT_TRUE(std::is_sorted(all.begin(), all.end()));
}

TEST(SceneFormats, ObjWithMissingMaterialLibraryWarns) {
    TempDir dir;
    writeTextFile(dir.file("tri.obj"), "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Red\nf 1 2 3\n");
    SceneLoadReport r;
    const Scene s = loadScene(dir.file("tri.obj"), {}, &r);
    EXPECT_EQ(s.triangleCount(), 1u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("gone.mtl' not found"), std::string::npos) << r.warnings[0];
    EXPECT_TRUE(r.defaultAlbedoOnly);
}

TEST(SceneFormats, BadScaleIsRefused) {
    SceneLoadOptions o;
    o.scale = -1;
    EXPECT_THROW(loadScene(defaultScenePath(), o), ValueError);
    o.scale = std::nan("");
    EXPECT_THROW(loadScene(defaultScenePath(), o), ValueError);
}

TEST(SceneFormats, PlyUnknownHeaderLinesWarnUnlessTheyCouldDeclareData) {
    TempDir dir;
    // Blender 2.47's exporter wrote its signature without "comment"; scanner software writes
    // similar free text. The layout (elements and properties) is untouched by such a line.
    const std::string body = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    writeTextFile(dir.file("old_blender.ply"),
                  "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: 'room.blend'\n"
                  "Scanner serial 0042 calibrated 2009\n" + body);
    SceneLoadReport r;
    const Scene s = loadScene(dir.file("old_blender.ply"), {}, &r);
    EXPECT_EQ(s.triangleCount(), 1u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("skipped 2 header line(s)"), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("line 3 'Created by Blender3D 247"), std::string::npos) << r.warnings[0];

    // A misspelt property would change how every record is read: still an error.
    writeTextFile(dir.file("misspelt.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                            "property float y\nproperty float z\nprop float w\nend_header\n"
                                            "0 0 0 0\n1 0 0 0\n0 1 0 0\n");
    try {
        loadScene(dir.file("misspelt.ply"));
        FAIL() << "read a PLY whose header may declare an unknown property";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown keyword 'prop' in what may declare a property or element"),
                  std::string::npos) << e.what();
    }
}

TEST(SceneFormats, ObjVariantsAssimpMisreads) {
    // Assimp 5.2.5 alone skips indented lines and drops vertex lines with numbers like ".5"
    // (the face then reads as "vertex index out of range"): both are real-world OBJ variants.
    TempDir dir;
    writeTextFile(dir.file("variants.obj"),
                  "# indented, tabs, leading-dot numbers, CRLF\r\n"
                  "  v 0 0 0\r\n\tv\t-.5 0 +.25\r\nv .5 .75 -.125\r\n"
                  "\tvn 0 0 1\r\n  f 1//1 2//1 3//1\r\n");
    const Scene s = loadScene(dir.file("variants.obj"));
    ASSERT_EQ(s.triangleCount(), 1u);
    const Bounds b = s.worldBounds();
    expectVec(b.lo, {-0.5, 0, -0.125}, 1e-7, "obj variants lo");
    expectVec(b.hi, {0.5, 0.75, 0.25}, 1e-7, "obj variants hi");
    // Only vertex data is touched: a material named ".5" keeps its name and colour.
    writeTextFile(dir.file("dot.mtl"), "newmtl .5\nKd 0.5 0.25 0.125\n");
    writeTextFile(dir.file("dot.obj"), "mtllib dot.mtl\n v 0 0 0\nv 1 0 0\nv 0 .5 0\nusemtl .5\nf 1 2 3\n");
    const Scene d = loadScene(dir.file("dot.obj"));
    ASSERT_EQ(d.triangleCount(), 1u);
    EXPECT_EQ(d.material(0).name, ".5");
    expectVec(Vec3d(d.material(0).albedo), {0.5, 0.25, 0.125}, 1e-6, "material '.5'");
    expectVec(d.worldBounds().hi, {1, 0.5, 0}, 1e-7, "dot.obj");
}

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
