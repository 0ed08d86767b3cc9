// Folding an occlusion volume's direct light into the exported SH (fold_direct.h).
#include "fold_direct.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>

#include "vdblight/core/errors.h"
#include "query/query_direct.h"  // OcclusionLookup, and DirectLight / formatDirectLight through it
#include "basis/sh.h"

namespace vdblight::exporter {

namespace {

// The fit, computed once: the normals and the 9 x N matrix taking the N irradiance values to
// radiance coefficients, F = diag(1 / A_l) (Y^T Y)^-1 Y^T with Y_ij = Y_j(n_i).
struct FoldFit {
    std::array<Vec3f, kFoldNormals> normals;
    double rows[sh::kCoeffs][kFoldNormals];

    FoldFit() {
        // Spherical Fibonacci: equal-area bands in z, golden-angle steps in phi. Fixed, so
        // every export folds with the same bits.
        const double golden = kPi * (3.0 - std::sqrt(5.0));
        double Y[kFoldNormals][sh::kCoeffs];
        for (int i = 0; i < kFoldNormals; ++i) {
            const double z = 1.0 - (2.0 * i + 1.0) / kFoldNormals, r = std::sqrt(1.0 - z * z), phi = golden * i;
            normals[std::size_t(i)] = Vec3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
            // The lookup normalises the float normal in double (OcclusionLookup::direct): fit at that one.
            sh::evalGeneric(2, normalize(Vec3d(normals[std::size_t(i)])), Y[i]);
        }
        // Normal equations M = Y^T Y (9 x 9, well conditioned for 128 spread normals), solved
        // by Cholesky for every column of Y^T.
        double M[sh::kCoeffs][sh::kCoeffs] = {};
        for (int i = 0; i < kFoldNormals; ++i)
            for (int a = 0; a < sh::kCoeffs; ++a)
                for (int b = 0; b < sh::kCoeffs; ++b) M[a][b] += Y[i][a] * Y[i][b];
        double L[sh::kCoeffs][sh::kCoeffs] = {};
        for (int a = 0; a < sh::kCoeffs; ++a)
            for (int b = 0; b <= a; ++b) {
                double s = M[a][b];
                for (int k = 0; k < b; ++k) s -= L[a][k] * L[b][k];
                L[a][b] = a == b ? std::sqrt(s) : s / L[b][b];
            }
        for (int i = 0; i < kFoldNormals; ++i) {
            double y[sh::kCoeffs];
            for (int a = 0; a < sh::kCoeffs; ++a) {  // L y = Y_i
                double s = Y[i][a];
                for (int k = 0; k < a; ++k) s -= L[a][k] * y[k];
                y[a] = s / L[a][a];
            }
            for (int a = sh::kCoeffs - 1; a >= 0; --a) {  // L^T c = y
                double s = y[a];
                for (int k = a + 1; k < sh::kCoeffs; ++k) s -= L[k][a] * rows[k][i];
                rows[a][i] = s / L[a][a];
            }
            for (int a = 0; a < sh::kCoeffs; ++a) rows[a][i] /= sh::kCosineLobe[sh::bandOf(a)];
        }
    }
};

const FoldFit& fit() {
    static const FoldFit f;
    return f;
}

const OcclusionLookup& occlusionOf(const IrradianceQuery& query) {
    const auto* occlusion = dynamic_cast<const OcclusionLookup*>(&query.lookup());
    if (!occlusion) throw FormatError("folding direct light: the volume's lookup reads no light visibility");
    return *occlusion;
}

}  // namespace

Vec3f foldNormal(int i) { return fit().normals.at(std::size_t(i)); }

void foldedDirectRadiance(const IrradianceQuery& query, const Vec3d& x, Rgb out[9]) {
    const OcclusionLookup& occlusion = occlusionOf(query);
    const FoldFit& f = fit();
    double sum[sh::kCoeffs][3] = {};
    for (int i = 0; i < kFoldNormals; ++i) {
        const Rgb e = occlusion.direct(x, f.normals[std::size_t(i)]);
        if (e == Rgb(0, 0, 0)) continue;  // half the normals face away from every light
        for (int j = 0; j < sh::kCoeffs; ++j)
            for (int c = 0; c < 3; ++c) sum[j][c] += f.rows[j][i] * double(e[c]);
    }
    for (int j = 0; j < sh::kCoeffs; ++j) out[j] = Rgb(float(sum[j][0]), float(sum[j][1]), float(sum[j][2]));
}

bool foldsDirectLight(const Volume& volume) { return volume.direct.hasVisibility(); }

void addFoldedDirectLight(const Volume& volume, const IrradianceQuery& query, const TextureLattice& lattice,
                          ExportLayout layout, std::vector<std::vector<float>>& textures) {
    if (!foldsDirectLight(volume)) return;
    if (layout != ExportLayout::Sh2 && layout != ExportLayout::Sh2Packed)
        throw ValueError("direct light folds only into the sh2 and sh2-packed layouts");
    occlusionOf(query);  // FormatError before any work
    const std::size_t floats = textures.size() * 4;
    const int nx = lattice.dims[0], ny = lattice.dims[1];
    tbb::parallel_for(tbb::blocked_range<int>(0, lattice.dims[2]), [&](const tbb::blocked_range<int>& r) {
        Rgb L[9];
        std::vector<float> texel(floats);
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    foldedDirectRadiance(query, lattice.point(i, j, k), L);
                    bool any = false;
                    for (const Rgb& c : L) any = any || c != Rgb(0, 0, 0);
                    if (!any) continue;
                    packTexel(layout, L, texel.data());
                    const std::size_t t = (std::size_t(k) * ny + j) * nx + i;
                    for (std::size_t tex = 0; tex < textures.size(); ++tex)
                        for (int c = 0; c < 4; ++c) textures[tex][4 * t + std::size_t(c)] += texel[4 * tex + std::size_t(c)];
                }
    });
}

nlohmann::ordered_json foldedDirectJson(const Volume& volume) {
    nlohmann::ordered_json j;
    j["folded_into_sh"] = true;
    j["method"] = "bake --direct occlusion: the listed lights' direct light (exact irradiance x interpolated visibility, "
                  "as vdblight query adds it) fitted onto SH bands 0..2 by least squares over " +
                  std::to_string(kFoldNormals) +
                  " fixed normals at each probe, divided by A_l and added to the coefficients; the engine loses the part "
                  "beyond band 2 (for a point light at most 3/32 of its peak irradiance)";
    nlohmann::ordered_json lights = nlohmann::ordered_json::array();
    for (const DirectLight& light : volume.direct.lights) lights.push_back(formatDirectLight(light));
    j["lights"] = std::move(lights);
    return j;
}

}  // namespace vdblight::exporter
