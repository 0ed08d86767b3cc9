// Formats and variants Blender 3.4 does not write, through loadScene, from small hand-written
// files (ASCII FBX, OFF, DirectX .x, 3DS, PLY and OBJ variants), and the loader's refusals and
// warnings. Files written by Blender itself: scene_formats_blender_test.cpp; diffuse textures:
// scene_formats_texture_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "scene_formats_util.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectVec;
using vdblight::test::kPiD;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

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
