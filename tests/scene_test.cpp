// Tests of the scene module: the bundled Cornell box, loading each supported format
// (materials, emission, lights, node transforms), the error paths and the content hash
// (the sky map convention: sky_map_test.cpp). Every input file is written by the test into
// a TempDir.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "expect_throw.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::expectThrowWith;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

Vec3f triangleNormal(const Scene& s, std::size_t t) {
    return normalize(cross(s.vertex(t, 1) - s.vertex(t, 0), s.vertex(t, 2) - s.vertex(t, 0)));
}

const Material* findMaterial(const Scene& s, const std::string& name) {
    for (const auto& m : s.materials) if (m.name == name) return &m;
    return nullptr;
}

void expectRgbNear(const Rgb& actual, const Rgb& expected, float tol = 1e-5f) {
    EXPECT_NEAR(actual.x, expected.x, tol);
    EXPECT_NEAR(actual.y, expected.y, tol);
    EXPECT_NEAR(actual.z, expected.z, tol);
}

std::string base64(const std::vector<unsigned char>& data) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < data.size(); i += 3) {
        const uint32_t n = (uint32_t(data[i]) << 16) | (i + 1 < data.size() ? uint32_t(data[i + 1]) << 8 : 0) |
                           (i + 2 < data.size() ? uint32_t(data[i + 2]) : 0);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < data.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < data.size() ? table[n & 63] : '=';
    }
    return out;
}

/// Bytes of one triangle (0,0,0) (1,0,0) (0,1,0): counter-clockwise seen from +z.
std::vector<unsigned char> triangleBytes() {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::vector<unsigned char> bytes(sizeof p);
    std::memcpy(bytes.data(), p, sizeof p);
    return bytes;
}

/// A glTF document with one triangle mesh (mesh 0, material 0 if `materials` is not empty).
/// `nodes` is the JSON array of nodes; `extra` is spliced into the top-level object.
std::string gltfJson(const std::string& materials, const std::string& nodes, const std::string& extra,
                     const std::string& bufferUri) {
    const std::string uri = bufferUri.empty() ? "" : "\"uri\": \"" + bufferUri + "\", ";
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": )" + nodes + R"(,
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0})" +
           (materials.empty() ? "" : ", \"material\": 0") + R"(}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{)" + uri + R"("byteLength": 36}])" +
           (materials.empty() ? "" : ",\n  \"materials\": " + materials) + extra + "}";
}

std::string gltfWithTriangle(const std::string& materials, const std::string& nodes, const std::string& extra = "") {
    return gltfJson(materials, nodes, extra, "data:application/octet-stream;base64," + base64(triangleBytes()));
}

/// A .glb: 12-byte header, JSON chunk, BIN chunk (both padded to 4 bytes).
std::string glbWithTriangle(const std::string& materials, const std::string& nodes, const std::string& extra) {
    std::string json = gltfJson(materials, nodes, extra, "");
    while (json.size() % 4) json += ' ';
    const std::vector<unsigned char> bin = triangleBytes();  // 36 bytes, already aligned
    auto u32 = [](std::string& s, uint32_t v) { for (int k = 0; k < 4; ++k) s += char((v >> (8 * k)) & 0xff); };
    std::string out = "glTF";
    u32(out, 2);
    u32(out, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    u32(out, uint32_t(json.size()));
    out += "JSON";
    out += json;
    u32(out, uint32_t(bin.size()));
    out += std::string("BIN\0", 4);
    out.append(bin.begin(), bin.end());
    return out;
}

const char* kEmissiveMaterial = R"([{"name": "lamp", "doubleSided": true,
    "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
    "emissiveFactor": [1.0, 0.5, 0.25],
    "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5.0}}}])";
const char* kEmissiveExtensions = R"(, "extensionsUsed": ["KHR_materials_emissive_strength"])";

}  // namespace

// ---------------------------------------------------------------------------------------
// The bundled Cornell box

TEST(CornellBox, LoadsWithPublishedGeometryAndColours) {
    const Scene s = loadScene(defaultScenePath());
    EXPECT_EQ(s.name, "cornell_box");
    EXPECT_EQ(s.triangleCount(), 32u);  // 16 quads
    EXPECT_EQ(s.stats.degenerateTrianglesSkipped, 0u);
    const Bounds b = s.bounds();
    EXPECT_NEAR(b.lo.x, 0.0, 1e-6); EXPECT_NEAR(b.hi.x, 0.556, 1e-6);
    EXPECT_NEAR(b.lo.y, 0.0, 1e-6); EXPECT_NEAR(b.hi.y, 0.5488, 1e-6);
    EXPECT_NEAR(b.lo.z, 0.0, 1e-6); EXPECT_NEAR(b.hi.z, 0.5592, 1e-6);

    int emissiveMaterials = 0;
    for (const auto& m : s.materials) emissiveMaterials += m.isEmissive();
    EXPECT_EQ(emissiveMaterials, 1);
    std::size_t emissiveTriangles = 0;
    for (std::size_t t = 0; t < s.triangleCount(); ++t) {
        if (!s.material(t).isEmissive()) continue;
        ++emissiveTriangles;
        expectRgbNear(s.material(t).emission, {17, 12, 4});
        EXPECT_FALSE(s.material(t).twoSidedEmission);
        EXPECT_NEAR(triangleNormal(s, t).y, -1.0f, 1e-6f) << "the light must face down";
        EXPECT_NEAR(s.vertex(t, 0).y, 0.5487f, 1e-6f);
    }
    EXPECT_EQ(emissiveTriangles, 2u);
    ASSERT_TRUE(findMaterial(s, "red") && findMaterial(s, "green") && findMaterial(s, "white"));
    expectRgbNear(findMaterial(s, "red")->albedo, {0.63f, 0.065f, 0.05f});
    expectRgbNear(findMaterial(s, "green")->albedo, {0.14f, 0.45f, 0.091f});
    expectRgbNear(findMaterial(s, "white")->albedo, {0.725f, 0.71f, 0.68f});
    EXPECT_TRUE(s.hasEmissiveTriangles());
    EXPECT_TRUE(s.hasLight());
}

TEST(CornellBox, FrontFacesPointIntoTheRoomAndOutOfTheBlocks) {
    const Scene s = loadScene(defaultScenePath());
    const Vec3f room{0.278f, 0.274f, 0.28f}, shortBlock{0.186f, 0.0825f, 0.169f}, tallBlock{0.3685f, 0.165f, 0.3515f};
    for (std::size_t t = 0; t < s.triangleCount(); ++t) {
        bool block = true;
        float top = 0;
        for (int k = 0; k < 3; ++k) {
            const Vec3f p = s.vertex(t, k);
            block = block && p.x > 0.08f && p.x < 0.48f && p.z > 0.06f && p.z < 0.46f && p.y < 0.331f;
            top = std::max(top, p.y);
        }
        const Vec3f p = s.vertex(t, 0), n = triangleNormal(s, t);
        if (block)
            EXPECT_GT(dot(n, p - (top < 0.2f ? shortBlock : tallBlock)), 0.0f) << "block triangle " << t;
        else
            EXPECT_GT(dot(n, room - p), 0.0f) << "room triangle " << t << " (" << s.material(t).name << ")";
    }
}

TEST(DefaultScenePath, HonoursDataDirEnvironmentVariable) {
    TempDir dir;
    writeTextFile(dir.file("cornell_box.obj"), "v 0 0 0\n");
    ::setenv("VDBLIGHT_DATA_DIR", dir.path().c_str(), 1);
    const std::string path = defaultScenePath();
    ::unsetenv("VDBLIGHT_DATA_DIR");
    EXPECT_EQ(path, dir.file("cornell_box.obj"));
    ::setenv("VDBLIGHT_DATA_DIR", "/nonexistent/vdblight", 1);
    EXPECT_NE(defaultScenePath(), "");  // falls back to the build/source tree
    ::unsetenv("VDBLIGHT_DATA_DIR");
}

// ---------------------------------------------------------------------------------------
// Formats

TEST(LoadObj, MtlDiffuseAndEmission) {
    TempDir dir;
    writeTextFile(dir.file("lamp.mtl"), "newmtl glow\nKd 0.5 0.25 0.125\nKe 2 3 4\n"
                                        "newmtl bright\nKd 1.5 1 1\n");
    writeTextFile(dir.file("lamp.obj"), "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                        "usemtl glow\nf 1 2 3\nusemtl bright\nf 2 4 3\n");
    const Scene s = loadScene(dir.file("lamp.obj"));
    EXPECT_EQ(s.name, "lamp");
    ASSERT_EQ(s.triangleCount(), 2u);
    const Material* glow = findMaterial(s, "glow");
    ASSERT_TRUE(glow);
    expectRgbNear(glow->albedo, {0.5f, 0.25f, 0.125f});
    expectRgbNear(glow->emission, {2, 3, 4});
    expectRgbNear(findMaterial(s, "bright")->albedo, {0.999f, 0.999f, 0.999f});  // clamped
    EXPECT_FALSE(findMaterial(s, "bright")->isEmissive());
    EXPECT_EQ(s.stats.inputTriangles, 2u);
    EXPECT_GE(s.stats.meshes, 1u);
    EXPECT_NEAR(triangleNormal(s, 0).z, 1.0f, 1e-6f);
}

TEST(LoadObj, QuadsAreTriangulated) {
    TempDir dir;
    writeTextFile(dir.file("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    const Scene s = loadScene(dir.file("quad.obj"));
    ASSERT_EQ(s.triangleCount(), 2u);
    for (std::size_t t = 0; t < 2; ++t) EXPECT_NEAR(triangleNormal(s, t).z, 1.0f, 1e-6f);
    expectRgbNear(s.materials[s.materialIds[0]].albedo, {0.8f, 0.8f, 0.8f});  // no MTL: default grey
}

TEST(LoadGltf, EmissiveStrengthScalesEmissiveFactor) {
    TempDir dir;
    writeTextFile(dir.file("lamp.gltf"), gltfWithTriangle(kEmissiveMaterial, R"([{"mesh": 0}])", kEmissiveExtensions));
    const Scene s = loadScene(dir.file("lamp.gltf"));
    ASSERT_EQ(s.triangleCount(), 1u);
    const Material& m = s.material(0);
    EXPECT_EQ(m.name, "lamp");
    expectRgbNear(m.albedo, {0.2f, 0.4f, 0.6f});
    expectRgbNear(m.emission, {5.0f, 2.5f, 1.25f});
    EXPECT_TRUE(m.twoSidedEmission);  // doubleSided
}

TEST(LoadGltf, GlbReadsEmissiveStrengthFromJsonChunk) {
    TempDir dir;
    writeTextFile(dir.file("lamp.glb"), glbWithTriangle(kEmissiveMaterial, R"([{"mesh": 0}])", kEmissiveExtensions));
    const Scene s = loadScene(dir.file("lamp.glb"));
    ASSERT_EQ(s.triangleCount(), 1u);
    expectRgbNear(s.material(0).emission, {5.0f, 2.5f, 1.25f});
}

TEST(LoadGltf, WithoutStrengthEmissionIsTheFactorAndSingleSided) {
    TempDir dir;
    writeTextFile(dir.file("plain.gltf"),
                  gltfWithTriangle(R"([{"emissiveFactor": [0.5, 0.5, 0.5]}])", R"([{"mesh": 0}])"));
    const Scene s = loadScene(dir.file("plain.gltf"));
    expectRgbNear(s.material(0).emission, {0.5f, 0.5f, 0.5f});
    expectRgbNear(s.material(0).albedo, {0.999f, 0.999f, 0.999f});  // glTF default base colour 1
    EXPECT_FALSE(s.material(0).twoSidedEmission);
}

TEST(LoadGltf, NodeTransformAppliesToVertices) {
    TempDir dir;
    // Parent translates by (10, 0, 0); child scales by 2: p -> (10 + 2x, 2y, 2z).
    writeTextFile(dir.file("moved.gltf"),
                  gltfWithTriangle("", R"([{"translation": [10, 0, 0], "children": [1]},
                                           {"scale": [2, 2, 2], "mesh": 0}])"));
    const Scene s = loadScene(dir.file("moved.gltf"));
    ASSERT_EQ(s.triangleCount(), 1u);
    const Bounds b = s.bounds();
    EXPECT_NEAR(b.lo.x, 10.0, 1e-5); EXPECT_NEAR(b.hi.x, 12.0, 1e-5);
    EXPECT_NEAR(b.lo.y, 0.0, 1e-5);  EXPECT_NEAR(b.hi.y, 2.0, 1e-5);
    EXPECT_NEAR(triangleNormal(s, 0).z, 1.0f, 1e-6f);
}

TEST(LoadGltf, MirroringTransformKeepsTheAuthoredFrontFace) {
    TempDir dir;
    // The triangle faces +z; mirrored in z its front face must face -z (glTF: det < 0 flips winding).
    writeTextFile(dir.file("mirror.gltf"), gltfWithTriangle("", R"([{"scale": [1, 1, -1], "mesh": 0}])"));
    const Scene s = loadScene(dir.file("mirror.gltf"));
    ASSERT_EQ(s.triangleCount(), 1u);
    EXPECT_NEAR(triangleNormal(s, 0).z, -1.0f, 1e-6f);
}

TEST(LoadGltf, PunctualLightsUnderATransformedNode) {
    TempDir dir;
    // Parent at (1, 2, 3) rotated +90 degrees about +Y: local -Z becomes world -X, local +Z world +X.
    const std::string nodes = R"([{"children": [1, 2, 3, 4], "translation": [1, 2, 3],
                                   "rotation": [0, 0.70710678, 0, 0.70710678]},
        {"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [0, 0, 1], "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"extensions": {"KHR_lights_punctual": {"light": 2}}},
        {"mesh": 0}])";
    const std::string lights = R"(, "extensionsUsed": ["KHR_lights_punctual"],
      "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 10},
        {"type": "spot", "color": [1, 1, 1], "intensity": 4,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
        {"type": "directional", "color": [0.5, 1, 1], "intensity": 3},
        {"type": "point", "intensity": 99}]}})";  // no node refers to it: not in the scene
    writeTextFile(dir.file("lights.gltf"), gltfWithTriangle("", nodes, lights));
    const Scene s = loadScene(dir.file("lights.gltf"));

    ASSERT_EQ(s.pointLights.size(), 1u);
    expectRgbNear(s.pointLights[0].position, {1, 3, 3});
    expectRgbNear(s.pointLights[0].intensity, {10, 5, 2.5f});  // colour x intensity, cd as W/sr

    ASSERT_EQ(s.spotLights.size(), 1u);
    expectRgbNear(s.spotLights[0].position, {2, 2, 3});
    expectRgbNear(s.spotLights[0].direction, {-1, 0, 0});
    expectRgbNear(s.spotLights[0].intensity, {4, 4, 4});
    EXPECT_NEAR(s.spotLights[0].innerConeAngle, 0.2f, 1e-6f);  // half-angles, as in glTF
    EXPECT_NEAR(s.spotLights[0].outerConeAngle, 0.5f, 1e-6f);

    ASSERT_EQ(s.directionalLights.size(), 1u);
    expectRgbNear(s.directionalLights[0].direction, {-1, 0, 0});  // the way the light travels
    expectRgbNear(s.directionalLights[0].irradiance, {1.5f, 3, 3});  // lux as W/m^2
    EXPECT_TRUE(s.hasLight());
    EXPECT_FALSE(s.hasEmissiveTriangles());
    // The mesh sits under the same rotated, translated parent.
    expectRgbNear(s.vertex(0, 1), {1, 2, 2});  // (1,0,0) -> R (1,0,0) = (0,0,-1), + (1,2,3)
}

TEST(LoadPly, AsciiLoadsWithDefaultAlbedo) {
    TempDir dir;
    writeTextFile(dir.file("square.ply"), "ply\nformat ascii 1.0\nelement vertex 4\n"
                                          "property float x\nproperty float y\nproperty float z\n"
                                          "element face 2\nproperty list uchar int vertex_indices\n"
                                          "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    const Scene s = loadScene(dir.file("square.ply"));
    EXPECT_EQ(s.name, "square");
    ASSERT_EQ(s.triangleCount(), 2u);
    ASSERT_EQ(s.materials.size(), 1u);
    expectRgbNear(s.material(0).albedo, {0.8f, 0.8f, 0.8f});
    EXPECT_FALSE(s.hasLight());
}

// ---------------------------------------------------------------------------------------
// Errors

TEST(LoadErrors, MissingFileIsIoError) {
    TempDir dir;
    expectThrowWith<IoError>([&] { loadScene(dir.file("nothing.obj")); }, "nothing.obj");
}

TEST(LoadErrors, UnsupportedExtensionIsSceneError) {
    TempDir dir;
    writeTextFile(dir.file("scene.xyz"), "whatever\n");
    expectThrowWith<SceneError>([&] { loadScene(dir.file("scene.xyz")); },
                                "unsupported scene format '.xyz' (supported: .3d .3ds");
}

TEST(LoadErrors, GarbageContentThrowsWithoutCrashing) {
    TempDir dir;
    std::string garbage = "\x01\x02 this is not a scene {\"[ \xff\xfe\n";
    for (int i = 0; i < 50; ++i) garbage += char((i * 37 + 11) & 0xff);
    for (const char* name : {"g.obj", "g.gltf", "g.glb", "g.ply"}) {
        writeTextFile(dir.file(name), garbage);
        try {
            loadScene(dir.file(name));
            ADD_FAILURE() << name << " loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        } catch (const IoError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
}

TEST(LoadErrors, ObjWithoutFacesHasNoTriangles) {
    TempDir dir;
    writeTextFile(dir.file("points.obj"), "# only vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    expectThrowWith<SceneError>([&] { loadScene(dir.file("points.obj")); }, "scene 'points' has no triangles");
}

TEST(LoadErrors, NanCoordinateNamesTheFile) {
    TempDir dir;
    writeTextFile(dir.file("nan.obj"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    expectThrowWith<SceneError>([&] { loadScene(dir.file("nan.obj")); }, "nan.obj");
}

TEST(LoadErrors, DegenerateTrianglesAreSkippedAndCounted) {
    TempDir dir;
    writeTextFile(dir.file("degenerate.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                              "f 1 2 3\nf 1 2 4\nf 1 2 2\n");  // collinear, repeated
    const Scene s = loadScene(dir.file("degenerate.obj"));
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_EQ(s.stats.inputTriangles, 3u);
    EXPECT_EQ(s.stats.degenerateTrianglesSkipped, 2u);
}

// ---------------------------------------------------------------------------------------
// Building blocks

TEST(AddTriangle, SkipsSliversAndRejectsNonFinite) {
    Scene s;
    s.name = "t";
    const uint32_t m = addMaterial(s, Material{"m"});
    addTriangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, m);
    addTriangle(s, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, m);           // zero area
    addTriangle(s, {0, 0, 0}, {1e6f, 0, 0}, {0.5e6f, 1e-8f, 0}, m);  // sine ~ 1e-14
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_EQ(s.stats.inputTriangles, 3u);
    EXPECT_EQ(s.stats.degenerateTrianglesSkipped, 2u);
    EXPECT_EQ(s.positions.size(), 3u);  // skipped triangles leave no vertices behind
    EXPECT_THROW(addTriangle(s, {0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}, m), SceneError);
    EXPECT_THROW(addTriangle(s, {0, 0, 0}, {INFINITY, 0, 0}, {0, 1, 0}, m), SceneError);
    EXPECT_NO_THROW(validateScene(s));
}

TEST(AddMaterial, ClampsAlbedoAndEmission) {
    Scene s;
    Material m;
    m.albedo = {1.2f, -0.1f, 0.5f};
    m.emission = {-1, 2, 0};
    const Material& stored = s.materials[addMaterial(s, m)];
    expectRgbNear(stored.albedo, {0.999f, 0, 0.5f});
    expectRgbNear(stored.emission, {0, 2, 0});
    m.albedo = {NAN, 0, 0};
    EXPECT_THROW(addMaterial(s, m), SceneError);
}

TEST(ValidateScene, ReportsEachBrokenInvariant) {
    Scene s;
    s.name = "broken";
    expectThrowWith<SceneError>([&] { validateScene(s); }, "scene 'broken' has no triangles");
    addMaterial(s, Material{});
    addTriangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0);
    validateScene(s);
    s.materialIds[0] = 7;
    expectThrowWith<SceneError>([&] { validateScene(s); }, "material id 7");
    s.materialIds[0] = 0;
    s.indices[1] = 99;
    expectThrowWith<SceneError>([&] { validateScene(s); }, "vertex index 99");
    s.indices[1] = 1;
    s.positions[2].y = NAN;
    expectThrowWith<SceneError>([&] { validateScene(s); }, "not finite");
}

TEST(ContentHash, StableAndSensitiveToAlbedo) {
    const Scene a = loadScene(defaultScenePath());
    const Scene b = loadScene(defaultScenePath());
    const std::string h = a.contentHash();
    ASSERT_EQ(h.size(), 16u);
    EXPECT_EQ(h.find_first_not_of("0123456789abcdef"), std::string::npos) << h;
    EXPECT_EQ(h, b.contentHash());
    Scene c = a;
    c.materials[0].albedo.x *= 0.5f;
    EXPECT_NE(h, c.contentHash());
    Scene d = a;
    d.sky.constant = {0.1f, 0.1f, 0.1f};
    EXPECT_NE(h, d.contentHash());
    Scene e = a;
    e.name = "renamed";
    EXPECT_EQ(h, e.contentHash()) << "names do not change the lighting";
}
