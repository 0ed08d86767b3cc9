// exportTextures: check everything, sample, then write all files under temporary names and
// rename them into place at the end (an error leaves nothing half-written).

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "compact_sh.h"
#include "export_internal.h"
#include "staged_files.h"
#include "vdblight/core/atomic_file.h"
#include "vdblight/basis/bins.h"
#include "basis/sh.h"
#include "vdblight/core/errors.h"
#include "basis/irradiance_vectors_compact.h"
#include "query/query_direct.h"

namespace vdblight {

namespace fs = std::filesystem;
using namespace exporter;

namespace {

std::string gib(double bytes) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f GiB", bytes / double(1ull << 30));
    return buf;
}

std::string dimsText(const TextureLattice& l) {
    return std::to_string(l.dims[0]) + " x " + std::to_string(l.dims[1]) + " x " + std::to_string(l.dims[2]);
}

// Texture sizes the format (and the APIs that load it) allow; ValueError naming the limit.
void checkFormatLimits(TextureFormat format, const TextureLattice& l) {
    const int largest = std::max(l.dims[0], std::max(l.dims[1], l.dims[2]));
    if (format == TextureFormat::Dds && largest > 2048)
        throw ValueError("a " + dimsText(l) + " texture exceeds the DDS volume limit of 2048 texels per axis "
                         "(D3D11/D3D12 maximum 3-D texture size); lower --resolution");
    if (format == TextureFormat::Ktx2 && largest > 2048)
        throw ValueError("a " + dimsText(l) + " texture exceeds the KTX2 export limit of 2048 texels per axis "
                         "(maxImageDimension3D of desktop Vulkan GPUs, and the D3D limit); lower --resolution");
    if (format == TextureFormat::ExrAtlas) {
        const AtlasGrid g = atlasGrid(l.dims[2]);
        const long long w = 1LL * g.columns * l.dims[0], h = 1LL * g.rows * l.dims[1];
        if (w > 16384 || h > 16384)
            throw ValueError("the EXR atlas would be " + std::to_string(w) + " x " + std::to_string(h) +
                             " pixels, over the 16384-pixel 2-D texture limit (D3D11/D3D12, Unity); lower --resolution");
    }
    if (l.texelCount() > (1ull << 31))
        throw ValueError("a " + dimsText(l) + " texture has over 2^31 texels; lower --resolution");
}
}  // namespace

void exporter::checkHalfRange(const std::vector<std::vector<float>>& textures, const std::vector<TextureDesc>& descs) {
    for (std::size_t t = 0; t < textures.size(); ++t)
        for (std::size_t i = 0; i < textures[t].size(); ++i) {
            const float v = textures[t][i];
            if (std::isfinite(v) && std::fabs(v) <= 65504.0f) continue;
            std::ostringstream s;
            s << "texture '" << descs[t].name << "' texel " << i / 4 << " holds " << v
              << ", outside the half-float range (+-65504); export with --float";
            throw ValueError(s.str());
        }
}

// The directory (or its first existing ancestor) must be a writable directory.
void exporter::checkOutputDirectory(const std::string& dirName) {
    const fs::path dir(dirName);
    std::error_code ec;
    fs::path p = fs::absolute(dir, ec);
    while (!p.empty() && !fs::exists(p, ec)) {
        if (p == p.parent_path()) break;
        p = p.parent_path();
    }
    if (!fs::is_directory(p, ec))
        throw IoError("cannot create output directory '" + dir.string() + "': '" + p.string() + "' is not a directory");
    if (::access(p.c_str(), W_OK) != 0)
        throw IoError("cannot write into '" + dir.string() + "': '" + p.string() + "' is not writable");
}

std::vector<TextureDesc> exporter::visibilityTextures(const DirectLightSet& direct) {
    std::vector<TextureDesc> out;
    if (!direct.hasVisibility()) return out;
    const std::size_t n = direct.lights.size();
    for (std::size_t first = 0; first < n; first += 4) {
        const std::size_t last = std::min(n, first + 4) - 1;
        TextureDesc d;
        d.name = "light_visibility_" + std::to_string(first) + "_" + std::to_string(last);
        for (std::size_t c = 0; c < 4; ++c)
            d.components[c] = first + c <= last ? "visibility of light " + std::to_string(first + c) : "0";
        out.push_back(d);
    }
    return out;
}

std::vector<std::vector<float>> exporter::sampleVisibility(const IrradianceQuery& query, const TextureLattice& lattice,
                                                           std::size_t lights) {
    const auto* occlusion = dynamic_cast<const OcclusionLookup*>(&query.lookup());
    if (!occlusion) throw FormatError("the volume lists light visibility but its lookup does not read it");
    std::vector<std::vector<float>> out((lights + 3) / 4, std::vector<float>(lattice.texelCount() * 4, 0.0f));
    std::vector<float> v(lights);
    std::size_t texel = 0;
    for (int k = 0; k < lattice.dims[2]; ++k)
        for (int j = 0; j < lattice.dims[1]; ++j)
            for (int i = 0; i < lattice.dims[0]; ++i, ++texel) {
                occlusion->visibility(lattice.point(i, j, k), v.data());
                for (std::size_t l = 0; l < lights; ++l) out[l / 4][texel * 4 + l % 4] = v[l];
            }
    return out;
}

ExportSummary exportTextures(const Volume& volume, const std::string& outDir, const ExportOptions& o) {
    if (outDir.empty()) throw IoError("no output directory given");
    // A compact volume interpolates colour and direction separately between nodes; full
    // vectors interpolated trilinearly would not reproduce its query, so only `compact` fits.
    if (o.layout == ExportLayout::Vectors && volume.basis.isCompactIrradianceVectors())
        throw FormatError("layout 'vectors' does not fit a compact irradiance-vector volume (its colour and direction "
                          "are interpolated separately); use --layout compact");
    bins::BasisSpec binSpec;
    const bool binsVolume = bins::specFromVolume(volume.basis, binSpec);
    if (binsVolume != (o.layout == ExportLayout::Bins))
        throw FormatError(std::string("layout '") + layoutName(o.layout) + "' does not fit a '" + volume.basis.kind +
                          "' volume" + (binsVolume ? " (it stores directional bins); use --layout bins"
                                                   : " (it stores no directional bins; bins fits bins:R and moment:n volumes)"));
    const int binResolution = binsVolume ? binSpec.resolution : 0;
    // The basis of the registry the volume stores (basis.h), if any: the layouts 'bins' and
    // 'basis' are its own textures, sampled from the lookup's channel values.
    const std::unique_ptr<Basis> basis = basisOf(volume.basis);
    const bool ownLayout = o.layout == ExportLayout::Basis || o.layout == ExportLayout::Bins;
    if (o.layout == ExportLayout::Basis && !basis)
        throw FormatError("layout 'basis' fits the volumes of a registered basis (sh2, sh:N, bins:N, moment:N); this one "
                          "stores '" + volume.basis.kind + "' (try --layout vectors or compact)");
    // Real SH of order >= 2 (sh:N) exports its bands 0..2 in the SH order-2 layouts: truncating
    // orthonormal SH is the projection onto those bands (what an engine's L2 probes hold).
    if (basis && !binsVolume && basis->shCoefficients() < sh::kCoeffs && !ownLayout)
        throw FormatError(std::string("layout '") + layoutName(o.layout) + "' does not fit a '" + volume.basis.kind +
                          "' volume; use --layout basis");
    const IrradianceQuery query(volume);
    const double finest = finestSpacing(volume.levels);
    ExportSummary summary;
    summary.lattice = chooseLattice(query.bounds(), finest, o.resolution);
    const TextureLattice& lattice = summary.lattice;
    checkFormatLimits(o.format, lattice);

    std::vector<TextureDesc> descs = ownLayout ? basisTextures(*basis) : layoutTextures(o.layout, binResolution);
    const std::size_t layoutCount = descs.size();
    const std::vector<TextureDesc> visibility = visibilityTextures(volume.direct);  // bake --direct occlusion
    descs.insert(descs.end(), visibility.begin(), visibility.end());
    const double bytesPerTexel = double(descs.size()) * 16.0 + (o.halfFloat ? 16.0 : 32.0);
    const double needed = double(lattice.texelCount()) * bytesPerTexel;
    if (needed > double(o.maxBytes))
        throw ValueError("exporting " + dimsText(lattice) + " texels in " + std::to_string(descs.size()) +
                         " textures would need " + gib(needed) + " of memory (limit " + gib(double(o.maxBytes)) +
                         "); lower --resolution");
    checkOutputDirectory(outDir);

    std::vector<std::vector<float>> textures =
        ownLayout ? sampleBasis(query, lattice, *basis) : sampleLayout(query, lattice, o.layout, binResolution);
    if (!visibility.empty()) {
        std::vector<std::vector<float>> v = sampleVisibility(query, lattice, volume.direct.lights.size());
        for (auto& t : v) textures.push_back(std::move(t));
    }
    if (o.halfFloat) checkHalfRange(textures, descs);
    std::vector<TexelFormat> formats(descs.size(), lightingTexelFormat(o.halfFloat));
    // The engine-size layouts (compact_sh.h): every texture but L0_L1Rx holds values in [0, 1]
    // (the higher bands divided by L0, light visibility), stored in 8 bits where the container
    // has an 8-bit type (as the depth textures; the EXR atlas keeps half / float).
    if (isCompactSh(o.layout))
        std::fill(formats.begin() + 1, formats.end(), depthTexelFormat(o.format, o.halfFloat));
    // Depth moments (depth_moments.h) go along as three more textures when the texels are the
    // nodes. They are multiples of 1/255, so 8-bit unorm holds them exactly (12 B per node
    // against 24 in half); the EXR atlas has no 8-bit type and keeps half or float (half
    // rounds k/255 by up to 2^-12).
    // Shadow edges (shadow_edges.h) when the texels are the nodes, in the lighting format
    // (distances are signed), before the depth textures (the manifest reads those last). The
    // engine-size layouts' shaders fetch the eight corner texels anyway, so they compute each
    // corner's ramp from its d and w: no ramp texture there (8 B per probe less in half).
    // The second edge's strip textures where some node has one (docs/shadow_visibility.md,
    // "A second edge"), in every layout that carries the edges.
    const bool withRamp = !isCompactSh(o.layout), withStrips = hasShadowStrips(volume);
    std::vector<std::vector<float>> edges = edgeTextures(volume, lattice, withRamp, withStrips);
    std::vector<std::string> edgeNames;
    if (!edges.empty()) {
        for (TextureDesc& d : edgeTextureDescs(volume.direct, withRamp, withStrips)) {
            edgeNames.push_back(d.name);
            descs.push_back(std::move(d));
        }
        for (std::vector<float>& t : edges) textures.push_back(std::move(t));
        if (o.halfFloat) checkHalfRange(textures, descs);
        formats.resize(descs.size(), lightingTexelFormat(o.halfFloat));
    }
    int depthExport = 0;
    if (volume.hasDepth()) {
        std::vector<std::vector<float>> depth = depthTextures(volume, lattice);
        depthExport = depth.empty() ? -1 : 1;
        if (!depth.empty()) {
            for (TextureDesc& d : depthTextureDescs()) descs.push_back(std::move(d));
            for (std::vector<float>& t : depth) textures.push_back(std::move(t));
            formats.resize(descs.size(), depthTexelFormat(o.format, o.halfFloat));
        }
    }

    StagedFiles staged;
    staged.createDirectory(outDir);
    ManifestInput manifest;
    manifest.options = &o;
    manifest.lattice = &lattice;
    manifest.volumeKind = query.kind();
    manifest.basisKind = volume.basis.kind;
    manifest.binResolution = binResolution;
    manifest.momentOrder = binsVolume ? binSpec.order : 0;
    if (basis) manifest.basisFormula = basis->formula();
    manifest.textures = descs;
    manifest.direct = &volume.direct;
    for (std::size_t t = layoutCount; t < layoutCount + visibility.size(); ++t) manifest.visibilityTextures.push_back(descs[t].name);
    manifest.depth = depthExport;
    manifest.edgeTextures = edgeNames;
    for (std::size_t t = 0; t < descs.size(); ++t) {
        TextureImage image;
        image.rgba = textures[t].data();
        std::copy_n(lattice.dims, 3, image.dims);
        image.format = formats[t];
        image.name = descs[t].name;
        const std::string file = descs[t].name + textureExtension(o.format);
        const std::string path = staged.stage(outDir, file);
        uint64_t offset = 0;
        switch (o.format) {
            case TextureFormat::Ktx2: offset = writeKtx2(path, image); break;
            case TextureFormat::Dds: offset = writeDds(path, image); break;
            case TextureFormat::ExrAtlas: offset = writeExrAtlas(path, image); break;
            case TextureFormat::Raw: offset = writeRaw(path, image); break;
        }
        manifest.fileNames.push_back(file);
        manifest.texelFormats.push_back(formats[t]);
        manifest.dataOffsets.push_back(offset);
    }
    const std::string json = manifestJson(manifest);
    writeBytes(staged.stage(outDir, "manifest.json"), std::vector<uint8_t>(json.begin(), json.end()));
    summary.files = staged.commit();
    for (const std::string& f : summary.files) summary.bytes += fs::file_size(f);
    return summary;
}

}  // namespace vdblight
