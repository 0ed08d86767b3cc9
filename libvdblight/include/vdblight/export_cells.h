// Textures cut into streaming cells: one texture set per cell of K x K x K lattice steps plus
// an index, as engines stream probe volumes in cells (Unity's APV bricks, Unreal's volumetric
// lightmap bricks) instead of one 3-D texture for the world.
//
// The cells tile the export lattice of exportTextures (export.h): cell (a, b, c) holds texels
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
// Sampling goes through IrradianceQuery, so a streamed volume (query_stream.h) exports cell
// by cell without being read whole.
#pragma once

#include <string>

#include "vdblight/export.h"
#include "vdblight/query.h"
#include "vdblight/vdb_stream.h"

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

/// The same for a streamed volume (vdb_stream.h) and its makeStreamingQuery, the same files:
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
