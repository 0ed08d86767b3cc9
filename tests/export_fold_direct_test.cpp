// Exports for SH-only engines fold an occlusion volume's direct light into the SH (fold_direct.h
// in the export module): three.js's grid, decoded as its shader decodes it (trilinear between
// probes, E(n) = sum_j A_l c_j Y_j(n)), gives the query's full answer (SH + exact direct light
// x visibility) up to what SH order 2 cannot hold of a point light's clamped cosine; without
// the fold the error is the whole direct light; volumes with nothing to fold export bit for bit
// as before.
#include <gtest/gtest.h>

#include <random>

#include <nlohmann/json.hpp>

#include "export_file_checks.h"
#include "occlusion_volumes.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/query/query.h"

using namespace vdblight;
using namespace vdblight::test;

namespace {

// The float atlas of a three export and its probe dims (nodes + 2 border probes per axis).
struct ThreeGrid {
    std::vector<float> atlas;
    int dims[3];

    // Coefficient j, channel c of the probe for node (i, j, k) (border probes sit at 0 and n + 1).
    float coefficient(int i, int j, int k, int f) const {
        const int padded = dims[2] + 2, slice = (f / 4) * padded + 1 + (k + 1);
        return atlas[((std::size_t(slice) * dims[1] + (j + 1)) * dims[0] + (i + 1)) * 4 + std::size_t(f % 4)];
    }
    // What LightProbeGridWebGL's shader returns at a point of the node box: the 27 floats
    // interpolated trilinearly between the node probes, then sum_j A_l c_j Y_j(n), Y written out.
    Vec3d irradiance(const GridSpec& g, const Vec3d& x, const Vec3d& n) const {
        double u[3];
        int b[3];
        const int nodes[3] = {g.nx, g.ny, g.nz};
        for (int a = 0; a < 3; ++a) {
            u[a] = (x[a] - g.origin[a]) / g.spacing;
            b[a] = std::min(int(u[a]), nodes[a] - 2);
            u[a] -= b[a];
        }
        double c[27] = {};
        for (int corner = 0; corner < 8; ++corner) {
            const int d[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
            double w = 1;
            for (int a = 0; a < 3; ++a) w *= d[a] ? u[a] : 1 - u[a];
            for (int f = 0; f < 27; ++f) c[f] += w * coefficient(b[0] + d[0], b[1] + d[1], b[2] + d[2], f);
        }
        const double pi = 3.14159265358979323846;
        const double Y[9] = {0.282095,
                             0.488603 * n.y,
                             0.488603 * n.z,
                             0.488603 * n.x,
                             1.092548 * n.x * n.y,
                             1.092548 * n.y * n.z,
                             0.315392 * (3 * n.z * n.z - 1),
                             1.092548 * n.x * n.z,
                             0.546274 * (n.x * n.x - n.y * n.y)};
        const double A[9] = {pi, 2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4, pi / 4, pi / 4, pi / 4, pi / 4};
        Vec3d e(0, 0, 0);
        for (int j = 0; j < 9; ++j)
            for (int ch = 0; ch < 3; ++ch) e[ch] += A[j] * c[3 * j + ch] * Y[j];
        return e;
    }
};

ThreeGrid exportThree(const Volume& v, const std::string& dir) {
    ThreeGridOptions o;
    o.halfFloat = false;
    const ThreeGridSummary s = exportThreeGrid(v, dir, o);
    ThreeGrid g;
    std::copy_n(s.lattice.dims, 3, g.dims);
    const std::vector<uint8_t> b = readFile(dir + "/" + kThreeGridAtlasFile);
    for (std::size_t at = 0; at < b.size(); at += 4) g.atlas.push_back(f32(b, at));
    return g;
}

Volume withoutLights(Volume v) {
    v.direct = DirectLightSet{};
    v.levels[0].lightVisibility.clear();
    return v;
}

std::string readText(const std::string& path) {
    const std::vector<uint8_t> b = readFile(path);
    return std::string(b.begin(), b.end());
}

}  // namespace

// At 4000 random points of the node box with random normals: |three's E - query's E| stays
// within the L2 truncation of the two point lights (3/32 of each one's peak irradiance x
// visibility) plus 1 % of it for the probes' trilinear interpolation of a 1/d^2 field (the
// lights are 2 to 3 m from a 1 m box of 0.25 m spacing), and the squared error summed over
// the samples is under 1.2 % of the direct light's (the clamped cosine beyond band 2 holds
// 0.78 % of its energy for normals spread over the sphere). The same grid without the fold
// (the SH alone) misses the whole direct light: its RMS error is over 8 times the folded one's.
TEST(ExportFoldDirect, ThreeGridGivesTheQueryUpToTheL2TruncationOfItsPointLights) {
    const Volume v = occlusionVolume(41);
    TempDir dir;
    const ThreeGrid folded = exportThree(v, dir.file("folded"));
    const ThreeGrid shOnly = exportThree(withoutLights(v), dir.file("sh"));
    const IrradianceQuery q(v);
    const GridSpec& g = v.levels[0].grid;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    std::normal_distribution<double> gauss;
    double errFolded2 = 0, errShOnly2 = 0, direct2 = 0, worst = 0;
    for (int s = 0; s < 4000; ++s) {
        const Vec3d x = g.origin + Vec3d(u01(rng) * (g.nx - 1), u01(rng) * (g.ny - 1), u01(rng) * (g.nz - 1)) * g.spacing;
        const Vec3d n = normalize(Vec3d(gauss(rng), gauss(rng), gauss(rng)));
        const Rgb want = q.irradianceWorld(x, Vec3f(n));
        const Vec3d got = folded.irradiance(g, x, n), sh = shOnly.irradiance(g, x, n);
        const Vec3d peak = peakDirect(v, x);
        for (int c = 0; c < 3; ++c) {
            const double err = got[c] - want[c], direct = want[c] - sh[c];
            ASSERT_LE(std::fabs(err), (kL2PointLightWorstError + 0.01) * peak[c])
                << "point " << x.x << "," << x.y << "," << x.z << " normal " << n.x << "," << n.y << "," << n.z
                << " channel " << c << ": three " << got[c] << ", query " << want[c];
            worst = std::max(worst, std::fabs(err) / peak[c]);
            errFolded2 += err * err;
            errShOnly2 += direct * direct;
            direct2 += direct * direct;
        }
    }
    const double energy = errFolded2 / direct2, margin = std::sqrt(errShOnly2 / errFolded2);
    std::cout << "[ measured ] worst |error| / (peak irradiance x visibility) " << worst
              << ", squared error / direct light's " << energy << ", RMS error without / with the fold " << margin
              << "\n";
    EXPECT_LT(energy, 0.012);
    EXPECT_GT(margin, 8.0);
}

// The fold is stated in probe_grid.json with the lights it holds; three's shader needs nothing else.
TEST(ExportFoldDirect, ProbeGridJsonNamesTheFoldedLights) {
    const Volume v = occlusionVolume(42);
    TempDir dir;
    const ThreeGridSummary s = exportThreeGrid(v, dir.file("web"), {});
    EXPECT_EQ(s.foldedLights, 2);
    const nlohmann::json direct = nlohmann::json::parse(readText(dir.file("web") + "/" + kThreeGridJsonFile))["direct_light"];
    EXPECT_EQ(direct["folded_into_sh"], true) << direct;
    EXPECT_EQ(direct["lights"], nlohmann::json::array({formatDirectLight(v.direct.lights[0]), formatDirectLight(v.direct.lights[1])}))
        << direct;
    const ThreeGridSummary plain = exportThreeGrid(withoutLights(v), dir.file("plain"), {});
    EXPECT_EQ(plain.foldedLights, 0);
    EXPECT_EQ(readText(dir.file("plain") + "/" + kThreeGridJsonFile).find("direct_light"), std::string::npos);
}

// Nothing to fold, nothing changed: an occlusion volume whose lights are hidden at every node
// exports the same bytes as the volume baked without lights (float and half).
TEST(ExportFoldDirect, NothingToFoldExportsTheSameBits) {
    const Volume hidden = occlusionVolume(43, false);
    TempDir dir;
    for (bool half : {false, true}) {
        ThreeGridOptions o;
        o.halfFloat = half;
        const std::string baked = dir.file(half ? "baked_h" : "baked_f"), folded = dir.file(half ? "hidden_h" : "hidden_f");
        exportThreeGrid(withoutLights(hidden), baked, o);
        EXPECT_EQ(exportThreeGrid(hidden, folded, o).foldedLights, 2);
        EXPECT_EQ(readFile(folded + "/" + kThreeGridAtlasFile), readFile(baked + "/" + kThreeGridAtlasFile)) << half;
    }
}

// A runtime volume's lights need the scene's shadows at run time: still refused, in one line.
TEST(ExportFoldDirect, RuntimeVolumesAreStillRefused) {
    Volume v = withoutLights(occlusionVolume(44));
    v.direct.mode = DirectMode::Runtime;
    v.direct.lights.push_back(DirectLight{});
    TempDir dir;
    try {
        exportThreeGrid(v, dir.file("web"), {});
        ADD_FAILURE() << "not refused";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("--direct runtime"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("web")));
}
