// The volume module's in-memory data, in three parts: the surface bins' exact sums (below),
// the Volume itself, and the error summaries bakes and merges write into its metadata.
//
// `bake --probe-cache surface`'s bins (bake/surface_bins.h) as exact integer sums, which a
// probe stage volume carries from stage 0 through the merge to stage 1 (volume/tiles.h, "Staged
// bakes"): integers add exactly in any order, so the merge of the tiles' sums is the whole
// bake's.
//
// Sparse: only the cells that hold samples are listed. The samples lie on surfaces, so a bake
// touches a thin shell of its cells, and a tile only the cells its own nodes' paths reached;
// a dense array would cost every tile the whole grid's bins (issue 15, tile memory).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/layout/layout.h"
#include "vdblight/core/math.h"

namespace vdblight {

/// Cells of the node grid: cell (i, j, k) spans nodes i..i+1, j..j+1, k..k+1, linear index
/// (k * cy + j) * cx + i. Per cell kBinsPerCell bins (the normal's signed axis: 2a for +a,
/// 2a + 1 for -a), per bin kValuesPerBin values: the irradiance sums r, g, b in units of
/// `unit`, the sample count, the position sums x, y, z (SurfaceBins' fixed point).
struct SurfaceBinSums {
    static constexpr int kValuesPerBin = 7;
    static constexpr int kBinsPerCell = 6;
    static constexpr int kValuesPerCell = kValuesPerBin * kBinsPerCell;
    /// Irradiance per integer step.
    double unit = 0;
    /// The listed cells' linear indices, strictly ascending.
    std::vector<uint64_t> cellIndices;
    /// kValuesPerCell values per listed cell, in cellIndices' order: bin `face`'s values start
    /// at face * kValuesPerBin.
    std::vector<uint64_t> values;

    /// The cells of `grid` along each axis (at least one).
    static std::array<int, 3> cells(const GridSpec& grid) {
        return {std::max(1, grid.nx - 1), std::max(1, grid.ny - 1), std::max(1, grid.nz - 1)};
    }
    static uint64_t cellCount(const std::array<int, 3>& cells) {
        return uint64_t(cells[0]) * uint64_t(cells[1]) * uint64_t(cells[2]);
    }
    /// The linear index of cell (i, j, k), which must lie inside `cells`.
    static uint64_t cellIndex(const std::array<int, 3>& cells, int i, int j, int k) {
        return (uint64_t(k) * uint64_t(cells[1]) + uint64_t(j)) * uint64_t(cells[0]) + uint64_t(i);
    }
    /// Cell (i, j, k) of linear index `index`.
    static std::array<int, 3> cellCoord(const std::array<int, 3>& cells, uint64_t index) {
        const uint64_t cx = uint64_t(cells[0]), cy = uint64_t(cells[1]);
        return {int(index % cx), int(index / cx % cy), int(index / (cx * cy))};
    }

    /// Adds `other`'s sums (exact; the union of the listed cells). ValueError if the units
    /// differ.
    void add(const SurfaceBinSums& other);
    /// ValueError unless the unit is positive and finite, the indices ascend strictly and lie
    /// inside `cells`, and `values` has kValuesPerCell per listed cell.
    void validate(const std::array<int, 3>& cells) const;
};

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The in-memory volume: levels of nodes, each node holding one RGB value per basis
// channel, plus the metadata that travels with it into the .vdb.
//
// Storage in memory is plain arrays (fast to fill in parallel, no OpenVDB types in the
// public API); volume/vdb_io.h turns a Volume into OpenVDB grids and back (docs/format.md).

namespace vdblight {

/// Format version written as vdblight:format_version. Bumped on incompatible changes.
constexpr int kFormatVersion = 1;

using MetaValue = std::variant<std::string, int64_t, double>;
/// Metadata keys without the "vdblight:" prefix that the file adds.
using Metadata = std::map<std::string, MetaValue>;

/// A level: its topology (grid, active nodes, refined cells; layout/layout.h) plus the
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
    /// interpolate across walls (basis/depth_moments.h; grids depth_* in docs/format.md).
    std::vector<float> depth;
    /// Direct light in occlusion mode (Volume::direct), level 0 only: per node, the visibility
    /// (0..1) of each listed light, node-major: [node * lights + i]; written as the FloatGrids
    /// `light_visibility_<i>` (docs/format.md). Empty in the other modes.
    std::vector<float> lightVisibility;
    /// Optional beside lightVisibility, empty or shadow_edge::kFloatsPerLight floats per node
    /// and light: [(node * lights + i) * 2 + {0: distance, 1: width}] (shadow_edges.h); written
    /// as the FloatGrids `light_edge_distance_<i>` and `light_edge_width_<i>`.
    std::vector<float> lightShadowEdges;
    /// A tile's bake (volume/tiles.h) holds only the window of stored positions that its nodes span:
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
    /// How direct light is stored (`bake --direct`): mode and listed lights (light/direct_light.h).
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
/// interpolation at its position (seams: layout/layout.h; stencils: seamStencils).
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

// ---------------------------------------------------------------------------------------------
// The metadata summaries of per-node statistics that the point gathers write (bake/each_pass.h,
// bake/each_pass.h) and that a merge of tiles (volume/tiles.h) recomputes from the tiles' per-node
// values: one function for both, so that the merged file has the single bake's bytes.

namespace vdblight {

/// The per-node error value of a node that no lookup in free space reads: a node inside a
/// solid (most of its first hits are back faces, insideSolidByBackFaces) of a volume whose
/// depth weights (basis/depth_moments.h) keep it out of every lookup from open space. Its noise
/// is large (almost no light reaches it) and says nothing about what a user sees, so the
/// summaries leave it out and count it instead (issue 29). Negative: no real error is.
constexpr float kNodeInsideSolid = -1.0f;

/// True if more than half of a node's `rays` first hits were back faces: the node lies inside
/// closed geometry (the test of prt/prt.h's insideSolid and of the domain of interest, applied to
/// the gather's own first hits).
inline bool insideSolidByBackFaces(uint32_t backFaceHits, uint32_t rays) {
    return 2 * uint64_t(backFaceHits) > uint64_t(rays);
}

/// q-quantile (0..1, nearest rank) of the values that are not kNodeInsideSolid (any negative);
/// 0 if there are none.
double errorQuantile(const std::vector<float>& values, double q);

/// The per-node error summary (one value per node of `grid`, node order) over the nodes that
/// free-space lookups read: error_estimate (what it is), estimated_error_p50 / _p95 / _max
/// and estimated_error_worst_nodes ("i,j,k:error;..." for the five worst nodes, ties by node
/// index); nodes_inside_solids counts the kNodeInsideSolid nodes left out (written only if
/// there are any).
void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid);

/// How many of `values` are kNodeInsideSolid (negative).
std::size_t nodesInsideSolids(const std::vector<float>& values);

/// The sample summary of an error-targeted bake from its metadata samples_total, nodes and
/// max_rays: rays_per_node_mean and samples_saved_vs_max.
void addSampleSummary(Metadata& m);

}  // namespace vdblight
