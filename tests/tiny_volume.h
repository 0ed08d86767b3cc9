// The smallest valid volume (2 x 2 x 2 nodes of SH order 2, every value 0.25) for the tests that
// write a .vdb and then damage or cut its bytes (vdb_read_hostile_test, vdb_topology_guard_test,
// cut_file_test).
#pragma once

#include <cstddef>
#include <utility>

#include "vdblight/volume/volume.h"

namespace vdblight::test {

inline Volume tinySh2Volume() {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.origin = Vec3d(0, 0, 0);
    level.grid.spacing = 0.5;
    level.grid.nx = level.grid.ny = level.grid.nz = 2;
    level.data.assign(level.grid.nodeCount() * std::size_t(v.basis.channelCount()) * 3, 0.25f);
    v.levels.push_back(std::move(level));
    return v;
}

}  // namespace vdblight::test
