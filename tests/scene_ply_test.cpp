// Tests of vdblight's own PLY reader (scene/load_ply.cpp, through loadScene): the three
// encodings give the same scene, polygons are fan-triangulated, unknown properties and
// elements are skipped in any order, and every malformed file (truncated, counts larger than
// the file, bad indices, bad header lines, unknown format, and every truncation and byte
// corruption of the fuzz seeds) ends in a SceneError naming the file, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

using namespace vdblight;
using vdblight::test::TempDir;
using vdblight::test::writeTextFile;

namespace {

const std::string kSource = VDBLIGHT_SOURCE_DIR;

enum class Enc { Ascii, Little, Big };

/// Writes PLY records: text tokens for ascii, bytes in the chosen order for binary.
class PlyBody {
public:
    explicit PlyBody(Enc enc) : enc_(enc) {}
    template <typename T> PlyBody& put(T v) {
        if (enc_ == Enc::Ascii) {
            if (!text_.empty() && text_.back() != '\n') text_ += ' ';
            if constexpr (std::is_floating_point_v<T>) text_ += std::to_string(v);
            else text_ += std::to_string(int64_t(v));
            return *this;
        }
        unsigned char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));  // the test machine is little-endian (x86-64)
        if (enc_ == Enc::Big) std::reverse(b, b + sizeof(T));
        text_.append(reinterpret_cast<const char*>(b), sizeof(T));
        return *this;
    }
    PlyBody& end() { if (enc_ == Enc::Ascii) text_ += '\n'; return *this; }
    const std::string& str() const { return text_; }

private:
    Enc enc_;
    std::string text_;
};

const char* formatName(Enc e) {
    return e == Enc::Ascii ? "ascii" : e == Enc::Little ? "binary_little_endian" : "binary_big_endian";
}

/// A pyramid (square base as one quad, four triangular sides) with extra vertex properties,
/// an extra face property on each side of the index list, and two extra elements (one with
/// a list) placed before, between and after the ones read; face before vertex.
std::string pyramidPly(Enc enc) {
    std::string h = std::string("ply\nformat ") + formatName(enc) + " 1.0\ncomment any order\n"
                    "element edge 2\nproperty int vertex1\nproperty list ushort short corners\n"
                    "element face 5\nproperty list uchar float texcoord\nproperty list uchar int vertex_indices\n"
                    "property uint flags\n"
                    "element vertex 5\nproperty double nx\nproperty float x\nproperty uchar red\n"
                    "property short y\nproperty double z\nproperty char alpha\n"
                    "element material 1\nproperty float shine\nend_header\n";
    PlyBody b(enc);
    b.put<int32_t>(7).put<uint16_t>(3).put<int16_t>(1).put<int16_t>(2).put<int16_t>(3).end();
    b.put<int32_t>(8).put<uint16_t>(0).end();
    const std::vector<std::vector<int32_t>> faces = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
    for (const auto& f : faces) {
        b.put<uint8_t>(2).put<float>(0.5f).put<float>(0.25f).put<uint8_t>(uint8_t(f.size()));
        for (int32_t i : f) b.put<int32_t>(i);
        b.put<uint32_t>(42).end();
    }
    const int xyz[5][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 2, 0}};
    for (const auto& v : xyz)
        b.put<double>(0.125).put<float>(float(v[0])).put<uint8_t>(200).put<int16_t>(int16_t(v[1]))
            .put<double>(double(v[2])).put<int8_t>(-3).end();
    b.put<float>(1.5f).end();
    return h + b.str();
}

void writeBinaryFile(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::vector<uint32_t> triangles(const Scene& s) { return s.indices; }

/// loadScene(path) must throw SceneError naming the file and containing `fragment`.
void expectPlyError(const std::string& path, const std::string& fragment) {
    try {
        const Scene s = loadScene(path);
        ADD_FAILURE() << path << " loaded with " << s.triangleCount() << " triangles";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Loads or throws SceneError (with the file named); anything else fails the test.
void expectLoadsOrSceneError(const std::string& path, const std::string& label) {
    try {
        const Scene s = loadScene(path);
        validateScene(s);
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << label << ": " << e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << label << ": unexpected exception " << e.what();
    }
}

}  // namespace

TEST(PlyReader, AsciiAndBothBinaryEndiannessesGiveTheSameScene) {
    TempDir dir;
    std::vector<Scene> scenes;
    for (Enc e : {Enc::Ascii, Enc::Little, Enc::Big}) {
        const std::string path = dir.file(std::string("pyramid_") + formatName(e) + ".ply");
        writeBinaryFile(path, pyramidPly(e));
        scenes.push_back(loadScene(path));
    }
    const Scene& a = scenes[0];
    // Exact answer: the five declared vertices, the quad fanned from its corner 0, the sides.
    const std::vector<Vec3f> positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 2, 0}};
    const std::vector<uint32_t> indices = {0, 3, 2, 0, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    ASSERT_EQ(a.positions.size(), positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        EXPECT_EQ(a.positions[i].x, positions[i].x);
        EXPECT_EQ(a.positions[i].y, positions[i].y);
        EXPECT_EQ(a.positions[i].z, positions[i].z);
    }
    EXPECT_EQ(triangles(a), indices);
    ASSERT_EQ(a.materials.size(), 1u);
    EXPECT_EQ(a.materials[0].name, "default");
    EXPECT_FLOAT_EQ(a.materials[0].albedo.x, 0.8f);
    EXPECT_EQ(a.materialIds, std::vector<uint32_t>(6, 0u));
    EXPECT_EQ(a.stats.inputTriangles, 6u);
    for (std::size_t k = 1; k < scenes.size(); ++k) {
        EXPECT_EQ(scenes[k].contentHash(), a.contentHash()) << formatName(Enc(k));
        EXPECT_EQ(triangles(scenes[k]), indices);
    }
}

TEST(PlyReader, PolygonsAreFanTriangulated) {
    TempDir dir;
    // A convex pentagon in the z = 0 plane, and a concave quad ("arrowhead") whose reflex
    // corner is its corner 3: the fan must start there to stay inside the quad.
    writeTextFile(dir.file("polys.ply"),
                  "ply\nformat ascii 1.0\nelement vertex 9\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 2\nproperty list uchar uint vertex_index\nend_header\n"
                  "0 0 0\n2 0 0\n3 1 0\n1 2 0\n-1 1 0\n"
                  "0 0 1\n4 0 1\n0 4 1\n1 1 1\n"
                  "5 0 1 2 3 4\n4 5 6 7 8\n");
    const Scene s = loadScene(dir.file("polys.ply"));
    EXPECT_EQ(triangles(s), (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 3, 4, 8, 5, 6, 8, 6, 7}));
    // Both triangles of the concave quad keep its winding (a fan from corner 0 would give one
    // flipped triangle outside the quad) and together cover its area exactly.
    double area = 0;
    for (std::size_t t = 3; t < 5; ++t) {
        const Vec3f e1 = s.vertex(t, 1) - s.vertex(t, 0), e2 = s.vertex(t, 2) - s.vertex(t, 0);
        EXPECT_GT(cross(e1, e2).z, 0.0f) << "triangle " << t;
        area += 0.5 * double(cross(e1, e2).z);
    }
    EXPECT_DOUBLE_EQ(area, 6.0);  // shoelace area of (0,0) (4,0) (0,4) (1,1)
}

TEST(PlyReader, FacesWithFewerThanThreeCornersAreIgnored) {
    TempDir dir;
    writeTextFile(dir.file("mixed.ply"),
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                  "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
                  "0 0 0\n1 0 0\n0 1 0\n1 0\n2 0 1\n3 0 1 2\n");
    const Scene s = loadScene(dir.file("mixed.ply"));
    EXPECT_EQ(triangles(s), (std::vector<uint32_t>{0, 1, 2}));
}

TEST(PlyReader, MalformedFilesAreSceneErrors) {
    TempDir dir;
    const std::string vertexHeader =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    struct Case { const char* name; std::string text; const char* fragment; };
    const std::string binHeader =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    std::string fullBinary = binHeader;
    {
        PlyBody b(Enc::Little);
        for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put<float>(v);
        b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
        fullBinary += b.str();
    }
    const std::vector<Case> cases = {
        {"truncated_ascii.ply", vertexHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1", "file ends early"},
        {"truncated_binary.ply", fullBinary.substr(0, fullBinary.size() - 3), "list length 3 exceeds"},
        {"truncated_vertices.ply", fullBinary.substr(0, binHeader.size() + 20), "more than the"},
        {"huge_count.ply",
         "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n" + std::string(64, '\0'),
         "declares 4000000000 records"},
        {"huge_ascii_count.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 999999999999\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "declares 999999999999 records"},
        {"huge_list.ply", binHeader + fullBinary.substr(binHeader.size(), 36) + std::string("\xff\0\0\0\0", 5),
         "list length 255 exceeds"},
        {"huge_skipped_list.ply",
         "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
         "element junk 1\nproperty list uint double data\nend_header\n"
         "\x7f\xff\xff\xff" + std::string(16, '\0'),
         "list length 2147483647 exceeds"},
        {"negative_list.ply", vertexHeader + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", "negative list length"},
        {"index_too_big.ply", vertexHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "vertex index 3 out of range (3 vertices)"},
        {"index_negative.ply", vertexHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "vertex index -1 out of range"},
        {"not_a_number.ply", vertexHeader + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "'zero' is not a number"},
        {"not_an_integer.ply", vertexHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "'1.5' is not an integer"},
        {"nan.ply", vertexHeader + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "vertex 1 has a non-finite coordinate"},
        {"beyond_float.ply", vertexHeader + "0 0 0\n1 0 0\n0 1e300 0\n3 0 1 2\n", "vertex 2 has a non-finite coordinate"},
        {"unknown_format.ply", "ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n",
         "unknown format 'binary_middle_endian'"},
        {"format_version.ply", "ply\nformat ascii 2.0\nend_header\n", "unsupported format version '2.0'"},
        {"no_format.ply", "ply\nelement vertex 0\nend_header\n", "no 'format' line"},
        {"not_ply.ply", "plyx\nformat ascii 1.0\nend_header\n", "not a PLY file"},
        {"bad_keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n", "bad header line 3: unknown keyword 'elemnt'"},
        {"bad_count.ply", "ply\nformat ascii 1.0\nelement vertex 12abc\nend_header\n", "bad element count '12abc'"},
        {"property_first.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "property before any element"},
        {"bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "unknown type"},
        {"float_count.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
         "list count type must be an integer type"},
        {"float_index.ply",
         vertexHeader.substr(0, vertexHeader.find("element face")) +
             "element face 1\nproperty list uchar float vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "non-integer item type"},
        {"no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 0\n", "no 'end_header' line"},
        {"no_vertex.ply", "ply\nformat ascii 1.0\nend_header\n", "no 'vertex' element"},
        {"no_z.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
         "lacks an x, y or z property"},
        {"list_x.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nend_header\n1 0\n",
         "vertex property 'x' is a list"},
        {"two_vertex_elements.ply", "ply\nformat ascii 1.0\nelement vertex 0\nelement vertex 0\nend_header\n",
         "element 'vertex' declared twice"},
        {"long_header.ply", "ply\nformat ascii 1.0\n" + std::string(std::size_t(1) << 21, ' ') + "\nend_header\n",
         "header longer than 1 MiB"},
        {"no_faces.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n0 0 0\n",
         "has no triangles"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        writeBinaryFile(dir.file(c.name), c.text);
        expectPlyError(dir.file(c.name), c.fragment);
    }
}

TEST(PlyReader, CorpusSeedsAndEveryTruncationAndCorruptionLoadOrThrow) {
    TempDir dir;
    const std::filesystem::path corpus = kSource + "/tests/fuzz/corpus/fuzz_scene_ply";
    std::vector<std::filesystem::path> seeds;
    for (const auto& entry : std::filesystem::directory_iterator(corpus)) seeds.push_back(entry.path());
    std::sort(seeds.begin(), seeds.end());
    ASSERT_GE(seeds.size(), 3u);
    const std::string path = dir.file("mutant.ply");
    for (const auto& seed : seeds) {
        const std::string bytes = readFile(seed.string());
        expectLoadsOrSceneError(seed.string(), seed.filename().string());
        EXPECT_GT(loadScene(seed.string()).triangleCount(), 0u) << seed;  // the seeds are valid
        // Every prefix, and every byte replaced by 0xff, '9', '-' and NUL.
        for (std::size_t n = 0; n < bytes.size(); ++n) {
            writeBinaryFile(path, bytes.substr(0, n));
            expectLoadsOrSceneError(path, seed.filename().string() + " cut at " + std::to_string(n));
            for (char c : {'\xff', '9', '-', '\0'}) {
                std::string m = bytes;
                m[n] = c;
                writeBinaryFile(path, m);
                expectLoadsOrSceneError(path, seed.filename().string() + " byte " + std::to_string(n));
            }
        }
    }
}
