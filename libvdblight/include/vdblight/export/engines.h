// The export module's files for one engine or viewer each: engine presets and Bevy (below),
// three.js's probe grid, NanoVDB, the glTF probe view.
//
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

#include "vdblight/export/export.h"
#include "vdblight/volume/volume.h"

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
/// writes (export/engines.h).
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

// ---------------------------------------------------------------------------------------------
// The probe grid of three.js's LightProbeGridWebGL (npm `three` 0.187.0, r187,
// examples/jsm/lighting/LightProbeGridWebGL.js): `vdblight export --format three`.
//
// That class keeps L2 SH probes in one RGBA 3-D atlas of seven packed sub-volumes stacked
// along z, each with one padding slice (a copy of its first / last data slice) at both ends:
// nx x ny x 7 (nz + 2) texels. Sub-volume t holds components 4t .. 4t + 3 of the 27 floats
// c0.rgb, c1.rgb, ..., c8.rgb (the last alpha is 0). Its shader evaluates
//   E(n) = 0.886227 c0 + 1.023328 (c1 y + c2 z + c3 x) + ...  =  sum_j A_l(j) c_j Y_j(n),
// so c_j are radiance SH coefficients in docs/format.md's convention (orthonormal, no
// Condon-Shortley phase, j = l (l + 1) + m): the volume's bands 0..2 go in unchanged.
// The probes are export's lattice (the volume's nodes by default) plus one border probe on
// each side of every axis, a spacing outside, holding the edge node's value: between them
// three's trilinear filtering is the volume's trilinear interpolation, and beyond the nodes
// it gives what `query` gives there (the clamped value). Three puts probes at cell centres
// (a grid of width w and n probes has them at x0 + (i + 1/2) w / n), so the grid's box is
// the node box grown by 1.5 spacings: it covers the scene that a default bake's nodes (its
// bounds inset by half a spacing) leave a thin band of near the walls, which three would
// leave unlit (it lights only fragments whose sample point lies in the box).
//
//   ThreeGridSummary s = exportThreeGrid(readVolume("cornell.vdb"), "web/", {});
//   // web/probe_grid_sh.bin (the atlas texels) + web/probe_grid.json (bounds, resolution)

namespace vdblight {

struct ThreeGridOptions {
    bool halfFloat = true;           ///< HalfFloatType texels (default; 8 B per texel) or FloatType (16 B)
    int resolution = 0;              ///< probes along the longest axis; 0: the finest node spacing
    uint64_t maxBytes = 4ull << 30;  ///< refuse exports needing more memory than this
};

struct ThreeGridSummary {
    TextureLattice lattice;          ///< the probe points: export's lattice and one border probe per side
    int atlasDepth = 0;              ///< 7 (nz + 2)
    std::vector<std::string> files;  ///< probe_grid_sh.bin, probe_grid.json (full paths)
    uint64_t bytes = 0;
    int foldedLights = 0;            ///< lights whose direct light was folded into the SH (occlusion volumes)
};

/// The file names written into the output directory.
constexpr const char* kThreeGridAtlasFile = "probe_grid_sh.bin";
constexpr const char* kThreeGridJsonFile = "probe_grid.json";

/// Packs nine SH order-2 coefficient textures (RGB + unused alpha each, x fastest, as the
/// `sh2` layout samples them) of a dims[0] x dims[1] x dims[2] lattice into the atlas:
/// 4 floats per texel, dims[0] x dims[1] x 7 (dims[2] + 2) texels, x fastest, then y, then
/// the atlas slice.
std::vector<float> packThreeGridAtlas(const std::vector<std::vector<float>>& sh2Textures, const int dims[3]);

/// Writes probe_grid_sh.bin (the atlas as little-endian half or float RGBA, no header) and
/// probe_grid.json (what LightProbeGridWebGL needs: bounds, resolution, texel type; docs/engines.md)
/// into `outDir` (created if missing), all or nothing. The volume must hold real SH of order
/// >= 2 (sh2, sh:N; bands above 2 are left out, as `query --sh-order 2` does); FormatError
/// otherwise, and for a `--direct runtime` volume (its lights need the scene at run time). An
/// occlusion volume's listed lights (the default bake) have their direct light folded into
/// the probes' SH bands 0..2 (the query's exact direct light x visibility, fitted per probe;
/// probe_grid.json's "direct_light" names them). ValueError for an axis with a single probe, values beyond the half range, or
/// memory above maxBytes; IoError if the directory cannot be written.
ThreeGridSummary exportThreeGrid(const Volume& volume, const std::string& outDir, const ThreeGridOptions& options);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
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
    kDirectMode = 6,     ///< 0 baked, 1 runtime, 2 occlusion (light/direct_light.h)
    kLights = 7,         ///< listed lights (text in the blind data)
    kVisibility = 8,     ///< light visibility arrays after level 0's channel arrays (occlusion mode)
    kValidity = 9,       ///< 1 if every level has a `validity` grid
    kDimsX = 10,         ///< level 0's nodes along x, y, z
    kDimsY = 11,
    kDimsZ = 12,
    kShKind = 13,        ///< 0: sh:N; 1: sh2 (its lookup folds A_l into the coefficients first: other bits)
    kShadowEdges = 14,   ///< 0 none; 1 per light an edge distance and width array after the visibility
                         ///< arrays; 2 also per light a strip array (direction xyz, far) after those
    kFrame = 15,         ///< the voxel where level 0's exact frame starts (kFrameFloats numbers), 0 in
                         ///< files written before it: origin x y z rounded to float, origin minus
                         ///< that (x y z), spacing as s1 + s2 + s3 (s1, s2 of at most 12 significant
                         ///< bits, so that node index times either is exact in float), 1 / spacing
    kFieldCount = 16,
};
constexpr int kFrameFloats = 10;
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

// ---------------------------------------------------------------------------------------------
// A probe view any DCC opens: `vdblight export --format gltf` writes a glTF 2.0 binary (.glb)
// with one small sphere per node, coloured per vertex by the irradiance for that vertex's
// normal (so a sphere shows where the light comes from), and the volume's box as lines.
//
//   GltfProbeOptions o;
//   o.every = 4;  // every 4th node along each axis
//   exportGltfProbes(readVolume("office.vdb"), "office_probes.glb", o);

namespace vdblight {

struct GltfProbeOptions {
    int every = 0;          ///< keep nodes whose (i, j, k) are all multiples of `every` (0 or 1: all)
    int sliceAxis = -1;     ///< 0, 1, 2: keep only the nodes of each level on the plane nearest `sliceAt`
    double sliceAt = 0;     ///< world coordinate of the slice plane along sliceAxis
    double radius = 0;      ///< sphere radius; 0: 0.2 of each level's node spacing
    /// Without `every` or a slice, a volume with more nodes than this is refused (one line
    /// naming --every and --slice): a sphere per node of a million-node volume is a file of
    /// gigabytes that no DCC opens comfortably.
    uint64_t maxSpheresWithoutDecimation = 100000;
    uint64_t maxSpheres = 2000000;  ///< refused above this even with decimation (names --every)
};

struct GltfProbeSummary {
    uint64_t spheres = 0;
    uint64_t bytes = 0;
    double colourScale = 0;  ///< vertex colour = clamp(colourScale * E(n) / pi, 0, 1)
};

/// Writes the .glb to `path` (atomically: a temporary file renamed at the end). Colours: the
/// irradiance E(x_node, n_vertex) of the library's query, divided by pi (the radiance of a
/// white Lambertian surface there) and scaled by one factor for the file so that the
/// brightest channel is 1 (glTF's COLOR_0 is linear, in [0, 1]); the factor is in the file's
/// scene extras (`vdblight.colour_scale`). Throws ValueError for a refused size or bad option
/// and IoError if the file cannot be written.
GltfProbeSummary exportGltfProbes(const Volume& volume, const std::string& path, const GltfProbeOptions& options);

}  // namespace vdblight
