// The export module's textures: dense textures and a manifest (below), and tiled cells of a
// world larger than memory (second part).
//
// Dense 3-D textures of a baked volume for game engines and custom renderers.
//
// Export samples the volume through IrradianceQuery on a dense lattice of texels (texel
// (i, j, k) <-> lattice point lo + spacing * (i, j, k)), so that every kind of volume exports
// the same way; by default the lattice is the volume's finest node spacing over its bounds,
// so a uniform volume exports its nodes. Each texture is RGBA (half or float; the depth
// textures of a volume with depth moments, and all but the first texture of sh1-16 / sh2-32
// with their light visibility, are 8-bit unorm, except in the EXR atlas); a
// layout says what the components mean; `manifest.json` beside the textures states all of it, and
// docs/engines.md gives the shader code.
//
//   ExportOptions o;
//   o.format = TextureFormat::Ktx2;
//   o.layout = ExportLayout::Sh2Packed;
//   ExportSummary s = exportTextures(readVolume("cornell.vdb"), "out/", o);
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "vdblight/core/math.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

/// The container written for each texture.
enum class TextureFormat {
    Ktx2,      ///< KTX 2.0 3-D texture, vkFormat 97 (RGBA16F) or 109 (RGBA32F); depth: 37 (RGBA8 unorm)
    Dds,       ///< DDS + DX10 header, TEXTURE3D, DXGI format 10 (RGBA16F) or 2 (RGBA32F); depth: 28 (RGBA8 unorm)
    ExrAtlas,  ///< OpenEXR 2-D atlas of z slices (columns x rows of tiles, z = 0 top left); depth: half / float
    Raw,       ///< little-endian RGBA arrays, x fastest, no header; depth: 1 byte per component
};

/// What the four components of each texture hold (docs/engines.md).
enum class ExportLayout {
    Sh2,        ///< 9 textures: SH coefficient j's radiance RGB, alpha 0 (as stored in the .vdb)
    Sh2Packed,  ///< 7 textures shAr shAg shAb shBr shBg shBb shC: irradiance by dot products
    Sh1,        ///< 3 textures shAr shAg shAb: the order-1 (L0 + L1) part of the irradiance
    Vectors,    ///< 18 textures iv_<dir>_<r|g|b>: an irradiance vector (world xyz) each, alpha 0
    Compact,    ///< 12 textures ivc_<dir>_colour / ivc_<dir>_dir: Pacanowski et al. section 4.2
    Bins,       ///< bins:R / moment:n volumes: 2 R^2 textures bin_h<h>_u<iu>_v<iv>, the bin's RGB, alpha 0
    Basis,      ///< any registered basis (basis/basis.h, e.g. sh:N): the basis's own textures (Basis::textures)
    Sh1x16,     ///< "sh1-16": 3 textures, 16 B per probe: L0 half, L1 / L0 in UNORM8 (Unity APV's arrangement)
    Sh2x32,     ///< "sh2-32": 7 textures, 32 B per probe: sh1-16 + band 2 / L0 in four UNORM8 textures
};

/// Parses "ktx2" | "dds" | "exr-atlas" | "raw" (ValueError listing the choices otherwise).
TextureFormat parseTextureFormat(const std::string& name);
/// Parses "sh2" | "sh2-packed" | "sh1" | "sh1-16" | "sh2-32" | "vectors" | "compact" | "bins" | "basis"
/// (ValueError listing the choices otherwise).
ExportLayout parseExportLayout(const std::string& name);
const char* formatName(TextureFormat format);
const char* layoutName(ExportLayout layout);

struct ExportOptions {
    TextureFormat format = TextureFormat::Ktx2;
    ExportLayout layout = ExportLayout::Sh2Packed;
    bool halfFloat = true;                  ///< 16-bit floats (default) or 32-bit (not the 8-bit depth textures)
    int resolution = 0;                     ///< texels along the longest axis; 0: finest node spacing
    uint64_t maxBytes = 4ull << 30;         ///< refuse exports needing more memory than this
};

/// The dense lattice of texels. Texel (i, j, k) holds the volume at point(i, j, k); its
/// centre in normalised texture coordinates is ((i, j, k) + 0.5) / dims.
struct TextureLattice {
    Vec3d lo, hi;          ///< the box spanned by the texel points (the volume's node box)
    int dims[3] = {0, 0, 0};
    Vec3d spacing() const;  ///< distance between neighbouring texel points per axis
    Vec3d point(int i, int j, int k) const;
    uint64_t texelCount() const { return uint64_t(dims[0]) * uint64_t(dims[1]) * uint64_t(dims[2]); }
};

/// Chooses the lattice over `bounds`: `resolution` texels along the longest axis (others in
/// proportion), or with 0 the spacing `finestSpacing`. Throws ValueError for resolution < 2.
TextureLattice chooseLattice(const Bounds& bounds, double finestSpacing, int resolution);

struct ExportSummary {
    TextureLattice lattice;
    std::vector<std::string> files;  ///< written files (textures, then manifest.json), full paths
    uint64_t bytes = 0;               ///< total size of the written files
};

/// Writes the textures and `manifest.json` into `outDir` (created if missing). Everything is
/// checked and sampled before the first byte is written; files go to temporary names and
/// are renamed at the end, so an error leaves no partial file. Throws FormatError (the layout
/// does not fit the volume kind), ValueError (texture larger than the format allows, memory
/// above maxBytes, values beyond the half-float range) or IoError (directory not writable).
ExportSummary exportTextures(const Volume& volume, const std::string& outDir, const ExportOptions& options);

/// Runs `write`, an export of one file into the directory `outDir` (exportGltfProbes,
/// exportPreviewVdb): creates the directory if it is missing and removes it again if `write`
/// throws, so that a failed export leaves nothing behind.
void intoOutputDirectory(const std::string& outDir, const std::function<void()>& write);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Textures cut into streaming cells: one texture set per cell of K x K x K lattice steps plus
// an index, as engines stream probe volumes in cells (Unity's APV bricks, Unreal's volumetric
// lightmap bricks) instead of one 3-D texture for the world.
//
// The cells tile the export lattice of exportTextures (export/export.h): cell (a, b, c) holds texels
// [a K, min(a K + K, dims - 1)] per axis of the whole lattice, so neighbouring cells share
// their boundary texel plane and a cell's own trilinear filtering reproduces the whole
// volume's between its texels. Every texel holds the value the whole-volume export holds at
// the same lattice point (the same lookup at the same point, bit for bit).
//
//   OUT/cells.json                        the index: lattice, K, cells per axis, every cell's
//                                         directory, texel offset, dims and box
//   OUT/cell_<a>_<b>_<c>/manifest.json    that cell's textures, as exportTextures writes them
//   OUT/cell_<a>_<b>_<c>/<texture>.ktx2   the layout's textures, light_visibility_*, depth_x/y/z
//
// Sampling goes through IrradianceQuery, so a streamed volume (query/query.h) exports cell
// by cell without being read whole.

namespace vdblight {

struct CellsSummary {
    TextureLattice lattice;    ///< the whole export lattice
    int cells[3] = {0, 0, 0};  ///< cells per axis
    std::size_t files = 0;     ///< files written (textures, manifests, cells.json)
    uint64_t bytes = 0;        ///< their total size
};

/// Writes the cells of `query`'s volume into `outDir`: per cell the layout's textures (sh2,
/// sh2-packed, sh1, or basis: the volume's own channels), the light visibility textures of
/// a volume baked with --direct occlusion and, where the lattice is the finest level's nodes,
/// the three depth textures, each texel as the whole export (exportTextures) writes it.
/// `volume`: the volume in memory that `query` was built from (ValueError if it holds no node
/// values); `cellSize` K >= 1 lattice steps per cell edge. FormatError for other layouts.
/// Files are staged under temporary names and renamed at the end: an error leaves no partial
/// export.
CellsSummary exportCells(const IrradianceQuery& query, const Volume& volume, const std::string& outDir,
                         const ExportOptions& options, int cellSize);

/// Default of exportCells' `leafMemory`.
constexpr uint64_t kCellsLeafMemory = 1ull << 30;

/// The same for a streamed volume (volume/vdb_io.h) and its makeStreamingQuery, the same files:
/// the leaves the cells read stay in memory until they take more than `leafMemory` bytes
/// beyond the topology; then, between two cells, StreamedVolume::releaseLeaves drops them. So
/// the export holds the topology, the leaves of the cells since the last release and one
/// cell's textures, whatever the volume's size.
CellsSummary exportCells(const IrradianceQuery& query, StreamedVolume& volume, const std::string& outDir,
                         const ExportOptions& options, int cellSize, uint64_t leafMemory = kCellsLeafMemory);

/// exportCells of the volume file `path`: streamed when it is large (kStreamAboveBytes) and
/// its kind streams, as `vdblight query` does, read whole otherwise; the same texels either way.
CellsSummary exportCellsOfFile(const std::string& path, const std::string& outDir, const ExportOptions& options,
                               int cellSize, uint64_t leafMemory = kCellsLeafMemory);

}  // namespace vdblight
