// Opening a .vdb with OpenVDB's delayed loading, shared by vdb_read.cpp (which owns the
// checks) and vdb_stream.cpp (which reads nodes from the result). Internal.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

#include "vdblight/volume/volume.h"

namespace vdblight {
namespace vdb_detail {

/// One level's grids, topology in memory, every leaf buffer left in the memory-mapped file
/// until first accessed.
struct DelayedLevel {
    std::vector<openvdb::GridBase::Ptr> channels;  ///< Vec3SGrid per basis channel
    std::vector<openvdb::GridBase::Ptr> depth;     ///< Vec3SGrid per depth channel, or empty
    openvdb::GridBase::Ptr mask;                   ///< BoolGrid of refined cells (not on the finest level)
};

/// A volume file opened with delayed loading: the header as readVolume would return it but
/// without node values (levels carry their GridSpec only; the direct-light list without
/// visibility), every level's grids and, in occlusion mode, level 0's visibility grids.
struct DelayedVolumeFile {
    std::unique_ptr<openvdb::io::File> file;
    Volume header;
    std::vector<DelayedLevel> levels;
    std::vector<openvdb::GridBase::Ptr> visibility;  ///< FloatGrid per listed light (bake --direct occlusion), or empty
    /// FloatGrids of the shadow edges (shadow_edges.h): every light's distance, then every
    /// light's width, then the other parts in shadow_edge::Part order (files from before the
    /// second edge have the first two only); or empty.
    std::vector<openvdb::GridBase::Ptr> edges;
};

/// Opens `path` with the checks of readVolume that need no node values (header, metadata,
/// grid types, transforms, active voxels exactly the node box of a dense level, inside it and
/// the same in every channel of a sparse one; masks placed on the level's cells; visibility
/// grids of float type placed as level 0 with exactly its nodes active). The level
/// structure (validateLevelStructure) is not checked: it needs every node's index. Throws
/// IoError / FormatError.
DelayedVolumeFile openDelayedVolume(const std::string& path);

}  // namespace vdb_detail
}  // namespace vdblight
