// Exports shaped for one engine each: `vdblight export --preset unity|unreal|godot|three|bevy`.
//
// A preset fixes what a user would otherwise have to know about the engine: the file format
// and layout, the engine's axes and length unit (the volume itself is right-handed, +Y up, in
// metres: docs/scene.md), and how the channels are split into files. docs/engines.md gives
// the import steps per engine.
//
//   PresetSummary s = exportPreset(readVolume("cornell.vdb"), "out/", EnginePreset::Bevy);
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/export.h"
#include "vdblight/volume.h"

namespace vdblight {

enum class EnginePreset { Unity, Unreal, Godot, Three, Bevy };

/// Parses "unity" | "unreal" | "godot" | "three" | "bevy" (ValueError listing them otherwise).
EnginePreset parseEnginePreset(const std::string& name);
const char* presetName(EnginePreset preset);

/// An engine's axes and length unit relative to the volume's frame (right-handed, +Y up,
/// metres): engine coordinate a = metresToUnit * sign[a] * volume coordinate axis[a].
/// Directions (normals) map the same way without the scale.
struct EngineFrame {
    int axis[3] = {0, 1, 2};
    int sign[3] = {1, 1, 1};
    double metresToUnit = 1.0;
    const char* description = "right-handed, +Y up, metres";
    Vec3d point(const Vec3d& volumePoint) const;      ///< a volume point in engine coordinates
    Vec3d direction(const Vec3d& volumeDir) const;    ///< a volume direction in engine axes
    Vec3d volumeDirection(const Vec3d& engineDir) const;  ///< the inverse of direction()
};
/// Unity: left-handed, +Y up, metres (x negated: glTF's right is -X, Unity's +X).
/// Unreal: left-handed, +Z up, centimetres (x = volume z, y = -volume x, z = volume y).
/// Godot, three.js, Bevy: right-handed, +Y up, metres (the volume's own frame).
EngineFrame engineFrame(EnginePreset preset);

struct PresetSummary {
    TextureLattice lattice;          ///< the texel lattice, in the engine's coordinates
    std::vector<std::string> files;  ///< written files, manifest.json last, full paths
    uint64_t bytes = 0;
    int foldedLights = 0;            ///< lights whose direct light was folded into the SH (occlusion volumes)
};

/// Writes the preset's files and manifest.json into `outDir`, all or nothing (staged and
/// renamed as `exportTextures` does). `resolution`: texels along the longest axis (0: the
/// finest node spacing). Throws FormatError when the preset cannot take the volume's basis
/// (the SH presets, three included, need an SH volume of order >= 2, and refuse a `--direct
/// runtime` volume with lights), ValueError / IoError as exportTextures. The SH presets fold an
/// occlusion volume's listed lights into the SH (the query's direct light fitted per texel onto
/// bands 0..2; the manifest's "direct_light" names them). `three` writes what exportThreeGrid
/// writes (export_three.h).
PresetSummary exportPreset(const Volume& volume, const std::string& outDir, EnginePreset preset, int resolution = 0);

/// Bevy's IrradianceVolume texture (bevy_pbr light_probe/irradiance_volume.rs and .wgsl):
/// one ambient cube per voxel in a KTX2 Rgba16Float 3-D texture of (Rx, 2 Ry, 3 Rz) texels,
/// face +-a of voxel (x, y, z) at texel (x, y + Ry [face negative], z + a Rz), each face the
/// irradiance for that axis normal divided by pi (what Bevy multiplies by the albedo).
/// Any volume kind (sampled through IrradianceQuery). Part of exportPreset(Bevy).
PresetSummary exportBevyIrradianceVolume(const Volume& volume, const std::string& outDir, int resolution = 0);

/// The texel index of voxel (x, y, z)'s face (axis a, negative or not) in a Bevy texture of
/// voxel resolution r: (x, y + neg r[1], z + a r[2]), linear index x fastest.
uint64_t bevyTexelIndex(const int r[3], int x, int y, int z, int axis, bool negative);

}  // namespace vdblight
