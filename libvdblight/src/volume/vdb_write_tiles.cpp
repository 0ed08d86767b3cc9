// Tile files (tiles.h, docs/format.md "Tiles"): writeTile writes a gather tile's nodes as
// sparse grids of every level, writePhotonTile a photon tile's exact sums (photon_sums.h).
// Read back by vdb_read_tiles.cpp, merged by merge.cpp.
#include <algorithm>
#include <memory>

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include "vdb_conventions.h"
#include "vdb_write_parts.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/volume/tiles.h"
#include "basis/shadow_edges.h"

namespace vdblight {
using namespace vdb_detail;

void writeTile(const Volume& volume, const NodeMask& mask, const TileId& id, const std::string& path,
               const WriteOptions& options, const TileNodeStats* stats) {
    try {
        volume.validate();
    } catch (const FormatError& e) {
        throw ValueError(std::string("invalid volume: ") + e.what());
    }
    if (mask.size() != volume.levels.size()) throw ValueError("the tile's node mask does not match the volume's levels");
    if (id.count < 1 || id.index < 0 || id.index >= id.count || id.paramsHash.empty())
        throw ValueError("invalid tile identity " + std::to_string(id.index) + " of " + std::to_string(id.count));
    const std::size_t floats = std::size_t(volume.basis.channelCount()) * 3;
    const std::size_t lights = volume.direct.lights.size();
    const bool depth = volume.hasDepth();
    const bool error = stats && !stats->estimatedError.empty();
    if (error && (volume.levels.size() != 1 || stats->estimatedError.size() != volume.levels[0].heldNodes()))
        throw ValueError("the tile's per-node errors do not match the volume's nodes");
    const bool firstPass = stats && !stats->firstPassError.empty();
    if (firstPass && (!error || stats->firstPassError.size() != volume.levels[0].heldNodes() ||
                      stats->firstPassValues.size() != volume.levels[0].heldNodes() * floats))
        throw ValueError("the tile's pass-0 values do not match the volume's nodes");
    Volume part;
    part.basis = volume.basis;
    part.meta = volume.meta;
    part.direct = volume.direct;  // the light list; level 0's visibility of the tile's nodes below
    part.surfaceBins = volume.surfaceBins;  // a stage-0 tile's bins: the whole grid's, of its nodes' paths
    std::string dense;
    int64_t nodes = 0;
    std::vector<float> tileError, tileFirstError, tileFirstValues;
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const VolumeLevel& full = volume.levels[l];
        if (!full.validity.empty()) throw ValueError("a volume with validity (the anti-aliased pass) cannot be tiled");
        if (mask[l].size() != full.storedNodes()) throw ValueError("the tile's node mask does not match level " + std::to_string(l));
        // The volume may hold only the tile's window of nodes (VolumeLevel::windowFirst): it must
        // cover the mask.
        for (std::size_t n = 0; n < mask[l].size(); ++n)
            if (mask[l][n] && (n < full.windowFirst || n - full.windowFirst >= full.heldNodes()))
                throw ValueError("the tile's nodes lie outside the nodes the volume holds (level " + std::to_string(l) + ")");
        const bool visibility = !full.lightVisibility.empty(), edges = !full.lightShadowEdges.empty();
        const std::size_t edgeFloats = lights * shadow_edge::kFloatsPerLight;
        VolumeLevel level;
        level.grid = full.grid;
        level.refinedCells = full.refinedCells;
        for (std::size_t n = 0; n < mask[l].size(); ++n) {
            if (!mask[l][n]) continue;
            level.activeNodes.push_back(full.sparse() ? full.activeNodes[n] : n);
            level.data.insert(level.data.end(), full.nodeData(n, volume.basis.channelCount()),
                              full.nodeData(n, volume.basis.channelCount()) + floats);
            if (depth) level.depth.insert(level.depth.end(), full.nodeDepth(n), full.nodeDepth(n) + depth::kFloatsPerNode);
            if (visibility)
                level.lightVisibility.insert(level.lightVisibility.end(),
                                             full.lightVisibility.begin() + std::ptrdiff_t(full.held(n) * lights),
                                             full.lightVisibility.begin() + std::ptrdiff_t((full.held(n) + 1) * lights));
            if (edges)
                level.lightShadowEdges.insert(level.lightShadowEdges.end(),
                                              full.lightShadowEdges.begin() + std::ptrdiff_t(full.held(n) * edgeFloats),
                                              full.lightShadowEdges.begin() + std::ptrdiff_t((full.held(n) + 1) * edgeFloats));
            if (error) tileError.push_back(stats->estimatedError[full.held(n)]);
            if (firstPass) {
                tileFirstError.push_back(stats->firstPassError[full.held(n)]);
                const auto from = stats->firstPassValues.begin() + std::ptrdiff_t(full.held(n) * floats);
                tileFirstValues.insert(tileFirstValues.end(), from, from + std::ptrdiff_t(floats));
            }
        }
        nodes += int64_t(level.activeNodes.size());
        dense += std::string(l ? "," : "") + (full.sparse() ? "0" : "1");
        part.levels.push_back(std::move(level));
    }
    part.meta["tile_index"] = int64_t(id.index);
    part.meta["tile_count"] = int64_t(id.count);
    part.meta["tile_params_hash"] = id.paramsHash;
    part.meta["tile_dense_levels"] = dense;
    part.meta["tile_nodes"] = nodes;
    part.meta["tile_half_float"] = int64_t(options.halfFloat ? 1 : 0);
    part.meta["tile_reproducible"] = int64_t(options.reproducible ? 1 : 0);
    part.meta["tile_depth"] = int64_t(depth ? 1 : 0);
    part.meta["tile_visibility"] = int64_t(volume.levels[0].lightVisibility.empty() ? 0 : 1);
    part.meta["tile_shadow_edges"] = int64_t(volume.levels[0].lightShadowEdges.empty() ? 0 : 1);
    part.meta["tile_estimated_error"] = int64_t(error ? 1 : 0);
    part.meta["tile_first_pass_floats"] = int64_t(firstPass ? floats : 0);
    openvdb::GridCPtrVec extra;
    // A per-node scalar of the tile's level-0 nodes, values[position * stride + offset].
    const auto addScalar = [&](const std::string& name, const std::vector<float>& values, std::size_t stride,
                               std::size_t offset) {
        const VolumeLevel& level = part.levels[0];
        openvdb::FloatGrid::Ptr grid = buildSparseScalarGrid(level.grid, level.activeNodes, values.data(), stride, offset);
        grid->setName(name);
        grid->setTransform(levelTransform(level.grid));
        grid->setGridClass(openvdb::GRID_UNKNOWN);
        tagGrid(*grid, part, 0, -1);
        extra.push_back(grid);
    };
    // The per-node error the bake summarised over its nodes only: the merge summarises the
    // whole volume's (error_summary.h). Full floats: the summary prints them.
    if (error && !tileError.empty()) addScalar(kTileErrorName, tileError, 1, 0);
    if (firstPass && !tileFirstError.empty()) {
        addScalar(kTileFirstPassErrorName, tileFirstError, 1, 0);
        for (std::size_t f = 0; f < floats; ++f) addScalar(kTileFirstPassPrefix + std::to_string(f), tileFirstValues, floats, f);
    }
    // Full floats whatever the merged file will use: the merge interpolates seams from these
    // values, which must be the single bake's, not their half-float roundings.
    WriteOptions full = options;
    full.halfFloat = false;
    writeFile(part, path, full, true, extra);
}

namespace {
/// One 64-bit word of value v (0..53, the volume's float order 9 d + f) of every node's photon
/// sums, as an Int64Grid whose voxels are all active (zeros included), like the channel grids.
openvdb::Int64Grid::Ptr buildPhotonSumGrid(const PhotonSums& sums, const std::vector<Coord>& origins, int v, bool high) {
    using Int64LeafT = openvdb::Int64Grid::TreeType::LeafNodeType;
    const GridSpec& g = sums.grid;
    const PhotonSumLayout layout(g);
    const int d = v / 9, f = v % 9;
    std::vector<std::unique_ptr<Int64LeafT>> leaves(origins.size());
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t n) {
        const Coord o = origins[n];
        auto leaf = std::make_unique<Int64LeafT>(o, openvdb::Int64(0), false);
        for (int z = o.z(); z < std::min(o.z() + kLeafDim, g.nz); ++z)
            for (int y = o.y(); y < std::min(o.y() + kLeafDim, g.ny); ++y)
                for (int x = o.x(); x < std::min(o.x() + kLeafDim, g.nx); ++x) {
                    // Two's complement words: the value is hi * 2^64 + (unsigned) lo.
                    const unsigned __int128 u = (unsigned __int128)sums.values[layout.offset(d, x, y, z) + std::size_t(f)];
                    const uint64_t word = high ? uint64_t(u >> 64) : uint64_t(u);
                    leaf->setValueOn(Int64LeafT::coordToOffset(Coord(x, y, z)), openvdb::Int64(word));
                }
        leaves[n] = std::move(leaf);
    });
    auto grid = openvdb::Int64Grid::create(openvdb::Int64(0));
    for (auto& leaf : leaves) grid->tree().addLeaf(leaf.release());
    return grid;
}
}  // namespace

void writePhotonTile(const PhotonSums& sums, const Metadata& meta, const TileId& id, const std::string& path,
                     const WriteOptions& options, bool compact, const VolumeLevel* depth) {
    if (id.count < 1 || id.index < 0 || id.index >= id.count || id.paramsHash.empty())
        throw ValueError("invalid tile identity " + std::to_string(id.index) + " of " + std::to_string(id.count));
    const GridSpec& g = sums.grid;
    if (sums.values.size() != g.nodeCount() * iv::kFloatsPerNode || sums.firstBatch >= sums.endBatch ||
        sums.endBatch > sums.batches)
        throw ValueError("the photon tile's sums do not match their grid or batches");
    Volume part;  // the metadata and level of the volume; the sums as extra grids
    part.basis = iv::basis();
    part.levels.resize(1);
    part.levels[0].grid = g;
    if (depth) {  // the depth moments of the tile's run of nodes (photonTileDepthNodes)
        const std::vector<uint64_t>& nodes = depth->activeNodes;
        bool ascending = true;
        for (std::size_t n = 0; n < nodes.size(); ++n)
            ascending &= nodes[n] < g.nodeCount() && (n == 0 || nodes[n - 1] < nodes[n]);
        if (!ascending || depth->depth.size() != nodes.size() * depth::kFloatsPerNode)
            throw ValueError("the photon tile's depth moments do not match their nodes");
        part.levels[0].activeNodes = nodes;
        part.levels[0].depth = depth->depth;
    }
    part.meta = meta;
    part.meta["tile_index"] = int64_t(id.index);
    part.meta["tile_count"] = int64_t(id.count);
    part.meta["tile_params_hash"] = id.paramsHash;
    part.meta["tile_dense_levels"] = std::string("1");
    part.meta["tile_nodes"] = int64_t(g.nodeCount());
    part.meta["tile_half_float"] = int64_t(options.halfFloat ? 1 : 0);
    part.meta["tile_reproducible"] = int64_t(options.reproducible ? 1 : 0);
    part.meta["tile_photon_sums"] = int64_t(1);
    part.meta["tile_photon_exponent"] = int64_t(sums.exponent);
    part.meta["tile_photon_first_batch"] = int64_t(sums.firstBatch);
    part.meta["tile_photon_end_batch"] = int64_t(sums.endBatch);
    part.meta["tile_photon_batches"] = int64_t(sums.batches);
    part.meta["tile_photon_compact"] = int64_t(compact ? 1 : 0);
    part.meta["tile_depth"] = int64_t(depth ? 1 : 0);
    const std::vector<Coord> origins = leafOrigins(g);
    std::vector<openvdb::Int64Grid::Ptr> built(std::size_t(2 * iv::kFloatsPerNode));
    tbb::parallel_for(0, 2 * iv::kFloatsPerNode, [&](int w) {
        built[std::size_t(w)] = buildPhotonSumGrid(sums, origins, w / 2, w % 2 == 0);
    });
    openvdb::GridCPtrVec grids;
    for (int w = 0; w < 2 * iv::kFloatsPerNode; ++w) {
        openvdb::Int64Grid::Ptr grid = built[std::size_t(w)];
        grid->setName(photonSumGridName(w / 2, w % 2 == 0));
        grid->setTransform(levelTransform(g));
        grid->setGridClass(openvdb::GRID_UNKNOWN);
        tagGrid(*grid, part, 0, -1);
        grids.push_back(grid);
    }
    // Full floats whatever the merged file uses, as writeTile: the merge copies these values.
    if (depth) appendDepthGrids(part, 0, true, {}, false, grids);
    writeFile(part, path, options, true, grids, false);
}
}  // namespace vdblight
