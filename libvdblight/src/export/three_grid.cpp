// export --format three: the probe grid of three.js's LightProbeGridWebGL (export_three.h).
// The volume is sampled as the `sh2` layout (bands 0..2 of its radiance SH, at the lattice
// points), given one border probe per side, and the nine coefficients are repacked into the
// class's 3-D atlas.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "export_internal.h"
#include "fold_direct.h"
#include "staged_files.h"
#include "three_grid_json.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "basis/sh.h"

namespace vdblight {

namespace fs = std::filesystem;
using namespace exporter;

namespace {
constexpr int kSubVolumes = 7;  // 27 floats in RGBA texels
constexpr int kPadding = 1;     // slices at each end of a sub-volume (LightProbeGridWebGL's ATLAS_PADDING)

// The volume must hold SH bands 0..2 (sh2 or sh:N with N >= 2); one line naming the kind otherwise.
void checkBasis(const Volume& volume) {
    bins::BasisSpec spec;
    const std::unique_ptr<Basis> basis = basisOf(volume.basis);
    const bool shOrder2 = basis && !bins::specFromVolume(volume.basis, spec) && basis->shCoefficients() >= sh::kCoeffs;
    // Irradiance-vector volumes have no registered basis: refused here too, with the same line.
    if (!shOrder2)
        throw FormatError("--format three writes SH order-2 probes; a '" + volume.basis.kind +
                          "' volume stores no SH bands 0..2 (bake with --basis sh2 or sh:N, N >= 2)");
    // three's shader adds nothing but the grid's SH. An occlusion volume's direct light is folded
    // into it (fold_direct.h); a runtime volume's lights need the scene's shadows at run time,
    // which this grid cannot hold, so it is refused rather than exported dim.
    if (volume.direct.mode == DirectMode::Runtime)
        throw FormatError(std::string("--format three needs all light in the SH; this volume keeps the direct light of ") +
                          std::to_string(volume.direct.lights.size()) + " listed light(s) for the run time to add "
                          "(--direct runtime): bake with --direct occlusion (folded on export) or --direct baked");
}

// One more probe on each side of every axis holding the edge node's value (texels padded by
// replication). Three lights a fragment only if its sample point lies in the grid's box, and
// the nodes' box (scene bounds inset by half a spacing, minus the remainder of a spacing) can
// leave a thin band along the walls outside it, unlit; with the border the box reaches a
// spacing further, and a border probe holds exactly what query's clamping gives there.
std::vector<std::vector<float>> withBorderProbes(const std::vector<std::vector<float>>& textures, const int dims[3]) {
    const int nx = dims[0], ny = dims[1], nz = dims[2];
    std::vector<std::vector<float>> out;
    for (const std::vector<float>& t : textures) {
        std::vector<float> padded(std::size_t(nx + 2) * (ny + 2) * (nz + 2) * 4);
        std::size_t at = 0;
        for (int k = -1; k <= nz; ++k)
            for (int j = -1; j <= ny; ++j)
                for (int i = -1; i <= nx; ++i, at += 4) {
                    const std::size_t from = (std::size_t(std::clamp(k, 0, nz - 1)) * ny + std::clamp(j, 0, ny - 1)) * nx +
                                             std::clamp(i, 0, nx - 1);
                    std::copy_n(&t[from * 4], 4, &padded[at]);
                }
        out.push_back(std::move(padded));
    }
    return out;
}
}  // namespace

std::vector<float> packThreeGridAtlas(const std::vector<std::vector<float>>& sh2, const int dims[3]) {
    if (sh2.size() != std::size_t(sh::kCoeffs)) throw ValueError("the three.js atlas packs nine SH textures");
    const std::size_t nx = std::size_t(dims[0]), ny = std::size_t(dims[1]), nz = std::size_t(dims[2]);
    const std::size_t slice = nx * ny, padded = nz + 2 * kPadding;
    for (const std::vector<float>& t : sh2)
        if (t.size() != slice * nz * 4) throw ValueError("an SH texture does not match the lattice");
    std::vector<float> atlas(slice * padded * kSubVolumes * 4, 0.0f);
    for (std::size_t z = 0; z < padded; ++z) {
        // Padding slices repeat the nearest data slice, so filtering never blends sub-volumes.
        const std::size_t k = std::min(nz - 1, z < kPadding ? 0 : z - kPadding);
        for (std::size_t s = 0; s < slice; ++s) {
            const std::size_t texel = k * slice + s;
            for (int t = 0; t < kSubVolumes; ++t) {
                float* out = &atlas[((std::size_t(t) * padded + z) * slice + s) * 4];
                for (int c = 0; c < 4; ++c) {
                    const int f = 4 * t + c;  // c0.r c0.g c0.b c1.r ... c8.b, then 0
                    if (f < 3 * sh::kCoeffs) out[c] = sh2[std::size_t(f / 3)][texel * 4 + std::size_t(f % 3)];
                }
            }
        }
    }
    return atlas;
}

ThreeGridSummary exportThreeGrid(const Volume& volume, const std::string& outDir, const ThreeGridOptions& o) {
    if (outDir.empty()) throw IoError("no output directory given");
    checkBasis(volume);
    const IrradianceQuery query(volume);
    ThreeGridSummary summary;
    const TextureLattice nodes = chooseLattice(query.bounds(), finestSpacing(volume.levels), o.resolution);
    for (int a = 0; a < 3; ++a)
        if (nodes.dims[a] < 2)
            throw ValueError("a three.js probe grid needs at least 2 probes per axis; the volume has " +
                             std::to_string(nodes.dims[a]) + " along " + "xyz"[a] + " (raise --resolution)");
    // The probes: the lattice and one border probe on each side (withBorderProbes).
    TextureLattice& l = summary.lattice;
    l.lo = nodes.lo - nodes.spacing();
    l.hi = nodes.hi + nodes.spacing();
    for (int a = 0; a < 3; ++a) l.dims[a] = nodes.dims[a] + 2;
    summary.atlasDepth = kSubVolumes * (l.dims[2] + 2 * kPadding);
    const double texels = double(l.dims[0]) * double(l.dims[1]) * double(summary.atlasDepth);
    // The nine sampled and the nine bordered textures, the float atlas (16 B each), then the encoded copy.
    const double needed = double(l.texelCount()) * 18.0 * 16.0 + texels * (16.0 + (o.halfFloat ? 8.0 : 16.0));
    if (needed > double(o.maxBytes) || l.dims[0] > 2048 || l.dims[1] > 2048 || summary.atlasDepth > 2048)
        throw ValueError("a " + std::to_string(l.dims[0]) + " x " + std::to_string(l.dims[1]) + " x " +
                         std::to_string(summary.atlasDepth) + " atlas is over the 2048-texel 3-D texture limit "
                         "(WebGL 2's usual MAX_3D_TEXTURE_SIZE) or the memory limit; lower --resolution");
    checkOutputDirectory(outDir);

    std::vector<std::vector<float>> sh2 = sampleLayout(query, nodes, ExportLayout::Sh2);
    addFoldedDirectLight(volume, query, nodes, ExportLayout::Sh2, sh2);  // occlusion volumes (fold_direct.h)
    if (foldsDirectLight(volume)) summary.foldedLights = int(volume.direct.lights.size());
    const std::vector<float> atlas = packThreeGridAtlas(withBorderProbes(sh2, nodes.dims), l.dims);
    if (o.halfFloat) checkHalfRange({atlas}, {TextureDesc{"probe grid atlas", {}}});

    ThreeGridJsonInput json;
    json.lattice = &l;
    json.atlasDepth = summary.atlasDepth;
    json.halfFloat = o.halfFloat;
    json.basisKind = volume.basis.kind;
    json.hasDepthMoments = volume.hasDepth();
    if (foldsDirectLight(volume)) json.foldedDirect = foldedDirectJson(volume);
    StagedFiles staged;
    staged.createDirectory(outDir);
    const TexelFormat format = lightingTexelFormat(o.halfFloat);
    writeBytes(staged.stage(outDir, kThreeGridAtlasFile), encodeTexels(atlas.data(), atlas.size(), format));
    const std::string text = threeGridJson(json);
    writeBytes(staged.stage(outDir, kThreeGridJsonFile), std::vector<uint8_t>(text.begin(), text.end()));
    summary.files = staged.commit();
    for (const std::string& f : summary.files) summary.bytes += fs::file_size(f);
    return summary;
}

}  // namespace vdblight
