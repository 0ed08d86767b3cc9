// `vdblight export --layout basis` of real-SH volumes (sh:4, sh:3, sh2) end to end, and the
// shader of docs/engine_layouts.md ("Shaders for sh:N") pinned to the library:
// - the doc's table of Y_j polynomials (names, constants, polynomials) parsed from
//   docs/engine_layouts.md equals the library's sh:4 basis at random directions (to 1e-6), its A_l Y_j
//   are the lookup's terms, and the GLSL/HLSL lines use the table's constants and polynomials
//   and skip band 3;
// - exports in raw / ktx2 / dds, half and float, read back by scripts/check_export.py from
//   manifest.json and the doc's polynomials alone (numpy, not the library), match `vdblight
//   query` (the full query: bands 0..4), with the direct light of `--direct occlusion` and the
//   depth-weighted blend of depth moments (the Cornell box's defaults), and without them; the
//   npm package ktx-parse reads and rewrites every KTX2 file byte for byte;
// - negative controls: the script fails on a manifest that claims fewer bands and on swapped
//   band-2 or band-4 textures (swapped band-3 textures pass: A_3 = 0, nobody reads them), and
//   refuses a basis-layout manifest of a basis that is not real SH (export gives bins volumes
//   the bins layout only).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>

#include "cli_baked_suite.h"
#include "export_readers.h"
#include "manifest_util.h"
#include "vdblight/basis/basis.h"

namespace fs = std::filesystem;
using namespace vdblight;
using namespace vdblight::test;

namespace {
std::string readText(const std::string& path) {
    std::ifstream f(path);
    return std::string((std::istreambuf_iterator<char>(f)), {});
}

// What the doc's table must say for Y_j: the polynomial as the table writes it, as the GLSL
// and HLSL write it (empty for bands 0 and 1, checked separately), and its value.
struct DocRow {
    const char* table;
    const char* shader;
    double (*y)(double x, double y, double z);
};
const DocRow kRows[25] = {
    {"", "", [](double, double, double) { return 1.0; }},
    {"y", "", [](double, double y, double) { return y; }},
    {"z", "", [](double, double, double z) { return z; }},
    {"x", "", [](double x, double, double) { return x; }},
    {"x y", "x * y", [](double x, double y, double) { return x * y; }},
    {"y z", "y * z", [](double, double y, double z) { return y * z; }},
    {"(3z² − 1)", "(3.0 * z2 - 1.0)", [](double, double, double z) { return 3 * z * z - 1; }},
    {"x z", "x * z", [](double x, double, double z) { return x * z; }},
    {"(x² − y²)", "(x2 - y2)", [](double x, double y, double) { return x * x - y * y; }},
    {"y (3x² − y²)", "", [](double x, double y, double) { return y * (3 * x * x - y * y); }},
    {"x y z", "", [](double x, double y, double z) { return x * y * z; }},
    {"y (5z² − 1)", "", [](double, double y, double z) { return y * (5 * z * z - 1); }},
    {"z (5z² − 3)", "", [](double, double, double z) { return z * (5 * z * z - 3); }},
    {"x (5z² − 1)", "", [](double x, double, double z) { return x * (5 * z * z - 1); }},
    {"z (x² − y²)", "", [](double x, double y, double z) { return z * (x * x - y * y); }},
    {"x (x² − 3y²)", "", [](double x, double y, double) { return x * (x * x - 3 * y * y); }},
    {"x y (x² − y²)", "x * y * (x2 - y2)", [](double x, double y, double) { return x * y * (x * x - y * y); }},
    {"y z (3x² − y²)", "y * z * (3.0 * x2 - y2)", [](double x, double y, double z) { return y * z * (3 * x * x - y * y); }},
    {"x y (7z² − 1)", "x * y * (7.0 * z2 - 1.0)", [](double x, double y, double z) { return x * y * (7 * z * z - 1); }},
    {"y z (7z² − 3)", "y * z * (7.0 * z2 - 3.0)", [](double, double y, double z) { return y * z * (7 * z * z - 3); }},
    {"(35z⁴ − 30z² + 3)", "(35.0 * z2 * z2 - 30.0 * z2 + 3.0)",
     [](double, double, double z) { return 35 * z * z * z * z - 30 * z * z + 3; }},
    {"x z (7z² − 3)", "x * z * (7.0 * z2 - 3.0)", [](double x, double, double z) { return x * z * (7 * z * z - 3); }},
    {"(x² − y²)(7z² − 1)", "(x2 - y2) * (7.0 * z2 - 1.0)",
     [](double x, double y, double z) { return (x * x - y * y) * (7 * z * z - 1); }},
    {"x z (x² − 3y²)", "x * z * (x2 - 3.0 * y2)", [](double x, double y, double z) { return x * z * (x * x - 3 * y * y); }},
    {"(x⁴ − 6x²y² + y⁴)", "(x2 * x2 - 6.0 * x2 * y2 + y2 * y2)",
     [](double x, double y, double) { return x * x * x * x - 6 * x * x * y * y + y * y * y * y; }},
};

int band(int j) { return int(std::sqrt(double(j)) + 1e-9); }

// One row of the doc's table "| j | `name` | constant polynomial | exact |".
struct TableRow {
    std::string name, constant, polynomial;
};

std::string trim(const std::string& s) {
    const std::size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The 25 rows of the sh:N table in docs/engine_layouts.md, by j.
std::vector<TableRow> docTable(const std::string& doc) {
    std::vector<TableRow> rows(25);
    std::istringstream in(doc);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("| ", 0) != 0 || line.find("| `sh_l") == std::string::npos) continue;
        std::vector<std::string> cells;
        std::istringstream cellStream(line.substr(1));
        for (std::string cell; std::getline(cellStream, cell, '|');) cells.push_back(trim(cell));
        if (cells.size() < 4) continue;
        const int j = std::stoi(cells[0]);
        if (j < 0 || j >= 25) continue;
        const std::string& y = cells[2];
        const std::size_t space = y.find(' ');
        rows[j] = {cells[1], y.substr(0, space), space == std::string::npos ? "" : y.substr(space + 1)};
    }
    return rows;
}

// The fenced code block that contains `signature`.
std::string codeBlockWith(const std::string& doc, const std::string& signature) {
    const std::size_t at = doc.find(signature);
    if (at == std::string::npos) return "";
    const std::size_t begin = doc.rfind("```", at), end = doc.find("```", at);
    return doc.substr(begin, end - begin);
}

class CliExportBasis : public BakedSuite<CliExportBasis> {
public:
    static std::vector<SuiteBake> bakes() {
        // The Cornell box (no scene given) bakes with --direct occlusion and depth moments by default.
        return {{"sh4.vdb", "--resolution 5 --rays 48 --basis sh:4"},
                {"sh4_trilinear.vdb", "--resolution 5 --rays 48 --basis sh:4 --no-depth-moments"},
                {"sh4_baked.vdb", "--resolution 5 --rays 48 --basis sh:4 --direct baked --no-depth-moments"},
                {"sh3.vdb", "--resolution 5 --rays 48 --basis sh:3"},
                {"sh2.vdb", "--resolution 5 --rays 48 --basis sh2"},
                {"bins.vdb", "--resolution 3 --rays 16 --bounces 1 --basis bins:2"}};
    }

protected:
    // `export --layout basis` of `volume` into `where`; false (and a failure) if it fails.
    static bool exportBasis(const std::string& volume, const std::string& where, const std::string& options) {
        std::string log;
        const int status =
            runCommand(cliPath() + " export -q " + file(volume) + " -o " + where + " --layout basis " + options, &log);
        EXPECT_EQ(status, 0) << volume << " " << options << ": " << log;
        return status == 0;
    }
};
}  // namespace

TEST(ExportBasisDoc, ShTableAndShadersOfEngineLayoutsMdAreTheLibrarySh) {
    const std::string doc = readText(sourceDir() + "/docs/engine_layouts.md");
    const std::vector<TableRow> table = docTable(doc);
    const std::unique_ptr<Basis> sh4 = makeBasis("sh:4");
    const double lobe[5] = {kPi, 2 * kPi / 3, kPi / 4, 0.0, -kPi / 24};
    for (int j = 0; j < 25; ++j) {
        ASSERT_EQ(table[j].name, "`" + sh4->desc().channelNames[j] + "`") << "row " << j << " of the sh:N table";
        EXPECT_EQ(table[j].polynomial, kRows[j].table) << "row " << j;
    }
    std::mt19937 rng(11);
    std::normal_distribution<double> gauss;
    for (int k = 0; k < 1000; ++k) {
        Vec3d d(gauss(rng), gauss(rng), gauss(rng));
        d = d / std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        const Vec3f df(float(d.x), float(d.y), float(d.z));
        // Y_j of the library: one sample of unit radiance and weight 1 accumulates Y_j(d).
        std::vector<Rgbd> acc(sh4->accumulatorSize(), Rgbd(0, 0, 0));
        sh4->accumulate(df, Rgbd(1, 1, 1), 1.0, acc.data());
        double docY[25];
        for (int j = 0; j < 25; ++j) {
            docY[j] = std::stod(table[j].constant) * kRows[j].y(df.x, df.y, df.z);
            EXPECT_NEAR(docY[j], acc[j].x, 1e-6) << "Y_" << j << " at " << d.x << "," << d.y << "," << d.z;
        }
        // The lookup's terms: A_l Y_j for every channel but band 3's (A_3 = 0).
        int channels[25];
        float weights[25];
        const int count = sh4->terms(df, channels, weights);
        ASSERT_EQ(count, 18);
        for (int t = 0; t < count; ++t) {
            EXPECT_NE(band(channels[t]), 3);
            EXPECT_NEAR(weights[t], lobe[band(channels[t])] * docY[channels[t]], 1e-6) << "term of channel " << channels[t];
        }
    }
    // The shaders: the table's constants and polynomials, the A_l, band 3 never read.
    const std::string glsl = codeBlockWith(doc, "vec3 vdblightIrradianceShN(");
    const std::string hlsl = codeBlockWith(doc, "float3 VdblightIrradianceShN(");
    ASSERT_FALSE(glsl.empty());
    ASSERT_FALSE(hlsl.empty());
    for (const std::string* code : {&glsl, &hlsl}) {
        const bool isGlsl = code == &glsl;
        auto fetch = [&](int j) {
            return isGlsl ? "texture(L[" + std::to_string(j) + "], uvw).rgb" : "VDBLIGHT_L(" + std::to_string(j) + ")";
        };
        EXPECT_NE(code->find("A0 = PI, A1 = 2.0 * PI / 3.0, A2 = PI / 4.0, A4 = -PI / 24.0;  // A3 = 0"), std::string::npos);
        EXPECT_NE(code->find("A0 * " + table[0].constant + " * " + fetch(0)), std::string::npos);
        EXPECT_NE(code->find("A1 * " + table[1].constant + " * (y * " + fetch(1) + " + z * " + fetch(2) + " + x * " +
                             fetch(3) + ")"),
                  std::string::npos);
        EXPECT_NE(code->find("e += A2 * (" + table[4].constant), std::string::npos);
        EXPECT_NE(code->find("e += A4 * (" + table[16].constant), std::string::npos);
        for (int j = 4; j < 25; ++j) {
            const std::string term = table[j].constant + " * " + kRows[j].shader + " * " + fetch(j);
            if (band(j) == 3)
                EXPECT_EQ(code->find(isGlsl ? "L[" + std::to_string(j) + "]" : "L(" + std::to_string(j) + ")"), std::string::npos)
                    << "band 3 is read: " << j;
            else
                EXPECT_NE(code->find(term), std::string::npos) << (isGlsl ? "GLSL" : "HLSL") << " lacks " << term;
        }
    }
}

TEST_F(CliExportBasis, Sh4RoundTripThroughTheManifestMatchesQuery) {
    TempDir out;
    for (const char* format : {"ktx2", "dds", "raw"})
        for (const char* precision : {"--half", "--float"}) {
            const std::string where = out.file(std::string(format) + precision);
            ASSERT_TRUE(exportBasis("sh4.vdb", where, std::string("--format ") + format + " " + precision));
            EXPECT_TRUE(fs::exists(where + "/sh_l4m_neg3." + format));
            std::string log;
            EXPECT_EQ(checkExport(file("sh4.vdb"), where, &log), 0) << format << " " << precision << ": " << log;
            EXPECT_NE(log.find(std::string(format) + " basis float"), std::string::npos) << log;
            if (std::string(format) == "ktx2") {  // 25 SH + 1 visibility + 3 depth textures
                EXPECT_EQ(checkKtx2(where, &log), 0) << log;
                EXPECT_NE(log.find("pass"), std::string::npos) << log;
            }
        }
    // The default bake: the script adds the listed lights times visibility and blends every
    // texture with the depth-moment weights.
    const nlohmann::json manifest = readManifest(out.file("raw--float"));
    EXPECT_EQ(manifest["layout"], "basis");
    EXPECT_EQ(manifest["basis"], "sh:4");
    EXPECT_EQ(manifest["direct"]["mode"], "occlusion");
    EXPECT_EQ(manifest["direct"]["lights"][0]["visibility"]["texture"], "light_visibility_0_0");
    EXPECT_EQ(manifest["depth"]["exported"], true);
}

TEST_F(CliExportBasis, Sh3Sh2TrilinearAndBakedDirectRoundTrip) {
    TempDir out;
    // Each volume in one format and precision: the formats write the same textures whatever
    // the basis (every format and precision of sh:4 round-trips above), so each case takes the
    // next one (12 exports and checks here were 22 s of CI's ASan suite).
    const struct {
        const char *volume, *basis, *directMode, *options;
    } cases[] = {
        {"sh3.vdb", "sh:3", "occlusion", "--format raw --float"},
        {"sh2.vdb", "sh2", "occlusion", "--format ktx2 --half"},
        {"sh4_trilinear.vdb", "sh:4", "occlusion", "--format dds --half"},
        {"sh4_baked.vdb", "sh:4", "baked", "--format ktx2 --half"},
    };
    int run = 0;
    for (const auto& c : cases) {
        const std::string where = out.file("export" + std::to_string(run++));
        ASSERT_TRUE(exportBasis(c.volume, where, c.options));
        const nlohmann::json manifest = readManifest(where);
        EXPECT_EQ(manifest["basis"], c.basis) << manifest;
        EXPECT_EQ(manifest["direct"]["mode"], c.directMode) << c.volume << ": " << manifest;
        std::string log;
        EXPECT_EQ(checkExport(file(c.volume), where, &log), 0) << c.volume << " " << c.options << ": " << log;
    }
}

TEST_F(CliExportBasis, ScriptFailsOnAWrongManifestOrSwappedTextures) {
    TempDir out;
    auto freshExport = [&](const std::string& name) {
        const std::string where = out.file(name);
        EXPECT_TRUE(exportBasis("sh4_baked.vdb", where, "--format raw --float"));
        return where;
    };
    std::string log;
    // The reference: an untouched export passes.
    const std::string good = freshExport("good");
    ASSERT_EQ(checkExport(file("sh4_baked.vdb"), good, &log), 0) << log;

    // A manifest that claims sh:2: the script drops band 4, which the full query has.
    const std::string truncated = freshExport("truncated");
    nlohmann::json manifest = readManifest(truncated);
    ASSERT_EQ(manifest["basis"], "sh:4") << manifest;
    manifest["basis"] = "sh:2";
    writeManifest(truncated, manifest);
    EXPECT_EQ(checkExport(file("sh4_baked.vdb"), truncated, &log), 1) << log;

    // Two textures of one band swapped (each keeps its name): bands 2 and 4 are read and must
    // match; band 3 adds nothing to irradiance (A_3 = 0), so swapping it changes nothing.
    const struct {
        const char *a, *b;
        int expected;
    } swaps[] = {{"sh_l4m1", "sh_l4m_neg1", 1}, {"sh_l2m1", "sh_l2m_neg1", 1}, {"sh_l3m1", "sh_l3m_neg1", 0}};
    for (const auto& s : swaps) {
        const std::string where = freshExport(std::string("swap_") + s.a);
        const std::string a = where + "/" + s.a + ".raw", b = where + "/" + s.b + ".raw", tmp = where + "/tmp.raw";
        ASSERT_TRUE(fs::exists(a) && fs::exists(b));
        fs::rename(a, tmp);
        fs::rename(b, a);
        fs::rename(tmp, b);
        EXPECT_EQ(checkExport(file("sh4_baked.vdb"), where, &log), s.expected) << s.a << " <-> " << s.b << ": " << log;
    }

    // Other bases: export gives bins:R and moment:n volumes the bins layout only, and the
    // script refuses a basis-layout manifest that is not real SH (exit 2, with the reason).
    expectRefusal("export " + file("bins.vdb") + " -o " + out.file("bins") + " --layout basis", "use --layout bins",
                  out.file("bins"), "bins:2 --layout basis");
    const std::string notSh = freshExport("not_sh");
    manifest = readManifest(notSh);
    manifest["basis"] = "bins:2";
    writeManifest(notSh, manifest);
    EXPECT_EQ(checkExport(file("sh4_baked.vdb"), notSh, &log), 2) << log;
    EXPECT_NE(log.find("layout basis of basis bins:2: not checked"), std::string::npos) << log;
}
