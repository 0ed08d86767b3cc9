// export --format three: the probe grid of three.js's LightProbeGridWebGL (export_three.h).
// The volume is sampled as the `sh2` layout (bands 0..2 of its radiance SH, at the lattice
// points) and the nine coefficients are repacked into the class's 3-D atlas.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "export_internal.h"
#include "staged_files.h"
#include "three_grid_json.h"
#include "vdblight/basis.h"
#include "vdblight/bins.h"
#include "vdblight/errors.h"
#include "vdblight/export_three.h"
#include "vdblight/sh.h"

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
    // Irradiance-vector volumes have no registered basis: sampleLayout's probe refuses them.
    if (basis && !shOrder2)
        throw FormatError("--format three writes SH order-2 probes; a '" + volume.basis.kind +
                          "' volume stores no SH bands 0..2 (bake with --basis sh2 or sh:N, N >= 2)");
    // three's shader adds nothing but the grid's SH: light kept outside it (runtime lights, or
    // per-light visibility grids) would be lost, so such volumes are refused, not exported dim.
    if (volume.direct.mode != DirectMode::Baked)
        throw FormatError(std::string("--format three needs all light in the SH; this volume keeps the direct light of ") +
                          std::to_string(volume.direct.lights.size()) + " listed light(s) outside it (--direct " +
                          directModeName(volume.direct.mode) + "): bake with --direct baked");
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
    summary.lattice = chooseLattice(query.bounds(), finestSpacing(volume.levels), o.resolution);
    const TextureLattice& l = summary.lattice;
    for (int a = 0; a < 3; ++a)
        if (l.dims[a] < 2)
            throw ValueError("a three.js probe grid needs at least 2 probes per axis; the volume has " +
                             std::to_string(l.dims[a]) + " along " + "xyz"[a] + " (raise --resolution)");
    summary.atlasDepth = kSubVolumes * (l.dims[2] + 2 * kPadding);
    const double texels = double(l.dims[0]) * double(l.dims[1]) * double(summary.atlasDepth);
    // The nine sampled textures and the float atlas (16 B each), then the encoded copy.
    const double needed = double(l.texelCount()) * 9.0 * 16.0 + texels * (16.0 + (o.halfFloat ? 8.0 : 16.0));
    if (needed > double(o.maxBytes) || l.dims[0] > 2048 || l.dims[1] > 2048 || summary.atlasDepth > 2048)
        throw ValueError("a " + std::to_string(l.dims[0]) + " x " + std::to_string(l.dims[1]) + " x " +
                         std::to_string(summary.atlasDepth) + " atlas is over the 2048-texel 3-D texture limit "
                         "(WebGL 2's usual MAX_3D_TEXTURE_SIZE) or the memory limit; lower --resolution");
    checkOutputDirectory(outDir);

    const std::vector<float> atlas = packThreeGridAtlas(sampleLayout(query, l, ExportLayout::Sh2), l.dims);
    if (o.halfFloat) checkHalfRange({atlas}, {TextureDesc{"probe grid atlas", {}}});

    ThreeGridJsonInput json;
    json.lattice = &l;
    json.atlasDepth = summary.atlasDepth;
    json.halfFloat = o.halfFloat;
    json.basisKind = volume.basis.kind;
    json.hasDepthMoments = volume.hasDepth();
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
