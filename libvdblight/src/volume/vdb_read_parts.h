// The pieces the .vdb readers share (vdb_read*.cpp): a checked open of a vdblight file and
// the structural checks of its grids. Internal to the volume module.
//
// The readers are split by what they read: vdb_open.cpp opens a file and checks its header,
// size, grids' metadata lengths and tree topology counts (vdb_topology_guard.h) and content hash; vdb_read_grids.cpp checks and copies one level's grids;
// vdb_read.cpp reads complete volumes and lists a file's grids (`vdblight info`);
// vdb_read_delayed.cpp maps a volume for delayed loading (vdb_stream.h); vdb_read_tiles.cpp
// reads the tiles of a split bake (tiles.h); vdb_surface_bins.cpp a probe stage's surface bins.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

#include "content_hash.h"
#include "vdb_conventions.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/volume.h"

namespace vdblight::vdb_detail {

/// An opened vdblight file whose header and file metadata have been checked.
struct OpenedFile {
    std::unique_ptr<openvdb::io::File> file;
    openvdb::MetaMap::Ptr meta;
    int64_t version = 0;
    ContentHash hash;  ///< set when opened for Data: the hash the damage check computed (or was given)
};

/// Throws FormatError "'path' what".
[[noreturn]] void formatError(const std::string& path, const std::string& what);

/// Reads grid `name` of the file; FormatError naming the file if it cannot be read.
openvdb::GridBase::Ptr readGridChecked(OpenedFile& f, const std::string& name, const std::string& path);

/// IoError unless `path` is a readable file.
void checkReadable(const std::string& path);

template <typename T>
T requireMeta(const openvdb::MetaMap& meta, const std::string& key, const std::string& path) {
    auto m = meta.getMetadata<openvdb::TypedMetadata<T>>(key);
    if (!m) {
        formatError(path, "has no metadata " + key + " of type " + openvdb::TypedMetadata<T>::staticTypeName());
    }
    return m->value();
}

/// FormatError naming `path` unless OpenVDB can parse its structure without trusting a length
/// it cannot check: the grid table, every metadata length and every tree's root counts fit in
/// the file, and the grids end within it. OpenVDB allocates what those lengths say (a file cut
/// inside a grid's metadata made io::File::open allocate 19 GB), so every reader of a .vdb,
/// the PRT reader included, calls this before OpenVDB opens the file.
void checkNotTruncated(const std::string& path);

/// How much of a file a reader will let OpenVDB parse.
enum class OpenFor {
    Data,      ///< every grid's node data: the content hash is checked first (checkNotDamaged)
    Metadata,  ///< only the metadata and grid descriptors
    Delayed,   ///< delayed loading (vdb_stream.h): hashing the whole file is what it avoids
};

/// Opens a vdblight file after checking that it is readable, not truncated, (for Data) not
/// damaged, and of a format version this build reads. `knownHash` (purpose Data): the file's
/// content hash if the caller has it, else it is computed.
OpenedFile openVolumeFile(const std::string& path, OpenFor purpose, const ContentHash* knownHash = nullptr);

// --- One level's grids (vdb_read_grids.cpp) -----------------------------------------------

GridSpec readLevelSpec(const openvdb::MetaMap& meta, int level, const std::string& path);
/// Everything except the structural keys, prefix stripped.
Metadata userMetadata(const openvdb::MetaMap& meta);
/// True if `xf` is the linear transform placing voxel (0, 0, 0) at `at` with voxel size h.
bool placedAt(const openvdb::math::Transform& xf, const Vec3d& at, double h);
/// Throws unless `grid` is a Vec3SGrid placed as `g`.
Vec3SGrid::Ptr checkPlacedChannel(const openvdb::GridBase::Ptr& base, const GridSpec& g, const std::string& path);
/// Throws unless `grid` is a Vec3SGrid placed as `g` whose active voxels are exactly [0, dims).
Vec3SGrid::Ptr checkChannelGrid(const openvdb::GridBase::Ptr& base, const GridSpec& g, const std::string& path);
/// True if `box` is empty or inside [0, nx) x [0, ny) x [0, nz).
bool insideBox(const openvdb::CoordBBox& box, int nx, int ny, int nz);
/// Linear indices of the active voxels of `grid` (inside the level's box), ascending.
std::vector<uint64_t> activeLinear(const openvdb::GridBase& grid, const GridSpec& g);
/// A channel of a refined (sparse) level: placed as `g`, active voxels inside the box and
/// the same as the level's first channel (`first`, null for the first channel).
Vec3SGrid::Ptr checkSparseChannelGrid(const openvdb::GridBase::Ptr& base, const GridSpec& g, const Vec3SGrid* first,
                                      const std::string& path);
/// Copies the active voxels of a sparse channel into channel `channel` of level.data (whose
/// activeNodes are set).
void copySparseChannel(const Vec3SGrid& grid, VolumeLevel& level, int channel, int channels);
/// The refinement mask of level `index` (cells refined by the next level).
void readMask(OpenedFile& f, VolumeLevel& level, int index, const std::string& path);
/// A per-node scalar of a tile's nodes (tiles.h): a FloatGrid placed as the level whose
/// active voxels are exactly `level.activeNodes`; values in that order.
std::vector<float> readSparseScalar(OpenedFile& f, const std::string& name, const VolumeLevel& level,
                                    const std::string& path);
/// The direct-light mode and light list (docs/format.md, "Direct light").
void readDirectLights(OpenedFile& f, Volume& volume, const std::string& path);
/// Int64Grid `name` of the file, placed on `g`'s nodes, its active tiles voxelized; FormatError
/// naming the file if it is missing, of another type or placed elsewhere.
openvdb::Int64Grid::Ptr readPlacedInt64Grid(OpenedFile& f, const std::string& name, const GridSpec& g,
                                            const std::string& path);
/// readDirectLights plus level 0's visibility channels.
void readDirect(OpenedFile& f, Volume& volume, const std::string& path);
/// Level `level`'s depth moments.
void readDepth(OpenedFile& f, VolumeLevel& out, int level, const std::string& path);
/// One level of a complete volume: its grid, channels, validity and depth moments.
/// windowNodes > 0 (a dense one-level file): only nodes [windowFirst, windowFirst + windowNodes)
/// (VolumeLevel::windowFirst), for a stage tile that reads part of a probe stage file.
VolumeLevel readLevel(OpenedFile& f, const BasisDesc& basis, int level, const std::string& path, bool multiLevel,
                      std::size_t windowFirst = 0, std::size_t windowNodes = 0);

}  // namespace vdblight::vdb_detail
