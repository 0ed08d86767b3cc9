// Exports shaped for one engine each: `vdblight export --preset bevy`.
//
// A preset fixes what a user would otherwise have to know about the engine: the file format
// and layout, the engine's axes and length unit (the volume itself is right-handed, +Y up, in
// metres: docs/scene.md), and how the channels are split into files. docs/engines.md gives
// the import steps.
//
//   PresetSummary s = exportBevyIrradianceVolume(readVolume("cornell.vdb"), "out/");
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/export.h"
#include "vdblight/volume.h"

namespace vdblight {

struct PresetSummary {
    TextureLattice lattice;          ///< the texel lattice, in the engine's coordinates
    std::vector<std::string> files;  ///< written files, manifest.json last, full paths
    uint64_t bytes = 0;
};

/// Bevy's IrradianceVolume texture (bevy_pbr light_probe/irradiance_volume.rs and .wgsl):
/// one ambient cube per voxel in a KTX2 Rgba16Float 3-D texture of (Rx, 2 Ry, 3 Rz) texels,
/// face +-a of voxel (x, y, z) at texel (x, y + Ry [face negative], z + a Rz), each face the
/// irradiance for that axis normal divided by pi (what Bevy multiplies by the albedo).
/// Any volume kind (sampled through IrradianceQuery).
PresetSummary exportBevyIrradianceVolume(const Volume& volume, const std::string& outDir, int resolution = 0);

/// The texel index of voxel (x, y, z)'s face (axis a, negative or not) in a Bevy texture of
/// voxel resolution r: (x, y + neg r[1], z + a r[2]), linear index x fastest.
uint64_t bevyTexelIndex(const int r[3], int x, int y, int z, int axis, bool negative);

}  // namespace vdblight
