// The formats end to end through `vdblight bake` and `query`, and the bad-input table of
// docs/scene.md ("What the user sees for a bad scene file"): one row per class of bad file,
// each with the exact line the user sees, a non-zero exit and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "blender_scene.h"
#include "cli_util.h"
#include "test_util.h"

using namespace vdblight::test;

namespace {

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary);
    f.write(bytes.data(), std::streamsize(bytes.size()));
    ASSERT_TRUE(f.good()) << path;
}

void put32(std::string& s, uint32_t v) { for (int k = 0; k < 4; ++k) s += char((v >> (8 * k)) & 0xff); }
void putFloat(std::string& s, float f) { uint32_t u; std::memcpy(&u, &f, 4); put32(s, u); }

/// Binary STL: 80-byte header, `declared` facets, then `written` facets of one triangle.
std::string binaryStl(uint32_t declared, uint32_t written, float x = 0.0f) {
    std::string s(80, ' ');
    put32(s, declared);
    for (uint32_t i = 0; i < written; ++i) {
        for (float v : {0.f, 0.f, 1.f, x, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) putFloat(s, v);
        s += std::string(2, '\0');
    }
    return s;
}

/// A .glb: 12-byte header, then a JSON chunk whose declared length is `declaredJson` (with the
/// true length, Assimp reads it and stops at the missing buffer).
std::string glb(std::string json, uint32_t declaredJson, bool magic = true) {
    while (json.size() % 4) json += ' ';  // chunks are 4-byte aligned
    std::string s = magic ? "glTF" : "gltf";
    put32(s, 2);
    put32(s, uint32_t(12 + 8 + json.size()));
    put32(s, declaredJson);
    s += "JSON";
    return s + json;
}

const char* kTriangleGltf = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
"bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"uri":"missing.bin","byteLength":36}]})";

uint32_t padded(const std::string& json) { return uint32_t((json.size() + 3) / 4 * 4); }

struct BadFile {
    std::string row;       ///< the docs/scene.md table row this tests
    std::string name;      ///< file name in the test directory
    std::string contents;  ///< bytes
    std::string expected;  ///< text the one line of output must contain
};

}  // namespace

// Every row of the bad-input table: `bake FILE -o DIR/bad.vdb` exits non-zero with exactly one
// line that names the problem, and leaves no file behind.
TEST(CliFormats, BadInputTable) {
    TempDir dir;
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::vector<BadFile> rows = {
        {"wrong magic", "magic.glb", glb("{}", 2, false), "cannot load scene file"},
        {"wrong magic", "magic.ply", "plx\nformat ascii 1.0\nend_header\n", "PLY: not a PLY file (first line is not 'ply')"},
        {"wrong magic", "magic.fbx", "this is not an FBX file\n", "cannot load scene file"},
        {"wrong magic", "magic.dae", "<html><body>not COLLADA</body></html>\n", "cannot load scene file"},
        {"truncated", "cut.stl", binaryStl(2, 2).substr(0, 84 + 50 + 20),
         "the binary STL header declares 2 triangles, more than the file holds"},
        {"truncated", "cut.ply", ply + "0 0 0\n1 0 0\n0 1", "PLY: element 'vertex' record 2"},
        {"truncated", "cut.glb", glb(kTriangleGltf, padded(kTriangleGltf)).substr(0, 40), "but the file has 40"},
        {"declared size past the end", "size.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000\n"
                                                   "property float x\nproperty float y\nproperty float z\nend_header\n"
                                                   + std::string(36, '\0'),
         "PLY: element 'vertex' declares 1000 records, more than the 36 bytes left"},
        {"declared size past the end", "size.stl", binaryStl(1000, 1),
         "the binary STL header declares 1000 triangles, more than the file holds"},
        {"declared size past the end", "size.glb", glb(kTriangleGltf, 100000),
         "GLB chunk 0 declares 100000 bytes, past the end of the file"},
        {"absurd count", "count.ply", "ply\nformat ascii 1.0\nelement vertex 9999999999999999999\nproperty float x\n"
                                      "property float y\nproperty float z\nend_header\n0 0 0\n",
         "PLY: more than 2^32 - 1 vertices"},
        {"absurd count", "count.stl", binaryStl(0xFFFFFFFFu, 1),
         "the binary STL header declares 4294967295 triangles, more than the file holds"},
        {"absurd count", "count.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n", "cannot load scene file"},
        {"NaN / Inf", "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "non-finite"},
        {"NaN / Inf", "inf.ply", ply + "inf 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "PLY: vertex 0 has a non-finite coordinate"},
        {"NaN / Inf", "nan.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                 "endloop\nendfacet\nendsolid t\n", "non-finite"},
        {"no triangles", "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "has no triangles"},
        {"no triangles", "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n", "has no triangles"},
        {"no triangles", "empty.ply", ply.substr(0, ply.find("element face")) + "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
         "has no triangles"},
        {"no triangles", "degenerate.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n", "has no triangles"},
        {"missing .bin", "nobin.gltf", kTriangleGltf, "cannot load scene file"},
        {"unsupported extension", "scene.xyz", "0 0 0\n", "unsupported scene format '.xyz' (supported: "},
    };
    for (const BadFile& r : rows) {
        SCOPED_TRACE(r.row + ": " + r.name);
        writeBytes(dir.file(r.name), r.contents);
        const std::size_t before = filesIn(dir.path());
        const CliRun run = runCli("bake '" + dir.file(r.name) + "' --sky 1,1,1 --resolution 4 --rays 16 -o '" +
                                  dir.file("bad.vdb") + "'");
        EXPECT_NE(run.status, 0) << run.output;
        EXPECT_LT(run.status, 128) << "crashed: " << run.output;
        EXPECT_EQ(countLines(run.output), 1) << run.output;
        EXPECT_NE(run.output.find(r.expected), std::string::npos) << "expected '" << r.expected << "' in: " << run.output;
        EXPECT_NE(run.output.find(dir.file(r.name)), std::string::npos) << "the line names the file: " << run.output;
        EXPECT_EQ(filesIn(dir.path()), before) << "a file was left behind";
    }
}

TEST(CliFormats, BadPathsAreOneLine) {
    TempDir dir;
    std::filesystem::create_directory(dir.path() / "folder.obj");
    expectCleanFailureWithOutput(dir, "bake '" + dir.file("folder.obj") + "' --sky 1,1,1",
                                 "scene file '" + dir.file("folder.obj") + "' is a directory");
    expectCleanFailureWithOutput(dir, "bake '" + dir.file("nowhere.obj") + "' --sky 1,1,1",
                                 "scene file '" + dir.file("nowhere.obj") + "' does not exist");
    // A name that is not UTF-8 (Latin-1 e acute) is a name like any other: missing, then read.
    const std::string latin1 = dir.file("sc\xe9ne.obj");
    expectCleanFailureWithOutput(dir, "bake '" + latin1 + "' --sky 1,1,1", "' does not exist");
    writeTextFile(latin1, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const CliRun ok = runCli("bake '" + latin1 + "' --sky 1,1,1 --resolution 4 --rays 16 -o '" + dir.file("ok.vdb") + "'");
    EXPECT_EQ(ok.status, 0) << ok.output;
    EXPECT_TRUE(std::filesystem::exists(dir.file("ok.vdb")));
    // Options: a scale that is not positive, an up axis that is not y or z.
    expectCleanFailureWithOutput(dir, "bake '" + latin1 + "' --sky 1,1,1 --scale 0",
                                 "--scale must be a positive number of metres per file unit, got '0'");
    expectCleanFailureWithOutput(dir, "bake '" + latin1 + "' --sky 1,1,1 --up x", "--up must be y or z, got 'x'");
    // Every command that loads a scene has them.
    expectCleanFailureWithOutput(dir, "prt bake '" + latin1 + "' --scale -2", "--scale must be a positive number");
    expectCleanFailure(dir, "check-scene '" + latin1 + "' --up w", "--up must be y or z, got 'w'");
    writeTextFile(dir.file("points.csv"), "0.2,0.2,0.5,0,0,-1\n");
    expectCleanFailure(dir, "reference '" + latin1 + "' --sky 1,1,1 --scale abc --points '" + dir.file("points.csv") + "'",
                       "--scale must be a positive number of metres per file unit, got 'abc'");
}

// Files that refer to other files that are missing still bake, with one warning line on stderr.
TEST(CliFormats, MissingReferencedFilesWarn) {
    TempDir dir;
    writeTextFile(dir.file("nomtl.obj"), "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Red\nf 1 2 3\n");
    CliRun r = runCli("bake '" + dir.file("nomtl.obj") + "' --sky 1,1,1 --resolution 4 --rays 16 -o '" +
                      dir.file("a.vdb") + "'");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("vdblight: warning: OBJ material library '" + dir.file("gone.mtl") +
                            "' not found: its materials get the default albedo 0.8"),
              std::string::npos) << r.output;
    EXPECT_NE(r.output.find("no materials: default albedo 0.8"), std::string::npos) << r.output;
    // A texture that does not exist: the diffuse colour is used.
    writeTextFile(dir.file("tex.obj"), "mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Wood\nf 1 2 3\n");
    writeTextFile(dir.file("tex.mtl"), "newmtl Wood\nKd 0.5 0.3 0.1\nmap_Kd missing_wood.png\n");
    r = runCli("bake '" + dir.file("tex.obj") + "' --sky 1,1,1 --resolution 4 --rays 16 -o '" + dir.file("b.vdb") + "'");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("vdblight: warning: 1 diffuse texture(s) not read (first: file '" +
                            dir.file("missing_wood.png") + "' not found): their materials' diffuse colour is the albedo"),
              std::string::npos) << r.output;
}

// ---------------------------------------------------------------------------------------
// End to end: bake an FBX, a COLLADA and an STL file written by Blender, query the volume,
// and check that the scene is 2 m x 0.9 m x 1 m (Blender's 2 x 1 x 0.9, Z up).


TEST(CliFormats, BlenderFilesBakeAndQueryInMetres) {
    if (std::getenv("VDBLIGHT_SKIP_BLENDER")) GTEST_SKIP() << "VDBLIGHT_SKIP_BLENDER is set";
    if (!haveBlender())
        GTEST_SKIP() << "blender not found on PATH: this test bakes files written by Blender 3.4's own exporters "
                        "(scripts/setup.sh installs blender)";
    TempDir dir;
    const std::string error = exportBlenderScene(dir.path().string(), 100.0, false);  // 1 Blender unit = 1 cm
    ASSERT_TRUE(error.empty()) << error;
    struct Case { const char* file; const char* options; const char* format; };
    for (const Case& c : {Case{"scene.fbx", "", "FBX (binary): 3 meshes in 4 instances"},
                          Case{"scene.dae", "", "COLLADA: 3 meshes in 4 instances"},
                          Case{"scene_bin.stl", "--scale 0.01 --up z --sky 0.5,0.5,0.5", "STL (binary): 1 mesh in 1 instance"}}) {
        SCOPED_TRACE(c.file);
        const std::string vdb = dir.file(std::string(c.file) + ".vdb");
        // --spacing 0.1 (m): the nodes are the cell centres of a tiling of the scene's bounds, so
        // 20 x 9 x 10 of them only if the scene is 2 m x 0.9 m x 1 m.
        const CliRun bake = runCli("bake '" + dir.file(c.file) + "' " + c.options +
                                   " --spacing 0.1 --rays 32 -o '" + vdb + "'");
        ASSERT_EQ(bake.status, 0) << bake.output;
        EXPECT_NE(bake.output.find(c.format), std::string::npos) << bake.output;
        EXPECT_NE(bake.output.find("38 triangles"), std::string::npos) << bake.output;
        EXPECT_NE(bake.output.find("(20 x 9 x 10, spacing 0.1)"), std::string::npos) << bake.output;
        const CliRun q = runCli("query '" + vdb + "' --at 0,0.7,0 --normal 0,1,0");
        ASSERT_EQ(q.status, 0) << q.output;
        const double e = firstIrradiance(q.output);
        EXPECT_TRUE(std::isfinite(e) && e > 0) << q.output;
    }
}
