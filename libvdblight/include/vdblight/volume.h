// The in-memory volume: levels of nodes, each node holding one RGB value per basis
// channel, plus the metadata that travels with it into the .vdb.
//
// Storage in memory is plain arrays (fast to fill in parallel, no OpenVDB types in the
// public API); vdb_io.h turns a Volume into OpenVDB grids and back (docs/format.md).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "vdblight/basis_desc.h"
#include "vdblight/direct_light.h"
#include "vdblight/depth_moments.h"
#include "vdblight/level_topology.h"
#include "vdblight/math.h"
#include "vdblight/surface_bin_sums.h"

namespace vdblight {

/// Format version written as vdblight:format_version. Bumped on incompatible changes.
constexpr int kFormatVersion = 1;

using MetaValue = std::variant<std::string, int64_t, double>;
/// Metadata keys without the "vdblight:" prefix that the file adds.
using Metadata = std::map<std::string, MetaValue>;

/// A level: its topology (grid, active nodes, refined cells; level_topology.h) plus the
/// channels stored at its nodes.
struct VolumeLevel : LevelTopology {
    /// Node-major: data[(node * channels + c) * 3 + rgb], node = grid.index(i, j, k).
    std::vector<float> data;
    /// Optional, empty or one value per node in [0, 1]: the fraction of the node's
    /// trilinear basis-function weight that lay in the domain of interest when it was baked
    /// (bake_antialiased.h); written as the FloatGrid `validity` (docs/format.md).
    std::vector<float> validity;
    /// Optional, empty or depth::kFloatsPerNode floats per stored node (same order as
    /// `data`): the depth moments a lookup weights corners with so that it does not
    /// interpolate across walls (depth_moments.h; grids depth_* in docs/format.md).
    std::vector<float> depth;
    /// Direct light in occlusion mode (Volume::direct), level 0 only: per node, the visibility
    /// (0..1) of each listed light, node-major: [node * lights + i]; written as the FloatGrids
    /// `light_visibility_<i>` (docs/format.md). Empty in the other modes.
    std::vector<float> lightVisibility;
    /// Optional beside lightVisibility, empty or shadow_edge::kFloatsPerLight floats per node
    /// and light: [(node * lights + i) * 2 + {0: distance, 1: width}] (shadow_edges.h); written
    /// as the FloatGrids `light_edge_distance_<i>` and `light_edge_width_<i>`.
    std::vector<float> lightShadowEdges;
    /// A tile's bake (tiles.h) holds only the window of stored positions that its nodes span:
    /// `data`, `depth` and `lightVisibility` then hold positions [windowFirst, windowFirst +
    /// windowNodes) (position n at n - windowFirst), so that a tile allocates memory for about
    /// its own nodes, not the whole volume's. windowNodes 0 (complete volumes): every position.
    std::size_t windowFirst = 0;
    std::size_t windowNodes = 0;
    /// Positions the per-node arrays hold.
    std::size_t heldNodes() const { return windowNodes ? windowNodes : storedNodes(); }
    /// Index in the per-node arrays of stored position `node` (inside the window).
    std::size_t held(std::size_t node) const { return node - windowFirst; }
    const float* nodeData(std::size_t node, int channels) const { return data.data() + held(node) * channels * 3; }
    bool hasDepth() const { return !depth.empty(); }
    const float* nodeDepth(std::size_t node) const { return depth.data() + held(node) * depth::kFloatsPerNode; }
};

struct Volume {
    BasisDesc basis;
    std::vector<VolumeLevel> levels;  ///< level 0 is the coarsest (a uniform volume has one)
    Metadata meta;
    /// How direct light is stored (`bake --direct`): mode and listed lights (direct_light.h).
    DirectLightSet direct;
    /// A probe stage volume of a bake with --probe-cache surface: its bins' sums (else null).
    std::shared_ptr<const SurfaceBinSums> surfaceBins;

    /// Throws FormatError if levels, grids and data sizes are inconsistent, or if the level
    /// structure of a multi-level volume is (validateLevelStructure below).
    void validate() const;
    /// Refinement factor K between consecutive levels (1 for a single-level volume).
    int refineFactor() const;
    /// True if every level carries depth moments (VolumeLevel::depth).
    bool hasDepth() const;
};

/// The level-structure part of Volume::validate: level 0 dense; for several levels, every
/// level's spacing h0 / K^l with one integer K >= 2, the same origin, dims (n - 1) K + 1,
/// refined cells inside the box and under a refined parent, and active nodes exactly the
/// corners of the children of the coarser level's refined cells. Throws FormatError naming
/// the first problem.
void validateLevelStructure(const Volume& volume);

/// Levels with the given topology (a placed layout's, LevelLayout::levels) and no data yet.
std::vector<VolumeLevel> volumeLevels(const std::vector<LevelTopology>& topology);

/// Sets every seam node of levels 1.. (coarse to fine) to the coarser level's trilinear
/// interpolation at its position (seams: layout_levels.h; stencils: seamStencils).
/// Requires a structurally valid volume with filled data.
void applySeamConstraints(Volume& volume);

/// Places a volume baked in a scene's local frame into the world: adds `origin` to every
/// level's grid origin (double) and moves its listed direct lights. The .vdb written from it
/// maps index space to world space (scene_origin.h, docs/scene.md "Large coordinates").
void placeVolumeInWorld(Volume& volume, const Vec3d& origin);

/// Reads a metadata value (with conversion between int and double), or `fallback`.
double metaNumber(const Metadata& meta, const std::string& key, double fallback);
std::string metaString(const Metadata& meta, const std::string& key, const std::string& fallback = {});

}  // namespace vdblight
