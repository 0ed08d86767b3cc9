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
//   OUT/cell_<a>_<b>_<c>/<texture>.ktx2
//
// Sampling goes through IrradianceQuery, so a streamed volume (query_stream.h) exports cell
// by cell without being read whole.
#pragma once

#include <string>

#include "vdblight/export.h"
#include "vdblight/query.h"

namespace vdblight {

struct CellsSummary {
    TextureLattice lattice;    ///< the whole export lattice
    int cells[3] = {0, 0, 0};  ///< cells per axis
    std::size_t files = 0;     ///< files written (textures, manifests, cells.json)
    uint64_t bytes = 0;        ///< their total size
};

/// Writes the cells of `query`'s volume into `outDir`. `header` is the volume (or a streamed
/// volume's header, vdb_stream.h) for its basis, finest spacing and direct-light mode;
/// `cellSize` K >= 1 lattice steps per cell edge. Layouts: sh2, sh2-packed, sh1 (FormatError
/// for others and for volumes with per-light visibility, which cells do not carry; depth
/// moments are not exported per cell: manifest "depth" says so). Files are staged under
/// temporary names and renamed at the end: an error leaves no partial export.
CellsSummary exportCells(const IrradianceQuery& query, const Volume& header, const std::string& outDir,
                         const ExportOptions& options, int cellSize);

}  // namespace vdblight
