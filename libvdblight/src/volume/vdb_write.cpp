// Volume -> .vdb file (layout specified in docs/format.md).
//
// One Vec3SGrid per (level, channel); voxel (i, j, k) of a level's grids is node (i, j, k)
// of that level, every node an active voxel. Grids are built leaf by leaf (8^3 voxels) in
// parallel. Writing goes through the atomic file writer (atomic_file.h): a temporary file in
// the target directory, renamed over the destination only once complete. Tile files are
// written by vdb_write_tiles.cpp with the pieces vdb_write_parts.h exposes.
#include "vdblight/volume/vdb_io.h"
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <set>
#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <tbb/parallel_for.h>
#include "vdblight/core/atomic_file.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "basis/shadow_edges.h"
#include "vdb_conventions.h"
#include "vdb_surface_bins.h"
#include "vdb_write_parts.h"
#include "content_hash.h"

namespace vdblight {
namespace vdb_detail {

std::vector<Coord> leafOrigins(const GridSpec& g) {
    std::vector<Coord> origins;
    for (int z = 0; z < g.nz; z += kLeafDim)
        for (int y = 0; y < g.ny; y += kLeafDim)
            for (int x = 0; x < g.nx; x += kLeafDim) origins.emplace_back(x, y, z);
    return origins;
}

}  // namespace vdb_detail

namespace {
using namespace vdb_detail;

/// One channel of one level as a grid whose voxels are all active (zeros included).
Vec3SGrid::Ptr buildChannelGrid(const VolumeLevel& level, int channel, int channels,
                                const std::vector<Coord>& origins) {
    const GridSpec& g = level.grid;
    std::vector<std::unique_ptr<LeafT>> leaves(origins.size());
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t n) {
        const Coord o = origins[n];
        auto leaf = std::make_unique<LeafT>(o, openvdb::Vec3s(0.0f), false);
        const Coord hi(std::min(o.x() + kLeafDim, g.nx), std::min(o.y() + kLeafDim, g.ny),
                       std::min(o.z() + kLeafDim, g.nz));
        for (int z = o.z(); z < hi.z(); ++z)
            for (int y = o.y(); y < hi.y(); ++y)
                for (int x = o.x(); x < hi.x(); ++x) {
                    const float* v = level.nodeData(g.index(x, y, z), channels) + channel * 3;
                    leaf->setValueOn(LeafT::coordToOffset(Coord(x, y, z)), openvdb::Vec3s(v[0], v[1], v[2]));
                }
        leaves[n] = std::move(leaf);
    });
    auto grid = Vec3SGrid::create(openvdb::Vec3s(0.0f));
    for (auto& leaf : leaves) grid->tree().addLeaf(leaf.release());
    return grid;
}

/// One channel of a sparse level: exactly its active nodes are active voxels.
Vec3SGrid::Ptr buildSparseChannelGrid(const VolumeLevel& level, int channel, int channels) {
    auto grid = Vec3SGrid::create(openvdb::Vec3s(0.0f));
    auto acc = grid->getAccessor();
    for (std::size_t n = 0; n < level.activeNodes.size(); ++n) {
        const float* v = level.nodeData(n, channels) + channel * 3;
        acc.setValue(unpackCoord(level.grid, level.activeNodes[n]), openvdb::Vec3s(v[0], v[1], v[2]));
    }
    return grid;
}

/// The mask of refined cells of one level.
openvdb::BoolGrid::Ptr buildMaskGrid(const Volume& volume, int level) {
    const VolumeLevel& lv = volume.levels[std::size_t(level)];
    auto grid = openvdb::BoolGrid::create(false);
    auto acc = grid->getAccessor();
    for (uint64_t cell : lv.refinedCells) acc.setValue(unpackCoord(lv.grid, cell), true);
    grid->setName(maskNameFor(level));
    grid->setTransform(maskTransform(lv.grid));
    grid->setGridClass(openvdb::GRID_UNKNOWN);
    grid->insertMeta(kPrefix + "format_version", openvdb::Int64Metadata(kFormatVersion));
    grid->insertMeta(kPrefix + "level", openvdb::Int64Metadata(level));
    grid->insertMeta(kPrefix + "mask", openvdb::StringMetadata("refined cells"));
    return grid;
}


/// A per-node scalar of a dense level as a FloatGrid whose voxels are all active, like the
/// channel grids: values[node * stride + offset]. Used for validity (stride 1; the anti-aliased
/// pass bakes uniform volumes) and for the light visibility channels (stride = light count).
openvdb::FloatGrid::Ptr buildScalarGrid(const VolumeLevel& level, const std::vector<Coord>& origins,
                                        const float* values, std::size_t stride, std::size_t offset) {
    const GridSpec& g = level.grid;
    std::vector<std::unique_ptr<FloatLeafT>> leaves(origins.size());
    tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t n) {
        const Coord o = origins[n];
        auto leaf = std::make_unique<FloatLeafT>(o, 0.0f, false);
        for (int z = o.z(); z < std::min(o.z() + kLeafDim, g.nz); ++z)
            for (int y = o.y(); y < std::min(o.y() + kLeafDim, g.ny); ++y)
                for (int x = o.x(); x < std::min(o.x() + kLeafDim, g.nx); ++x)
                    leaf->setValueOn(FloatLeafT::coordToOffset(Coord(x, y, z)), values[g.index(x, y, z) * stride + offset]);
        leaves[n] = std::move(leaf);
    });
    auto grid = openvdb::FloatGrid::create(0.0f);
    for (auto& leaf : leaves) grid->tree().addLeaf(leaf.release());
    return grid;
}

}  // namespace

openvdb::FloatGrid::Ptr vdb_detail::buildSparseScalarGrid(const GridSpec& g, const std::vector<uint64_t>& activeNodes,
                                              const float* values, std::size_t stride, std::size_t offset) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    auto acc = grid->getAccessor();
    for (std::size_t n = 0; n < activeNodes.size(); ++n) acc.setValue(unpackCoord(g, activeNodes[n]), values[n * stride + offset]);
    return grid;
}

namespace {
bool isRunSpecific(const std::string& key) {
    const std::vector<std::string>& keys = runSpecificMetadataKeys();
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

/// File-level metadata: the caller's entries (less the run-specific ones for a reproducible
/// file) plus the structural keys.
openvdb::MetaMap fileMetadata(const Volume& volume, const WriteOptions& options) {
    openvdb::MetaMap meta;
    for (const auto& [key, value] : volume.meta)
        if (!options.reproducible || !isRunSpecific(key)) meta.insertMeta(kPrefix + key, *toVdbMeta(value));
    meta.insertMeta(kPrefix + "format_version", openvdb::Int64Metadata(kFormatVersion));
    meta.insertMeta(kPrefix + "basis", openvdb::StringMetadata(volume.basis.kind));
    meta.insertMeta(kPrefix + "channels", openvdb::StringMetadata(joinNames(volume.basis.channelNames)));
    meta.insertMeta(kPrefix + "levels", openvdb::Int64Metadata(int64_t(volume.levels.size())));
    // Direct light (direct_light.h): the mode, and the listed lights one string each.
    meta.insertMeta(kPrefix + "direct", openvdb::StringMetadata(directModeName(volume.direct.mode)));
    meta.insertMeta(kPrefix + "direct_lights", openvdb::Int64Metadata(int64_t(volume.direct.lights.size())));
    for (std::size_t i = 0; i < volume.direct.lights.size(); ++i)
        meta.insertMeta(kPrefix + directLightKey(i), openvdb::StringMetadata(formatDirectLight(volume.direct.lights[i])));
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const GridSpec& g = volume.levels[l].grid;
        meta.insertMeta(levelKey(int(l), "origin"), openvdb::Vec3DMetadata({g.origin.x, g.origin.y, g.origin.z}));
        meta.insertMeta(levelKey(int(l), "spacing"), openvdb::DoubleMetadata(g.spacing));
        meta.insertMeta(levelKey(int(l), "dims"), openvdb::Vec3IMetadata({g.nx, g.ny, g.nz}));
    }
    return meta;
}

}  // namespace

void vdb_detail::tagGrid(openvdb::GridBase& grid, const Volume& volume, int level, int channel) {
    const GridSpec& g = volume.levels[std::size_t(level)].grid;
    grid.insertMeta(kPrefix + "format_version", openvdb::Int64Metadata(kFormatVersion));
    grid.insertMeta(kPrefix + "basis", openvdb::StringMetadata(volume.basis.kind));
    grid.insertMeta(kPrefix + "level", openvdb::Int64Metadata(level));
    if (channel >= 0) {  // channel -1: the validity grid, which is no basis channel
        grid.insertMeta(kPrefix + "channel", openvdb::Int64Metadata(channel));
        grid.insertMeta(kPrefix + "channel_name",
                        openvdb::StringMetadata(volume.basis.channelNames[std::size_t(channel)]));
    }
    grid.insertMeta(kPrefix + "origin", openvdb::Vec3DMetadata({g.origin.x, g.origin.y, g.origin.z}));
    grid.insertMeta(kPrefix + "spacing", openvdb::DoubleMetadata(g.spacing));
    grid.insertMeta(kPrefix + "dims", openvdb::Vec3IMetadata({g.nx, g.ny, g.nz}));
}

namespace {
/// Rejects NaN/Inf (a file must never carry them) and, for half floats, values that would
/// overflow to infinity.
void checkValues(const Volume& volume, const WriteOptions& options) {
    constexpr float kHalfMax = 65504.0f;
    const int channels = volume.basis.channelCount();
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const std::vector<float>& data = volume.levels[l].data;
        for (std::size_t n = 0; n < data.size(); ++n) {
            const bool bad = !std::isfinite(data[n]) || (options.halfFloat && std::abs(data[n]) > kHalfMax);
            if (!bad) continue;
            const std::size_t node = n / (std::size_t(channels) * 3);
            const std::string where = "level " + std::to_string(l) + ", node " + std::to_string(node) + ", channel " +
                                      volume.basis.channelNames[n / 3 % std::size_t(channels)];
            if (!std::isfinite(data[n])) throw ValueError("non-finite value at " + where);
            throw ValueError("value " + std::to_string(data[n]) + " at " + where +
                             " exceeds the half-float range (65504); write with full floats");
        }
    }
}

/// `tile`: a partial volume from writeTile, whose levels list the tile's nodes (not a
/// complete volume: no structure check).
void checkWritable(const Volume& volume, const WriteOptions& options, bool tile) {
    if (!tile) {
        try {
            volume.validate();
        } catch (const FormatError& e) {
            throw ValueError(std::string("invalid volume: ") + e.what());
        }
    }
    for (const auto& entry : volume.meta) {
        if (entry.first.empty()) throw ValueError("metadata key is empty");
        if (isStructuralKey(entry.first) || (!tile && isTileKey(entry.first))) {
            throw ValueError("metadata key '" + entry.first + "' is reserved (the writer sets it)");
        }
    }
    checkValues(volume, options);
    std::set<std::string> names;
    for (std::size_t l = 0; l < volume.levels.size(); ++l)
        for (const std::string& c : volume.basis.channelNames)
            if (!names.insert(gridNameFor(c, int(l))).second)
                throw ValueError("grid name '" + gridNameFor(c, int(l)) + "' would appear twice");
    for (const std::string& c : volume.basis.channelNames)
        if (c == kValidityName) throw ValueError("channel name '" + kValidityName + "' is reserved for the validity grid");
    for (std::size_t l = 0; l < volume.levels.size(); ++l)
        for (int c = 0; volume.levels[l].hasDepth() && c < depth::kChannels; ++c)
            if (!names.insert(gridNameFor(depth::channelName(c), int(l))).second)
                throw ValueError("grid name '" + gridNameFor(depth::channelName(c), int(l)) + "' would appear twice");
    for (const VolumeLevel& level : volume.levels)
        if (level.sparse() && !level.validity.empty())
            throw ValueError("validity is stored for dense levels only");
    for (const VolumeLevel& level : volume.levels)
        if (level.sparse() && !level.lightVisibility.empty() && !tile)
            throw ValueError("light visibility is stored for dense levels only");
    for (const std::string& c : volume.basis.channelNames)
        if (c.compare(0, 17, "light_visibility_") == 0 || c.compare(0, 11, "light_edge_") == 0)
            throw ValueError("channel name '" + c + "' is reserved for the light visibility grids");
    if (volume.levels.size() > 1)
        for (std::size_t l = 0; l + 1 < volume.levels.size(); ++l)
            if (!names.insert(maskNameFor(int(l))).second)
                throw ValueError("grid name '" + maskNameFor(int(l)) + "' would appear twice");
}

openvdb::GridCPtrVec buildGrids(const Volume& volume, const WriteOptions& options, bool tile) {
    const int channels = volume.basis.channelCount();
    openvdb::GridCPtrVec grids;
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const VolumeLevel& level = volume.levels[l];
        const bool sparse = level.sparse() || tile;  // a tile lists its nodes, maybe none
        const std::vector<Coord> origins = sparse ? std::vector<Coord>() : leafOrigins(level.grid);
        std::vector<Vec3SGrid::Ptr> built(std::size_t(channels), nullptr);
        tbb::parallel_for(0, channels, [&](int c) {
            built[std::size_t(c)] = sparse ? buildSparseChannelGrid(level, c, channels)
                                                   : buildChannelGrid(level, c, channels, origins);
        });
        for (int c = 0; c < channels; ++c) {
            Vec3SGrid::Ptr grid = built[std::size_t(c)];
            grid->setName(gridNameFor(volume.basis.channelNames[std::size_t(c)], int(l)));
            grid->setTransform(levelTransform(level.grid));
            grid->setGridClass(openvdb::GRID_UNKNOWN);
            grid->setVectorType(openvdb::VEC_INVARIANT);
            grid->setSaveFloatAsHalf(options.halfFloat);
            tagGrid(*grid, volume, int(l), c);
            grids.push_back(grid);
        }
        if (!level.validity.empty()) {
            openvdb::FloatGrid::Ptr grid = buildScalarGrid(level, origins, level.validity.data(), 1, 0);
            grid->setName(gridNameFor(kValidityName, int(l)));
            grid->setTransform(levelTransform(level.grid));
            grid->setGridClass(openvdb::GRID_UNKNOWN);
            grid->setSaveFloatAsHalf(options.halfFloat);
            tagGrid(*grid, volume, int(l), -1);
            grids.push_back(grid);
        }
        // Direct light, occlusion mode: one visibility grid per listed light (docs/format.md).
        const std::size_t lights = volume.direct.lights.size();
        for (std::size_t i = 0; i < lights && !level.lightVisibility.empty(); ++i) {
            openvdb::FloatGrid::Ptr grid =
                sparse ? buildSparseScalarGrid(level.grid, level.activeNodes, level.lightVisibility.data(), lights, i)
                       : buildScalarGrid(level, origins, level.lightVisibility.data(), lights, i);
            grid->setName(gridNameFor(visibilityGridName(i), int(l)));
            grid->setTransform(levelTransform(level.grid));
            grid->setGridClass(openvdb::GRID_UNKNOWN);
            grid->setSaveFloatAsHalf(options.halfFloat);
            tagGrid(*grid, volume, int(l), -1);
            grid->insertMeta(kPrefix + "light", openvdb::Int64Metadata(int64_t(i)));
            grids.push_back(grid);
        }
        // Their shadow edges, when baked: kFloatsPerLight grids per light (shadow_edges.h, docs/format.md).
        for (std::size_t i = 0; i < lights && !level.lightShadowEdges.empty(); ++i)
            for (int part = 0; part < shadow_edge::kFloatsPerLight; ++part) {
                const std::size_t stride = lights * shadow_edge::kFloatsPerLight, at = i * shadow_edge::kFloatsPerLight + part;
                openvdb::FloatGrid::Ptr grid =
                    sparse ? buildSparseScalarGrid(level.grid, level.activeNodes, level.lightShadowEdges.data(), stride, at)
                           : buildScalarGrid(level, origins, level.lightShadowEdges.data(), stride, at);
                grid->setName(gridNameFor(shadow_edge::partGridName(part, i), int(l)));
                grid->setTransform(levelTransform(level.grid));
                grid->setGridClass(openvdb::GRID_UNKNOWN);
                grid->setSaveFloatAsHalf(options.halfFloat);
                tagGrid(*grid, volume, int(l), -1);
                grid->insertMeta(kPrefix + "light", openvdb::Int64Metadata(int64_t(i)));
                grids.push_back(grid);
            }
        if (level.hasDepth()) appendDepthGrids(volume, int(l), sparse, origins, options.halfFloat, grids);
        if (volume.levels.size() > 1 && l + 1 < volume.levels.size()) grids.push_back(buildMaskGrid(volume, int(l)));
    }
    if (volume.surfaceBins) appendSurfaceBinGrids(*volume.surfaceBins, volume.levels.at(0).grid, grids);
    return grids;
}

}  // namespace

void vdb_detail::appendDepthGrids(const Volume& volume, int l, bool sparse, const std::vector<Coord>& origins,
                                  bool halfFloat, openvdb::GridCPtrVec& grids) {
    // Four Vec3S grids with the channel grids' active voxels, built by the same code from a
    // level whose data is the depth.
    const VolumeLevel& level = volume.levels[std::size_t(l)];
    VolumeLevel depthLevel;
    depthLevel.grid = level.grid;
    depthLevel.activeNodes = level.activeNodes;
    depthLevel.data = level.depth;
    for (int c = 0; c < depth::kChannels; ++c) {
        Vec3SGrid::Ptr grid = sparse ? buildSparseChannelGrid(depthLevel, c, depth::kChannels)
                                     : buildChannelGrid(depthLevel, c, depth::kChannels, origins);
        grid->setName(gridNameFor(depth::channelName(c), l));
        grid->setTransform(levelTransform(level.grid));
        grid->setGridClass(openvdb::GRID_UNKNOWN);
        grid->setVectorType(openvdb::VEC_INVARIANT);
        grid->setSaveFloatAsHalf(halfFloat);
        tagGrid(*grid, volume, l, -1);
        grid->insertMeta(kPrefix + "depth_channel", openvdb::StringMetadata(depth::channelName(c)));
        grids.push_back(grid);
    }
}

const std::vector<std::string>& runSpecificMetadataKeys() {
    static const std::vector<std::string> keys = {"bake_seconds", "threads"};
    return keys;
}

void vdb_detail::writeFile(const Volume& volume, const std::string& path, const WriteOptions& options, bool tile,
                           const openvdb::GridCPtrVec& extra, bool channels) {
    checkWritable(volume, options, tile);
    initOpenVdb();
    openvdb::GridCPtrVec grids = channels ? buildGrids(volume, options, tile) : openvdb::GridCPtrVec();
    grids.insert(grids.end(), extra.begin(), extra.end());
    const openvdb::MetaMap meta = fileMetadata(volume, options);
    writeFileAtomically(path, [&](const std::string& temp) {
        openvdb::io::File(temp).write(grids, meta);
        stampContentUuid(temp);  // OpenVDB's random UUID -> one from the content (content_hash.h)
    });
}

void writeVolume(const Volume& volume, const std::string& path, const WriteOptions& options) {
    vdb_detail::writeFile(volume, path, options, false);
}

}  // namespace vdblight
