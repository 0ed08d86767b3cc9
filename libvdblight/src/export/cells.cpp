// exportCells (export_cells.h): the export lattice cut into cells with one shared texel plane
// between neighbours, each sampled and written like a small whole-volume export.
#include "vdblight/export_cells.h"


#include <filesystem>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "compact_sh.h"
#include "export_internal.h"
#include "staged_files.h"
#include "vdblight/errors.h"

namespace vdblight {

namespace fs = std::filesystem;
using namespace exporter;

namespace {

std::string vec3(const Vec3d& v) {
    std::ostringstream s;
    s.precision(17);
    s << '[' << v.x << ", " << v.y << ", " << v.z << ']';
    return s.str();
}

std::string ints3(const int v[3]) {
    return "[" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + "]";
}


// The cell's texels: the whole lattice's points offset by `first`, sampled as sampleLayout
// samples them (shRadiance at the point, then packTexel), one RGBA array per texture.
std::vector<std::vector<float>> sampleCell(const VolumeLookup& lookup, const TextureLattice& whole, const int first[3],
                                           const int dims[3], ExportLayout layout, std::size_t textures) {
    const std::size_t count = std::size_t(dims[0]) * dims[1] * dims[2];
    std::vector<std::vector<float>> out(textures, std::vector<float>(count * 4));
    tbb::parallel_for(tbb::blocked_range<int>(0, dims[2]), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> texel(textures * 4);
        Rgb L[9];
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < dims[1]; ++j)
                for (int i = 0; i < dims[0]; ++i) {
                    lookup.shRadiance(whole.point(first[0] + i, first[1] + j, first[2] + k), L);
                    packTexel(layout, L, texel.data());
                    const std::size_t t = (std::size_t(k) * dims[1] + j) * dims[0] + i;
                    for (std::size_t tex = 0; tex < textures; ++tex)
                        std::copy_n(texel.data() + 4 * tex, 4, out[tex].data() + 4 * t);
                }
    });
    return out;
}

uint64_t writeTexture(TextureFormat format, const std::string& path, const TextureImage& image) {
    switch (format) {
        case TextureFormat::Ktx2: return writeKtx2(path, image);
        case TextureFormat::Dds: return writeDds(path, image);
        case TextureFormat::ExrAtlas: return writeExrAtlas(path, image);
        case TextureFormat::Raw: return writeRaw(path, image);
    }
    return 0;
}
}  // namespace

CellsSummary exportCells(const IrradianceQuery& query, const Volume& header, const std::string& outDir,
                         const ExportOptions& o, int cellSize) {
    if (outDir.empty()) throw IoError("no output directory given");
    if (cellSize < 1) throw ValueError("--cells must be at least 1 lattice step");
    if (!layoutIsSh(o.layout) || isCompactSh(o.layout))
        throw FormatError(std::string("--cells exports the SH layouts (sh2, sh2-packed, sh1), not '") + layoutName(o.layout) + "'");
    if (header.direct.hasVisibility())
        throw FormatError("--cells does not export per-light visibility (bake --direct occlusion); export the whole volume");
    try {
        Rgb probe[9];
        query.lookup().shRadiance(query.bounds().lo, probe);
    } catch (const FormatError&) {
        throw FormatError(std::string("layout '") + layoutName(o.layout) + "' does not fit volume kind '" + query.kind() +
                          "' (it stores no SH order-2 coefficients)");
    }
    const double finest = finestSpacing(header.levels);
    CellsSummary summary;
    summary.lattice = chooseLattice(query.bounds(), finest, o.resolution);
    const TextureLattice& whole = summary.lattice;
    for (int a = 0; a < 3; ++a) summary.cells[a] = whole.dims[a] > 1 ? (whole.dims[a] - 2) / cellSize + 1 : 1;
    const std::vector<TextureDesc> descs = layoutTextures(o.layout);

    StagedFiles staging;
    const fs::path root(outDir);
    staging.createDirectory(root);
    std::ostringstream index;
    index << "{\n  \"vdblight_cells_version\": 1,\n";
    index << "  \"volume_kind\": \"" << query.kind() << "\",\n";
    index << "  \"format\": \"" << formatName(o.format) << "\",\n  \"layout\": \"" << layoutName(o.layout) << "\",\n";
    index << "  \"lattice\": {\"dims\": " << ints3(whole.dims) << ", \"bounds_min\": " << vec3(whole.lo)
          << ", \"bounds_max\": " << vec3(whole.hi) << ", \"texel_spacing\": " << vec3(whole.spacing()) << "},\n";
    index << "  \"cell_steps\": " << cellSize << ",\n  \"cells_per_axis\": " << ints3(summary.cells) << ",\n";
    index << "  \"tiling\": \"cell (a, b, c) holds lattice texels [a, b, c] * cell_steps + (0 .. dims - 1); neighbouring "
             "cells share their boundary texel plane, so each cell's trilinear filtering equals the whole volume's; a point "
             "x belongs to the cell floor((x - bounds_min) / (texel_spacing * cell_steps)), clamped to the last cell\",\n";
    index << "  \"cells\": [\n";
    bool firstCell = true;
    for (int c = 0; c < summary.cells[2]; ++c)
        for (int b = 0; b < summary.cells[1]; ++b)
            for (int a = 0; a < summary.cells[0]; ++a) {
                const int cell[3] = {a, b, c};
                int first[3], dims[3], last[3];
                for (int x = 0; x < 3; ++x) {
                    first[x] = cell[x] * cellSize;
                    last[x] = std::min(first[x] + cellSize, whole.dims[x] - 1);
                    dims[x] = last[x] - first[x] + 1;
                }
                TextureLattice lattice;
                lattice.lo = whole.point(first[0], first[1], first[2]);
                lattice.hi = whole.point(last[0], last[1], last[2]);
                std::copy_n(dims, 3, lattice.dims);
                const std::string name = "cell_" + std::to_string(a) + "_" + std::to_string(b) + "_" + std::to_string(c);
                const fs::path dir = root / name;
                staging.createDirectory(dir);
                std::vector<std::vector<float>> textures = sampleCell(query.lookup(), whole, first, dims, o.layout, descs.size());
                ManifestInput manifest;
                manifest.options = &o;
                manifest.lattice = &lattice;
                manifest.volumeKind = query.kind();
                manifest.basisKind = header.basis.kind;
                manifest.textures = descs;
                manifest.direct = &header.direct;
                manifest.depth = header.hasDepth() || query.depthWeighted() ? -1 : 0;
                for (std::size_t t = 0; t < descs.size(); ++t) {
                    for (float v : textures[t])
                        if (o.halfFloat && !(std::abs(v) <= 65504.0f))
                            throw ValueError("texture '" + descs[t].name + "' of " + name +
                                             " holds a value outside the half-float range (+-65504); export with --float");
                    TextureImage image;
                    image.rgba = textures[t].data();
                    std::copy_n(dims, 3, image.dims);
                    image.format = lightingTexelFormat(o.halfFloat);
                    image.name = descs[t].name;
                    const std::string file = descs[t].name + textureExtension(o.format);
                    manifest.fileNames.push_back(file);
                    manifest.texelFormats.push_back(image.format);
                    manifest.dataOffsets.push_back(writeTexture(o.format, staging.stage(dir, file), image));
                }
                const std::string json = manifestJson(manifest);
                writeBytes(staging.stage(dir, "manifest.json"), std::vector<uint8_t>(json.begin(), json.end()));
                index << (firstCell ? "" : ",\n") << "    {\"cell\": " << ints3(cell) << ", \"directory\": \"" << name
                      << "\", \"texel_offset\": " << ints3(first) << ", \"dims\": " << ints3(dims)
                      << ", \"bounds_min\": " << vec3(lattice.lo) << ", \"bounds_max\": " << vec3(lattice.hi) << "}";
                firstCell = false;
            }
    index << "\n  ]\n}\n";
    const std::string text = index.str();
    writeBytes(staging.stage(root, "cells.json"), std::vector<uint8_t>(text.begin(), text.end()));
    summary.files = staging.count();
    for (const std::string& f : staging.commit()) summary.bytes += fs::file_size(f);
    return summary;
}

}  // namespace vdblight
