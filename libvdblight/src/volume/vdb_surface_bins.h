// `--probe-cache surface`'s bins in a probe stage file (SurfaceBinSums, surface_bin_sums.h;
// docs/format.md): written by vdb_write.cpp's grids, read by the stage and tile readers.
// Internal to the volume module.
#pragma once

#include <string>

#include <openvdb/openvdb.h>

#include "vdb_read_parts.h"
#include "vdblight/volume/volume.h"

namespace vdblight::vdb_detail {

/// Appends `sums` as one Int64Grid per value (surfaceBinGridName), active at the cells of
/// `grid` whose bin has samples, holding the unsigned sums' bits as int64.
void appendSurfaceBinGrids(const SurfaceBinSums& sums, const GridSpec& grid, openvdb::GridCPtrVec& grids);

/// Sets volume.surfaceBins from the file's grids if it has them (level 0 must be read).
void readSurfaceBins(OpenedFile& f, Volume& volume, const std::string& path);

}  // namespace vdblight::vdb_detail
