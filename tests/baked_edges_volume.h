// A test volume with the shadow edges and strips of a real bake, for the tests of the lookups
// that port the edge model (nanovdb_export_test, nanovdb_gpu_test).
#pragma once

#include "vdblight/volume/volume.h"

namespace vdblight::test {

/// A default-kind volume (uniform sh:4, 12 x 5 x 12 nodes, random SH and depth moments) whose
/// visibility and shadow edges are baked as `bake --direct occlusion` bakes them: under a square
/// blocker lit by a downward polygon light (penumbrae: edge widths > 0), the sun and a point
/// light (hard edges), with a thin bar whose shadow is narrower than a cell (strips: far > 0).
/// About 0.1 s.
Volume bakedEdgesVolume();

}  // namespace vdblight::test
