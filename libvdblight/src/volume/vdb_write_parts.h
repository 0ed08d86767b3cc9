// The pieces of the .vdb writer (vdb_write.cpp) that the tile writers (vdb_write_tiles.cpp)
// share with it: leaf blocks, sparse grids, per-grid metadata, the depth grids and the atomic
// write of a file. Internal to the volume module.
#pragma once

#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "vdb_conventions.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight::vdb_detail {

/// Origins of the 8^3 leaf blocks overlapping the node box [0, dims) of `g`.
std::vector<Coord> leafOrigins(const GridSpec& g);

/// A per-node scalar of a sparse level (or of a tile's nodes, tiles.h): exactly the nodes of
/// `activeNodes` are active voxels, values[position * stride + offset].
openvdb::FloatGrid::Ptr buildSparseScalarGrid(const GridSpec& g, const std::vector<uint64_t>& activeNodes,
                                              const float* values, std::size_t stride, std::size_t offset);

/// Per-grid metadata, so that a grid taken out of the file still says what it holds
/// (channel -1: a grid that is no basis channel).
void tagGrid(openvdb::GridBase& grid, const Volume& volume, int level, int channel);

/// The four depth-moment grids of level `l` (depth_moments.h, docs/format.md): every node
/// active (`origins`: its leaf blocks), or with `sparse` exactly the level's activeNodes,
/// values from VolumeLevel::depth in their order.
void appendDepthGrids(const Volume& volume, int l, bool sparse, const std::vector<Coord>& origins, bool halfFloat,
                      openvdb::GridCPtrVec& grids);

/// Checks `volume` and writes it atomically with its content-derived UUID. `tile`: a partial
/// volume (tiles.h: its levels list the tile's nodes; no structure check; tile_* keys
/// allowed). `extra`: grids only a tile file carries, appended after the volume's.
/// `channels`: false for a file without the volume's grids (a photon tile).
void writeFile(const Volume& volume, const std::string& path, const WriteOptions& options, bool tile,
               const openvdb::GridCPtrVec& extra = {}, bool channels = true);

}  // namespace vdblight::vdb_detail
