// A baked volume as one NanoVDB file (`.nvdb`) for GPU renderers that read sparse volumes
// (`vdblight export VOLUME -o out.nvdb --format nanovdb`; docs/engines.md, "NanoVDB").
//
// Each level becomes one UInt32 grid `vdblight_nodes` with the `.vdb`'s transform and active
// voxels (docs/format.md), whose value is the node's index into the level's channels: float
// arrays in the grid's blind data, channel-major (basis channels, depth moments, then the light
// visibility on level 0), so that every channel shares one tree (a NanoVDB 32.4 tree costs
// hundreds of KB of dense internal tables: one grid per channel made the file 4.6x larger).
// The refined-cell masks of a multi-level volume and the validity stay float grids. The first grid, `vdblight_meta`, says what a lookup needs as numbers in its voxels
// (basis order, levels, refinement, depth, direct mode, lights) and carries the volume's
// metadata as text in its blind data (lights in the one-line form of docs/format.md). The
// grids follow in a fixed order, so that a shader finds them by walking the buffer
// (shaders/vdblight_nanovdb.h, written on PNanoVDB.h, evaluates irradiance as `query` does).
//
//   NanoVdbSummary s = exportNanoVdb(readVolume("room.vdb"), "room.nvdb");
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/volume.h"

namespace vdblight {

/// The numbers in voxels (i, 0, 0) of the grid `vdblight_meta`, by i (docs/engines.md).
namespace nanovdb_meta {
enum Field : int {
    kVersion = 0,        ///< 2 (1: one grid per channel)
    kShOrder = 1,        ///< N for basis sh:N (2 for sh2); -1 for a basis that is not real SH
    kChannels = 2,       ///< basis channels (RGB arrays per level)
    kLevels = 3,         ///< levels (1: uniform)
    kRefine = 4,         ///< refinement factor K between levels (1 for one level)
    kDepth = 5,          ///< 1 if every level has the four depth-moment arrays
    kDirectMode = 6,     ///< 0 baked, 1 runtime, 2 occlusion (direct_light.h)
    kLights = 7,         ///< listed lights (text in the blind data)
    kVisibility = 8,     ///< light visibility arrays after level 0's channel arrays (occlusion mode)
    kValidity = 9,       ///< 1 if every level has a `validity` grid
    kDimsX = 10,         ///< level 0's nodes along x, y, z
    kDimsY = 11,
    kDimsZ = 12,
    kShKind = 13,        ///< 0: sh:N; 1: sh2 (its lookup folds A_l into the coefficients first: other bits)
    kFieldCount = 16,    ///< 14, 15 reserved (0)
};
/// The listed lights as numbers, for a shader: light i's record of kLightFloats values starts at
/// voxel kFieldCount + kLightFloats i: kind (0 point, 1 spot, 2 directional, 3 polygon, 4 mesh),
/// two-sided (0/1), value (3), position (3), direction (3), cos inner, cos outer, normal (3),
/// the voxel where its loops start, the loop count, 2 reserved. Each loop there: its vertex
/// count, then x, y, z per vertex (world positions, as in the file's text).
constexpr int kLightFloats = 20;
constexpr int kVersionValue = 2;
}  // namespace nanovdb_meta

struct NanoVdbSummary {
    std::vector<std::string> grids;  ///< grid names in file order
    uint64_t activeNodes = 0;        ///< stored nodes over all levels
    uint64_t bytes = 0;              ///< size of the written file
};

/// Writes `file` (atomically: a temporary file renamed at the end, so an error leaves no
/// file). Throws ValueError for a volume with no stored node (an empty volume: nothing to
/// look up), FormatError for an inconsistent volume (Volume::validate) or a tile's window,
/// IoError if the file cannot be written.
NanoVdbSummary exportNanoVdb(const Volume& volume, const std::string& file);

}  // namespace vdblight
