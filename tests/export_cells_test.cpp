// export --cells (export_cells.h): the cells listed in cells.json tile the export lattice
// (neighbours share exactly one texel plane, every texel is in a cell) and every cell texel
// equals the whole-volume export's texel at the same lattice point, byte for byte; a streamed
// volume exports the same cells as the volume in memory.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "bar_scene.h"
#include "cli_util.h"
#include "manifest_util.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/export/export.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

template <typename T>
T at(const std::string& bytes, std::size_t offset) {
    T v;
    std::memcpy(&v, bytes.data() + offset, sizeof v);
    return v;
}

// A KTX2 file's dims and its level-0 texel bytes (header fields per the KTX 2.0 spec).
struct Ktx2 {
    int dims[3];
    std::string texels;
};
Ktx2 readKtx2(const fs::path& p) {
    const std::string b = readFile(p);
    Ktx2 k{{0, 0, 0}, {}};
    EXPECT_GE(b.size(), 104u) << p;
    if (b.size() < 104) return k;
    for (int a = 0; a < 3; ++a) k.dims[a] = int(at<uint32_t>(b, 20 + 4 * a));
    const uint64_t offset = at<uint64_t>(b, 80), length = at<uint64_t>(b, 88);
    EXPECT_LE(offset + length, b.size()) << p;
    if (offset + length > b.size()) return k;
    k.texels = b.substr(offset, length);
    return k;
}

// The cells of cells.json: directory, texel offset and dims.
struct Cell {
    std::string directory;
    int offset[3], dims[3];
};
void readInts(const nlohmann::json& value, int out[3]) {
    for (int a = 0; a < 3; ++a) out[a] = value.at(std::size_t(a)).get<int>();
}
std::vector<Cell> readIndex(const fs::path& dir, int perAxis[3]) {
    const nlohmann::json index = nlohmann::json::parse(readFile(dir / "cells.json"));
    readInts(index.at("cells_per_axis"), perAxis);
    std::vector<Cell> cells;
    for (const nlohmann::json& entry : index.at("cells")) {
        Cell c;
        c.directory = entry.at("directory").get<std::string>();
        readInts(entry.at("texel_offset"), c.offset);
        readInts(entry.at("dims"), c.dims);
        cells.push_back(c);
    }
    return cells;
}

const std::vector<std::string>& textureNames(ExportLayout layout) {
    static const std::vector<std::string> sh2 = {"sh2_sh_l0m0", "sh2_sh_l1m_neg1", "sh2_sh_l1m0", "sh2_sh_l1m1", "sh2_sh_l2m_neg2",
                                                 "sh2_sh_l2m_neg1", "sh2_sh_l2m0", "sh2_sh_l2m1", "sh2_sh_l2m2"};
    static const std::vector<std::string> packed = {"shAr", "shAg", "shAb", "shBr", "shBg", "shBb", "shC"};
    static const std::vector<std::string> sh1 = {"shAr", "shAg", "shAb"};
    return layout == ExportLayout::Sh2 ? sh2 : layout == ExportLayout::Sh1 ? sh1 : packed;
}

// A texture name and its texel size in the export (depth textures are RGBA8 in ktx2).
using Texture = std::pair<std::string, std::size_t>;

// Every cell texel equals the whole export's texel at the same lattice point; the cells
// cover the lattice, overlapping only in shared boundary planes.
void expectCellsMatchWhole(const fs::path& whole, const fs::path& cellsDir, const std::vector<Texture>& textures, int k) {
    int perAxis[3];
    const std::vector<Cell> cells = readIndex(cellsDir, perAxis);
    ASSERT_EQ(cells.size(), std::size_t(perAxis[0]) * perAxis[1] * perAxis[2]);
    std::size_t dirs = 0;
    for (const auto& e : fs::directory_iterator(cellsDir)) dirs += e.is_directory();
    EXPECT_EQ(dirs, cells.size());
    for (const auto& [name, texelBytes] : textures) {
        ASSERT_TRUE(fs::exists(whole / (name + ".ktx2"))) << name;
        const Ktx2 w = readKtx2(whole / (name + ".ktx2"));
        std::vector<int> covered(std::size_t(w.dims[0]) * w.dims[1] * w.dims[2], 0);
        for (const Cell& c : cells) {
            const Ktx2 t = readKtx2(cellsDir / c.directory / (name + ".ktx2"));
            for (int a = 0; a < 3; ++a) {
                ASSERT_EQ(t.dims[a], c.dims[a]) << c.directory;
                EXPECT_EQ(c.offset[a] % k, 0) << c.directory;
                // Interior cells span k steps; the last one ends on the lattice's last texel.
                const int end = c.offset[a] + c.dims[a] - 1;
                EXPECT_TRUE(end == c.offset[a] + k || (end == w.dims[a] - 1 && c.dims[a] <= k + 1)) << c.directory;
            }
            for (int z = 0; z < t.dims[2]; ++z)
                for (int y = 0; y < t.dims[1]; ++y)
                    for (int x = 0; x < t.dims[0]; ++x) {
                        const std::size_t wi =
                            (std::size_t(c.offset[2] + z) * w.dims[1] + (c.offset[1] + y)) * w.dims[0] + (c.offset[0] + x);
                        const std::size_t ti = (std::size_t(z) * t.dims[1] + y) * t.dims[0] + x;
                        ASSERT_EQ(t.texels.compare(ti * texelBytes, texelBytes, w.texels, wi * texelBytes, texelBytes), 0)
                            << name << " " << c.directory << " texel " << x << "," << y << "," << z;
                        ++covered[wi];
                    }
        }
        // Each texel lies in 2^(number of axes on which it is a shared cell boundary) cells.
        for (int z = 0; z < w.dims[2]; ++z)
            for (int y = 0; y < w.dims[1]; ++y)
                for (int x = 0; x < w.dims[0]; ++x) {
                    const int xyz[3] = {x, y, z};
                    int expect = 1;
                    for (int a = 0; a < 3; ++a)
                        if (xyz[a] % k == 0 && xyz[a] > 0 && xyz[a] < w.dims[a] - 1) expect *= 2;
                    ASSERT_EQ(covered[(std::size_t(z) * w.dims[1] + y) * w.dims[0] + x], expect) << x << "," << y << "," << z;
                }
    }
}

void expectCellsMatchWhole(const fs::path& whole, const fs::path& cellsDir, ExportLayout layout, int k,
                           std::size_t texelBytes) {
    std::vector<Texture> textures;
    for (const std::string& name : textureNames(layout)) textures.emplace_back(name, texelBytes);
    expectCellsMatchWhole(whole, cellsDir, textures, k);
}

// Every file of two cell exports is the same, but for the lookup kind their manifests name.
void expectSameFiles(const fs::path& a, const fs::path& b, std::size_t count) {
    std::size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(a)) {
        if (!e.is_regular_file()) continue;
        std::string x = readFile(e.path()), y = readFile(b / fs::relative(e.path(), a));
        if (e.path().filename() == "manifest.json" || e.path().filename() == "cells.json")
            for (std::string* s : {&x, &y}) {
                const std::size_t p = s->find("\"volume_kind\"");
                s->erase(p, s->find('\n', p) - p);
            }
        EXPECT_EQ(x, y) << e.path();
        ++files;
    }
    EXPECT_EQ(files, count);
}

}  // namespace

TEST(ExportCells, CellsTileTheLatticeAndEqualTheWholeExport) {
    const Volume v = test::randomShVolume(13, 9, 7, 0.1, 21);
    for (ExportLayout layout : {ExportLayout::Sh2Packed, ExportLayout::Sh2, ExportLayout::Sh1})
        for (bool half : {true, false}) {
            test::TempDir dir;
            ExportOptions o;
            o.layout = layout;
            o.halfFloat = half;
            exportTextures(v, dir.file("whole"), o);
            for (int k : {4, 5, 12, 40}) {
                const std::string out = dir.file("cells" + std::to_string(k));
                const CellsSummary s = exportCells(IrradianceQuery(v), v, out, o, k);
                EXPECT_EQ(s.cells[0], (13 - 2) / k + 1);
                expectCellsMatchWhole(dir.file("whole"), out, layout, k, half ? 8 : 16);
            }
        }
}

TEST(ExportCells, AdaptiveLevelsToo) {
    const Volume v = test::randomLevelsVolume(LayoutKind::Adaptive, 3, BasisDesc::sh2(), 6, -0.5f, 1.5f);
    test::TempDir dir;
    ExportOptions o;
    exportTextures(v, dir.file("whole"), o);
    exportCells(IrradianceQuery(v), v, dir.file("cells"), o, 6);
    expectCellsMatchWhole(dir.file("whole"), dir.file("cells"), ExportLayout::Sh2Packed, 6, 8);
}

TEST(ExportCells, StreamedVolumeExportsTheSameFiles) {
    test::TempDir dir;
    writeVolume(test::randomShVolume(21, 6, 10, 0.3, 5), dir.file("v.vdb"));
    const Volume v = readVolume(dir.file("v.vdb"));
    ExportOptions o;
    exportCells(IrradianceQuery(v), v, dir.file("memory"), o, 8);
    auto streamed = std::make_shared<StreamedVolume>(dir.file("v.vdb"));
    exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, dir.file("streamed"), o, 8);
    expectSameFiles(dir.file("memory"), dir.file("streamed"), 3u * 1u * 2u * 8u + 1u);  // 6 cells x (7 textures + manifest) + cells.json
}

// The default bake's kind (sh:4, depth moments, --direct occlusion with five lights: two
// visibility textures): the cells, read in memory or streamed, reassemble into the whole
// export's layout, visibility and depth textures; the basis layout (all 25 coefficients) too.
TEST(ExportCells, DefaultKindCellsCarryVisibilityAndDepth) {
    Volume v = test::randomUniformVolume(makeBasis("sh:4")->desc(), 11, 9, 7, 0.2, 31);
    test::randomDepth(v, 32);
    for (float& f : v.levels[0].data) f = 0.5f * f + 0.2f;
    v.direct.mode = DirectMode::Occlusion;
    Rng rng(33);
    for (int l = 0; l < 5; ++l) {
        DirectLight light;
        light.position = v.levels[0].grid.origin + Vec3d(0.3 * l, 2.5, 0.5);
        light.value = Rgb(1.0f, 1.0f, 1.0f);
        v.direct.lights.push_back(light);
    }
    v.levels[0].lightVisibility.resize(v.levels[0].grid.nodeCount() * 5);
    for (float& f : v.levels[0].lightVisibility) f = rng.uniform();
    test::TempDir dir;
    writeVolume(v, dir.file("v.vdb"));
    const Volume read = readVolume(dir.file("v.vdb"));
    std::vector<Texture> extra = {{"light_visibility_0_3", 8}, {"light_visibility_4_4", 8},
                                  {"depth_x", 4}, {"depth_y", 4}, {"depth_z", 4}};
    for (ExportLayout layout : {ExportLayout::Sh2Packed, ExportLayout::Basis}) {
        ExportOptions o;
        o.layout = layout;
        exportTextures(read, dir.file("whole"), o);
        std::vector<Texture> textures = extra;
        if (layout == ExportLayout::Basis)
            for (const BasisTexture& t : makeBasis("sh:4")->textures()) textures.emplace_back(t.name, 8);
        else
            for (const std::string& name : textureNames(layout)) textures.emplace_back(name, 8);
        exportCells(IrradianceQuery(read), read, dir.file("memory"), o, 6);
        expectCellsMatchWhole(dir.file("whole"), dir.file("memory"), textures, 6);
        // Streamed, with the leaves dropped after every cell (leafMemory 1 byte).
        auto streamed = std::make_shared<StreamedVolume>(dir.file("v.vdb"));
        exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, dir.file("streamed"), o, 6, 1);
        expectSameFiles(dir.file("memory"), dir.file("streamed"), 2u * 2u * 1u * (textures.size() + 1) + 1u);
        const nlohmann::json manifest = test::readManifest(dir.file("memory") + "/cell_0_0_0");
        bool visibility44 = false;
        for (const nlohmann::json& t : manifest["textures"]) visibility44 |= t["name"] == "light_visibility_4_4";
        EXPECT_TRUE(visibility44) << manifest;
        EXPECT_EQ(manifest["depth"]["exported"], true) << manifest;
        for (const char* d : {"whole", "memory", "streamed"}) fs::remove_all(dir.file(d));
    }
    // A volume's header alone (no node values) is refused, not exported without depth.
    auto streamed = std::make_shared<StreamedVolume>(dir.file("v.vdb"));
    EXPECT_THROW(exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), streamed->header(), dir.file("h"),
                             ExportOptions{}, 4),
                 ValueError);
    EXPECT_FALSE(fs::exists(dir.file("h")));
}

// Adaptive levels of sh:4 with depth moments: the depth textures lie on the finest lattice,
// free where the finest level stores no node; cells equal the whole export there too.
TEST(ExportCells, AdaptiveDepthTexturesOnTheFinestLattice) {
    Volume v = test::randomLevelsVolume(LayoutKind::Adaptive, 3, makeBasis("sh:4")->desc(), 7, -0.2f, 1.0f);
    test::randomDepth(v, 8);
    test::TempDir dir;
    writeVolume(v, dir.file("v.vdb"));
    const Volume read = readVolume(dir.file("v.vdb"));
    ExportOptions o;
    exportTextures(read, dir.file("whole"), o);
    std::vector<Texture> textures = {{"depth_x", 4}, {"depth_y", 4}, {"depth_z", 4}};
    for (const std::string& name : textureNames(ExportLayout::Sh2Packed)) textures.emplace_back(name, 8);
    exportCells(IrradianceQuery(read), read, dir.file("memory"), o, 8);
    expectCellsMatchWhole(dir.file("whole"), dir.file("memory"), textures, 8);
    auto streamed = std::make_shared<StreamedVolume>(dir.file("v.vdb"));
    exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, dir.file("streamed"), o, 8);
    std::size_t cells = 0;
    for (const auto& e : fs::directory_iterator(dir.file("memory"))) cells += e.is_directory();
    expectSameFiles(dir.file("memory"), dir.file("streamed"), cells * (textures.size() + 1) + 1u);
}

// The default bake (--direct occlusion, depth moments) of a light whose shadow is a strip
// narrower than a cell (bar_scene.h): every cell holds the whole export's shadow-edge and strip
// textures over its region, texel for texel, lists them in the same textures and "direct"
// entries of its manifest, in each layout --cells takes, half or float, and streamed too.
TEST(ExportCells, ShadowEdgesAndStripsInEveryCell) {
    test::TempDir dir;
    const std::string vdb = dir.file("v.vdb");
    ASSERT_EQ(test::runCli("bake -q -o " + vdb + " --bounds -0.5,0,-0.5,0.5,0.4,0.5 --resolution 9 --rays 16 --bounces 1 "
                           "--depth-moments --direct occlusion " + test::barScene(dir)).status, 0);
    const Volume read = readVolume(vdb);
    const std::vector<std::string> edges = {"light_edge_distance_0_0", "light_edge_width_0_0", "light_edge_ramp_0_0",
                                            "light_edge_strip_0"};
    for (const auto& [layout, half] : {std::pair{ExportLayout::Sh2Packed, true}, std::pair{ExportLayout::Sh2, false},
                                       std::pair{ExportLayout::Sh1, true}, std::pair{ExportLayout::Basis, true}}) {
        SCOPED_TRACE(layoutName(layout) + std::string(half ? " half" : " float"));
        ExportOptions o;
        o.layout = layout;
        o.halfFloat = half;
        exportTextures(read, dir.file("whole"), o);
        const nlohmann::json whole = test::readManifest(dir.file("whole"));
        // The bake made a strip, so the whole export has the four edge textures of its light.
        ASSERT_EQ(whole["direct"]["shadow_edges"]["strips"]["textures"], nlohmann::json({"light_edge_strip_0"})) << whole;
        ASSERT_EQ(whole["direct"]["shadow_edges"]["textures"], nlohmann::json(edges)) << whole;
        std::vector<Texture> textures;
        for (const std::string& name : edges) textures.emplace_back(name, half ? 8 : 16);
        exportCells(IrradianceQuery(read), read, dir.file("memory"), o, 4);
        expectCellsMatchWhole(dir.file("whole"), dir.file("memory"), textures, 4);
        std::size_t cells = 0;
        for (const auto& e : fs::directory_iterator(dir.file("memory"))) {
            if (!e.is_directory()) continue;
            const nlohmann::json manifest = test::readManifest(e.path().string());
            EXPECT_EQ(manifest["textures"], whole["textures"]) << e.path();  // names, order, formats
            EXPECT_EQ(manifest["direct"], whole["direct"]) << e.path();
            ++cells;
        }
        int perAxis[3];
        EXPECT_EQ(cells, readIndex(dir.file("memory"), perAxis).size());
        EXPECT_GT(cells, 1u);
        // Streamed, with the leaves dropped after every cell: the same files (one layout: the
        // edges do not depend on it, and each file written costs an fsync).
        if (layout == ExportLayout::Sh2Packed) {
            auto streamed = std::make_shared<StreamedVolume>(vdb);
            exportCells(makeStreamingQuery(streamed, OutsidePolicy::Clamp), *streamed, dir.file("streamed"), o, 4, 1);
            expectSameFiles(dir.file("memory"), dir.file("streamed"), cells * (whole["textures"].size() + 1) + 1u);
        }
        for (const char* d : {"whole", "memory", "streamed"}) fs::remove_all(dir.file(d));
    }
}

TEST(ExportCells, RefusesWhatCellsDoNotCarryAndLeavesNothing) {
    test::TempDir dir;
    const Volume v = test::randomShVolume(5, 5, 5, 0.1, 1);
    ExportOptions o;
    o.layout = ExportLayout::Vectors;
    EXPECT_THROW(exportCells(IrradianceQuery(v), v, dir.file("a"), o, 2), FormatError);
    o.layout = ExportLayout::Sh2Packed;
    EXPECT_THROW(exportCells(IrradianceQuery(v), v, dir.file("b"), o, 0), ValueError);
    Volume big = v;
    for (float& f : big.levels[0].data) f = 1e6f;  // beyond half floats
    EXPECT_THROW(exportCells(IrradianceQuery(big), big, dir.file("c"), o, 2), ValueError);
    EXPECT_FALSE(fs::exists(dir.file("a")));
    EXPECT_FALSE(fs::exists(dir.file("b")));
    EXPECT_FALSE(fs::exists(dir.file("c")));
}

TEST(ExportCells, CommandLine) {
    test::TempDir dir;
    writeVolume(test::randomShVolume(9, 9, 9, 0.2, 3), dir.file("v.vdb"));
    const test::CliRun r = test::runCli("export " + dir.file("v.vdb") + " -o " + dir.file("cells") + " --cells 4");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("2 x 2 x 2 cells"), std::string::npos) << r.output;
    ASSERT_EQ(test::runCli("export " + dir.file("v.vdb") + " -o " + dir.file("whole")).status, 0);
    expectCellsMatchWhole(dir.file("whole"), dir.file("cells"), ExportLayout::Sh2Packed, 4, 8);
    test::expectCleanFailure(dir, "export " + dir.file("v.vdb") + " -o " + dir.file("x") + " --cells 4 --layout vectors",
                             "SH layouts");
}
