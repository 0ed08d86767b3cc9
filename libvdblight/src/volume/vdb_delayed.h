// Opening a .vdb with OpenVDB's delayed loading, shared by vdb_read.cpp (which owns the
// checks) and vdb_stream.cpp (which reads nodes from the result). Internal.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

#include "vdblight/volume.h"

namespace vdblight {
namespace vdb_detail {

/// A volume file opened with delayed loading: the header as readVolume would return it but
/// without node values (levels carry their GridSpec only; the direct-light list without
/// visibility), and, for a single-level volume without light visibility, level 0's channel
/// grids (and its four depth grids if present) with their topology read and every leaf buffer
/// left in the memory-mapped file until first accessed.
struct DelayedVolumeFile {
    std::unique_ptr<openvdb::io::File> file;
    Volume header;
    std::vector<openvdb::GridBase::Ptr> channels;  ///< Vec3SGrid per basis channel (empty for other kinds)
    std::vector<openvdb::GridBase::Ptr> depth;     ///< Vec3SGrid per depth channel, or empty
};

/// Opens `path` with the checks of readVolume that need no node values (header, metadata,
/// grid types, transforms, active voxels exactly the node box). Throws IoError / FormatError.
DelayedVolumeFile openDelayedVolume(const std::string& path);

}  // namespace vdb_detail
}  // namespace vdblight
