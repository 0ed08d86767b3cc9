// exportCells (export_cells.h): the export lattice cut into cells with one shared texel plane
// between neighbours, each sampled and written like a small whole-volume export.
#include "vdblight/export/export.h"


#include <filesystem>
#include <functional>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "compact_sh.h"
#include "cell_textures.h"
#include "export_internal.h"
#include "staged_files.h"
#include "basis/shadow_edges.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"

namespace vdblight {

namespace fs = std::filesystem;
using namespace exporter;

namespace {

// cells.json is built as a JSON object whose keys keep the order they are added in.
using Json = nlohmann::ordered_json;

Json vec3(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }
Json ints3(const int v[3]) { return Json::array({v[0], v[1], v[2]}); }


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

namespace {

// The volume's part of a cell export: its header (basis, levels' grids, direct-light mode),
// for the depth textures the finest level's depth moments (null without them), and for the
// edge textures level 0's shadow edges (null without them) and whether some node has a strip.
struct CellSource {
    const Volume* header = nullptr;
    FinestNodeDepth depth;
    NodeShadowEdges edges;
    bool strips = false;  ///< hasShadowStrips of the whole volume: every cell lists the same textures
    std::function<void()> afterCell;  ///< called once a cell's files are staged (a streamed volume's leaves)
};

CellsSummary exportCellsFrom(const IrradianceQuery& query, const CellSource& source, const std::string& outDir,
                             const ExportOptions& o, int cellSize) {
    const Volume& header = *source.header;
    if (outDir.empty()) throw IoError("no output directory given");
    if (cellSize < 1) throw ValueError("--cells must be at least 1 lattice step");
    const std::unique_ptr<Basis> basis = basisOf(header.basis);
    if (o.layout == ExportLayout::Basis && !basis)
        throw FormatError("layout 'basis' fits the volumes of a registered basis (sh2, sh:N, bins:N, moment:N); this one "
                          "stores '" + header.basis.kind + "'");
    if ((!layoutIsSh(o.layout) || isCompactSh(o.layout)) && o.layout != ExportLayout::Basis)
        throw FormatError(std::string("--cells exports the SH layouts (sh2, sh2-packed, sh1) and basis, not '") +
                          layoutName(o.layout) + "'");
    const LightVisibility* visibility = dynamic_cast<const LightVisibility*>(&query.lookup());
    if (header.direct.hasVisibility() && !visibility)
        throw FormatError("the volume lists light visibility but its lookup does not read it");
    try {
        Rgb probe[9];
        std::vector<float> channels(basis ? basis->floatsPerNode() : 0);
        if (o.layout == ExportLayout::Basis) query.lookup().channelValues(query.bounds().lo, channels.data());
        else query.lookup().shRadiance(query.bounds().lo, probe);
    } catch (const FormatError&) {
        throw FormatError(std::string("layout '") + layoutName(o.layout) + "' does not fit volume kind '" + query.kind() +
                          (o.layout == ExportLayout::Basis ? "' (it exposes no channel values)"
                                                           : "' (it stores no SH order-2 coefficients)"));
    }
    const double finest = finestSpacing(header.levels);
    CellsSummary summary;
    summary.lattice = chooseLattice(query.bounds(), finest, o.resolution);
    const TextureLattice& whole = summary.lattice;
    for (int a = 0; a < 3; ++a) summary.cells[a] = whole.dims[a] > 1 ? (whole.dims[a] - 2) / cellSize + 1 : 1;
    std::vector<TextureDesc> descs = o.layout == ExportLayout::Basis ? basisTextures(*basis) : layoutTextures(o.layout);
    const std::size_t layoutCount = descs.size();
    // As the whole export (export.cpp): visibility textures of bake --direct occlusion, then
    // the depth textures where the lattice is the finest level's nodes (else manifest -1).
    const std::vector<TextureDesc> visibilityDescs = visibilityTextures(header.direct);
    descs.insert(descs.end(), visibilityDescs.begin(), visibilityDescs.end());
    // The shadow edges and strips where the whole export writes them (edgeTextures: a single
    // level whose nodes are the lattice), before the depth textures. Every layout --cells
    // takes has its ramp textures (only the engine-size layouts drop them, and cells refuse those).
    const bool edges = source.edges && header.levels.size() == 1 && depthOnFinestNodes(header.levels[0].grid, whole);
    const bool withRamp = !isCompactSh(o.layout);
    const std::vector<TextureDesc> edgeDescs = edges ? edgeTextureDescs(header.direct, withRamp, source.strips)
                                                     : std::vector<TextureDesc>();
    std::vector<std::string> edgeNames;
    for (const TextureDesc& d : edgeDescs) edgeNames.push_back(d.name);
    descs.insert(descs.end(), edgeDescs.begin(), edgeDescs.end());
    const bool depth = source.depth && depthOnFinestNodes(header.levels.back().grid, whole);
    if (depth)
        for (TextureDesc& d : depthTextureDescs()) descs.push_back(std::move(d));
    std::vector<TexelFormat> formats(layoutCount + visibilityDescs.size() + edgeDescs.size(), lightingTexelFormat(o.halfFloat));
    formats.resize(descs.size(), depthTexelFormat(o.format, o.halfFloat));

    StagedFiles staging;
    const fs::path root(outDir);
    staging.createDirectory(root);
    Json index;
    index["vdblight_cells_version"] = 1;
    index["volume_kind"] = query.kind();
    index["format"] = formatName(o.format);
    index["layout"] = layoutName(o.layout);
    index["lattice"] = {{"dims", ints3(whole.dims)}, {"bounds_min", vec3(whole.lo)}, {"bounds_max", vec3(whole.hi)},
                        {"texel_spacing", vec3(whole.spacing())}};
    index["cell_steps"] = cellSize;
    index["cells_per_axis"] = ints3(summary.cells);
    index["tiling"] = "cell (a, b, c) holds lattice texels [a, b, c] * cell_steps + (0 .. dims - 1); neighbouring cells "
                      "share their boundary texel plane, so each cell's trilinear filtering equals the whole volume's; a "
                      "point x belongs to the cell floor((x - bounds_min) / (texel_spacing * cell_steps)), clamped to the "
                      "last cell";
    Json cells = Json::array();
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
                CellRange range;
                std::copy_n(first, 3, range.first);
                std::copy_n(dims, 3, range.dims);
                std::vector<std::vector<float>> textures =
                    cellLayoutTextures(query.lookup(), whole, range, o.layout, basis.get(), layoutCount);
                if (!visibilityDescs.empty())
                    for (auto& t : cellVisibilityTextures(*visibility, whole, range, header.direct.lights.size()))
                        textures.push_back(std::move(t));
                if (edges)
                    for (auto& t : cellEdgeTextures(source.edges, range, header.direct.lights.size(), withRamp, source.strips))
                        textures.push_back(std::move(t));
                if (depth)
                    for (auto& t : cellDepthTextures(source.depth, range)) textures.push_back(std::move(t));
                ManifestInput manifest;
                manifest.options = &o;
                manifest.lattice = &lattice;
                manifest.volumeKind = query.kind();
                manifest.basisKind = header.basis.kind;
                manifest.textures = descs;
                manifest.direct = &header.direct;
                if (basis) manifest.basisFormula = basis->formula();
                for (std::size_t t = layoutCount; t < layoutCount + visibilityDescs.size(); ++t)
                    manifest.visibilityTextures.push_back(descs[t].name);
                manifest.depth = depth ? 1 : source.depth ? -1 : 0;
                manifest.edgeTextures = edgeNames;
                for (std::size_t t = 0; t < descs.size(); ++t) {
                    for (float v : textures[t])
                        if (o.halfFloat && !(std::abs(v) <= 65504.0f))
                            throw ValueError("texture '" + descs[t].name + "' of " + name +
                                             " holds a value outside the half-float range (+-65504); export with --float");
                    TextureImage image;
                    image.rgba = textures[t].data();
                    std::copy_n(dims, 3, image.dims);
                    image.format = formats[t];
                    image.name = descs[t].name;
                    const std::string file = descs[t].name + textureExtension(o.format);
                    manifest.fileNames.push_back(file);
                    manifest.texelFormats.push_back(image.format);
                    manifest.dataOffsets.push_back(writeTexture(o.format, staging.stage(dir, file), image));
                }
                const std::string json = manifestJson(manifest);
                writeBytes(staging.stage(dir, "manifest.json"), std::vector<uint8_t>(json.begin(), json.end()));
                cells.push_back({{"cell", ints3(cell)}, {"directory", name}, {"texel_offset", ints3(first)},
                                 {"dims", ints3(dims)}, {"bounds_min", vec3(lattice.lo)}, {"bounds_max", vec3(lattice.hi)}});
                if (source.afterCell) source.afterCell();
            }
    index["cells"] = std::move(cells);
    const std::string text = index.dump(2) + "\n";
    writeBytes(staging.stage(root, "cells.json"), std::vector<uint8_t>(text.begin(), text.end()));
    summary.files = staging.count();
    for (const std::string& f : staging.commit()) summary.bytes += fs::file_size(f);
    return summary;
}

}  // namespace

CellsSummary exportCells(const IrradianceQuery& query, const Volume& volume, const std::string& outDir,
                         const ExportOptions& options, int cellSize) {
    for (const VolumeLevel& level : volume.levels)
        if (level.data.empty())
            throw ValueError("exportCells: the volume holds no node values (a streamed volume's header?); give the "
                             "StreamedVolume instead");
    CellSource source;
    source.header = &volume;
    if (volume.hasDepth()) {
        const VolumeLevel& finest = volume.levels.back();
        source.depth = [&finest](int i, int j, int k, float* out) {
            const uint64_t n = finest.grid.index(i, j, k);
            const int64_t at = finest.sparse() ? findNode(finest, n) : int64_t(n);
            if (at < 0) return false;
            std::copy_n(finest.nodeDepth(std::size_t(at)), depth::kFloatsPerNode, out);
            return true;
        };
    }
    if (volume.levels.size() == 1 && !volume.levels[0].lightShadowEdges.empty()) {
        const VolumeLevel& level = volume.levels[0];
        const std::size_t floats = volume.direct.lights.size() * shadow_edge::kFloatsPerLight;
        source.edges = [&level, floats](int i, int j, int k, float* out) {
            std::copy_n(&level.lightShadowEdges[level.held(level.grid.index(i, j, k)) * floats], floats, out);
        };
        source.strips = hasShadowStrips(volume);
    }
    return exportCellsFrom(query, source, outDir, options, cellSize);
}

CellsSummary exportCells(const IrradianceQuery& query, StreamedVolume& volume, const std::string& outDir,
                         const ExportOptions& options, int cellSize, uint64_t leafMemory) {
    CellSource source;
    // Leaves read stay in memory; once those of the cells done so far pass leafMemory, drop them.
    const uint64_t topology = volume.residentBytes();
    source.afterCell = [&volume, topology, leafMemory] {
        if (volume.residentBytes() > topology + leafMemory) volume.releaseLeaves();
    };
    source.header = &volume.header();
    if (volume.hasDepth()) {
        const int finest = int(volume.header().levels.size()) - 1;
        source.depth = [&volume, finest](int i, int j, int k, float* out) {
            if (!volume.nodeStored(finest, i, j, k)) return false;
            volume.readDepth(finest, i, j, k, out);
            return true;
        };
    }
    if (volume.hasShadowEdges() && volume.header().levels.size() == 1) {
        source.edges = [&volume](int i, int j, int k, float* out) { volume.readShadowEdges(i, j, k, out); };
        source.strips = volume.hasShadowStrips();
        source.afterCell();  // the far sides' leaves that scan read
    }
    return exportCellsFrom(query, source, outDir, options, cellSize);
}

}  // namespace vdblight

