// One level's grids of a vdblight .vdb: every structural fact checked (docs/format.md), then
// copied into a VolumeLevel (vdb_read_parts.h).
#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "vdb_read_parts.h"
#include "vdblight/basis/depth_moments.h"
#include "basis/shadow_edges.h"

namespace vdblight::vdb_detail {

GridSpec readLevelSpec(const openvdb::MetaMap& meta, int level, const std::string& path) {
    const openvdb::Vec3d o = requireMeta<openvdb::Vec3d>(meta, levelKey(level, "origin"), path);
    const openvdb::Vec3i d = requireMeta<openvdb::Vec3i>(meta, levelKey(level, "dims"), path);
    GridSpec g;
    g.origin = Vec3d(o.x(), o.y(), o.z());
    g.spacing = requireMeta<double>(meta, levelKey(level, "spacing"), path);
    g.nx = d.x(), g.ny = d.y(), g.nz = d.z();
    return g;
}

/// Everything except the structural keys, prefix stripped.
Metadata userMetadata(const openvdb::MetaMap& meta) {
    Metadata out;
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        if (it->first.compare(0, kPrefix.size(), kPrefix) != 0) continue;
        const std::string key = it->first.substr(kPrefix.size());
        MetaValue value;
        if (!isStructuralKey(key) && it->second && fromVdbMeta(*it->second, value)) out[key] = value;
    }
    return out;
}

/// True if `xf` is the linear transform placing voxel (0, 0, 0) at `o` with voxel size h.
bool placedAt(const openvdb::math::Transform& xf, const Vec3d& at, double h) {
    const openvdb::Vec3d o = xf.indexToWorld(Coord(0, 0, 0)), vs = xf.voxelSize();
    const double tol = 1e-9 * std::max({h, std::abs(at.x), std::abs(at.y), std::abs(at.z)});
    return xf.isLinear() && std::abs(vs.x() - h) <= tol && std::abs(vs.y() - h) <= tol && std::abs(vs.z() - h) <= tol &&
           std::abs(o.x() - at.x) <= tol && std::abs(o.y() - at.y) <= tol && std::abs(o.z() - at.z) <= tol;
}

/// Throws unless `grid` is a Vec3SGrid placed as `g`.
Vec3SGrid::Ptr checkPlacedChannel(const openvdb::GridBase::Ptr& base, const GridSpec& g, const std::string& path) {
    auto grid = openvdb::gridPtrCast<Vec3SGrid>(base);
    const std::string name = "grid '" + base->getName() + "' ";
    if (!grid) formatError(path, name + "has type " + base->valueType() + ", expected vec3s");
    if (!placedAt(grid->transform(), g.origin, g.spacing))
        formatError(path, name + "has a transform that does not match its level's origin and spacing");
    return grid;
}

/// Throws unless `grid` is a Vec3SGrid placed as `g` whose active voxels are exactly [0, dims).
Vec3SGrid::Ptr checkChannelGrid(const openvdb::GridBase::Ptr& base, const GridSpec& g, const std::string& path) {
    Vec3SGrid::Ptr grid = checkPlacedChannel(base, g, path);
    const std::string name = "grid '" + base->getName() + "' ";
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    const bool inside = box.min() == Coord(0, 0, 0) && box.max() == Coord(g.nx - 1, g.ny - 1, g.nz - 1);
    if (grid->activeVoxelCount() != g.nodeCount() || !inside) {
        formatError(path, name + "has " + std::to_string(grid->activeVoxelCount()) +
                              " active voxels, expected exactly the " + std::to_string(g.nodeCount()) +
                              " nodes of a " + std::to_string(g.nx) + "x" + std::to_string(g.ny) + "x" +
                              std::to_string(g.nz) + " box");
    }
    grid->tree().voxelizeActiveTiles();  // another writer may have merged constant blocks
    return grid;
}

/// Copies the active voxels of `grid` into channel `channel` of the level's data.
static void copyChannel(const Vec3SGrid& grid, VolumeLevel& level, int channel, int channels) {
    std::vector<const LeafT*> leaves;
    leaves.reserve(grid.tree().leafCount());
    for (auto it = grid.tree().cbeginLeaf(); it; ++it) leaves.push_back(it.getLeaf());
    const GridSpec& g = level.grid;
    // A level with a window (VolumeLevel::windowFirst) keeps only the window's nodes.
    const std::size_t first = level.windowFirst, end = first + level.heldNodes();
    tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t n) {
        for (auto v = leaves[n]->cbeginValueOn(); v; ++v) {
            const Coord c = v.getCoord();
            const std::size_t node = g.index(c.x(), c.y(), c.z());
            if (node < first || node >= end) continue;
            float* out = level.data.data() + (level.held(node) * channels + channel) * 3;
            out[0] = v->x(), out[1] = v->y(), out[2] = v->z();
        }
    });
}

bool insideBox(const openvdb::CoordBBox& box, int nx, int ny, int nz) {
    return box.empty() || (box.min().x() >= 0 && box.min().y() >= 0 && box.min().z() >= 0 && box.max().x() < nx &&
                           box.max().y() < ny && box.max().z() < nz);
}

/// Linear indices of the active voxels of `grid` (inside the level's box), ascending.
std::vector<uint64_t> activeLinear(const openvdb::GridBase& grid, const GridSpec& g) {
    std::vector<uint64_t> out;
    const auto& tree = static_cast<const Vec3SGrid&>(grid).tree();
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        const Coord c = it.getCoord();
        out.push_back(g.index(c.x(), c.y(), c.z()));
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// A channel of a refined (sparse) level: placed as `g`, active voxels inside the box and
/// the same as the level's first channel (`first`, null for the first channel).
Vec3SGrid::Ptr checkSparseChannelGrid(const openvdb::GridBase::Ptr& base, const GridSpec& g,
                                      const Vec3SGrid* first, const std::string& path) {
    Vec3SGrid::Ptr grid = checkPlacedChannel(base, g, path);
    grid->tree().voxelizeActiveTiles();
    const std::string name = "grid '" + base->getName() + "' ";
    if (grid->activeVoxelCount() == 0) formatError(path, name + "has no active voxels");
    if (!insideBox(grid->evalActiveVoxelBoundingBox(), g.nx, g.ny, g.nz))
        formatError(path, name + "has active voxels outside its level's node box");
    if (first && !grid->tree().hasSameTopology(first->tree()))
        formatError(path, name + "has other active voxels than the first channel of its level");
    return grid;
}

void copySparseChannel(const Vec3SGrid& grid, VolumeLevel& level, int channel, int channels) {
    for (auto it = grid.tree().cbeginValueOn(); it; ++it) {
        const Coord c = it.getCoord();
        const uint64_t linear = level.grid.index(c.x(), c.y(), c.z());
        const auto at = std::lower_bound(level.activeNodes.begin(), level.activeNodes.end(), linear);
        float* out = level.data.data() + (std::size_t(at - level.activeNodes.begin()) * channels + channel) * 3;
        out[0] = it->x(), out[1] = it->y(), out[2] = it->z();
    }
}

/// Reads the mask of refined cells of `level` into its refinedCells.
void readMask(OpenedFile& f, VolumeLevel& level, int index, const std::string& path) {
    const std::string name = maskNameFor(index);
    if (!f.file->hasGrid(name))
        formatError(path, "has no grid '" + name + "' (the mask of level " + std::to_string(index) + "'s refined cells)");
    const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
    auto mask = openvdb::gridPtrCast<openvdb::BoolGrid>(base);
    if (!mask) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected bool");
    const GridSpec& g = level.grid;
    const double half = 0.5 * g.spacing;
    if (!placedAt(mask->transform(), g.origin + Vec3d(half, half, half), g.spacing))
        formatError(path, "grid '" + name + "' has a transform that does not match its level's cells");
    mask->tree().voxelizeActiveTiles();
    if (!insideBox(mask->evalActiveVoxelBoundingBox(), g.nx - 1, g.ny - 1, g.nz - 1))
        formatError(path, "grid '" + name + "' marks cells outside its level's cell range");
    for (auto it = mask->tree().cbeginValueOn(); it; ++it) {
        const Coord c = it.getCoord();
        level.refinedCells.push_back(g.index(c.x(), c.y(), c.z()));
    }
    std::sort(level.refinedCells.begin(), level.refinedCells.end());
}

/// Reads the optional validity FloatGrid of a level: same placement and active voxels as the
/// channel grids, values in [0, 1] (checked by Volume::validate).
static std::vector<float> readScalarGrid(OpenedFile& f, const std::string& name, const GridSpec& g, const std::string& path) {
    const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected float");
    const openvdb::math::Transform& xf = grid->transform();
    const openvdb::Vec3d o = xf.indexToWorld(Coord(0, 0, 0));
    const double tol = 1e-9 * std::max({g.spacing, std::abs(g.origin.x), std::abs(g.origin.y), std::abs(g.origin.z)});
    if (!xf.isLinear() || std::abs(xf.voxelSize().x() - g.spacing) > tol || std::abs(o.x() - g.origin.x) > tol ||
        std::abs(o.y() - g.origin.y) > tol || std::abs(o.z() - g.origin.z) > tol)
        formatError(path, "grid '" + name + "' has a transform that does not match its level's origin and spacing");
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (grid->activeVoxelCount() != g.nodeCount() || box.min() != Coord(0, 0, 0) ||
        box.max() != Coord(g.nx - 1, g.ny - 1, g.nz - 1))
        formatError(path, "grid '" + name + "' does not have exactly one active voxel per node");
    grid->tree().voxelizeActiveTiles();
    std::vector<float> values(g.nodeCount(), 0.0f);
    for (auto v = grid->cbeginValueOn(); v; ++v) {
        const Coord c = v.getCoord();
        values[g.index(c.x(), c.y(), c.z())] = *v;
    }
    return values;
}

/// A per-node scalar of a tile's nodes (tiles.h): a FloatGrid placed as the level whose
/// active voxels are exactly `level.activeNodes`; values in that order.
std::vector<float> readSparseScalar(OpenedFile& f, const std::string& name, const VolumeLevel& level,
                                    const std::string& path) {
    if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
    openvdb::GridBase::Ptr base;
    try {
        base = f.file->readGrid(name);
    } catch (const std::exception& e) {
        formatError(path, "grid '" + name + "' cannot be read (truncated or corrupt?): " + e.what());
    }
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected float");
    if (!placedAt(grid->transform(), level.grid.origin, level.grid.spacing))
        formatError(path, "grid '" + name + "' has a transform that does not match its level's origin and spacing");
    grid->tree().voxelizeActiveTiles();
    std::vector<float> values;
    std::vector<uint64_t> linear;
    for (auto v = grid->cbeginValueOn(); v; ++v) {
        const Coord c = v.getCoord();
        if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() >= level.grid.nx || c.y() >= level.grid.ny || c.z() >= level.grid.nz)
            formatError(path, "grid '" + name + "' has active voxels outside its level's node box");
        linear.push_back(level.grid.index(c.x(), c.y(), c.z()));
    }
    std::vector<std::size_t> order(linear.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return linear[a] < linear[b]; });
    std::vector<float> raw;
    for (auto v = grid->cbeginValueOn(); v; ++v) raw.push_back(*v);
    std::vector<uint64_t> sorted;
    for (std::size_t i : order) sorted.push_back(linear[i]), values.push_back(raw[i]);
    if (sorted != level.activeNodes) formatError(path, "grid '" + name + "' has other active voxels than the tile's nodes");
    return values;
}

openvdb::Int64Grid::Ptr readPlacedInt64Grid(OpenedFile& f, const std::string& name, const GridSpec& g,
                                            const std::string& path) {
    if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
    const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
    auto grid = openvdb::gridPtrCast<openvdb::Int64Grid>(base);
    if (!grid) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected int64");
    if (!placedAt(grid->transform(), g.origin, g.spacing))
        formatError(path, "grid '" + name + "' has a transform that does not match its level's origin and spacing");
    grid->tree().voxelizeActiveTiles();
    return grid;
}

/// The direct-light mode and light list (files without them: baked).
void readDirectLights(OpenedFile& f, Volume& volume, const std::string& path) {
    const openvdb::MetaMap& meta = *f.meta;
    const auto mode = meta.getMetadata<openvdb::StringMetadata>(kPrefix + "direct");
    if (!mode) return;
    try {
        volume.direct.mode = parseDirectMode(mode->value());
    } catch (const ValueError&) {
        formatError(path, "has an unknown direct-light mode '" + mode->value() + "'");
    }
    const int64_t count = requireMeta<int64_t>(meta, kPrefix + "direct_lights", path);
    if (count < 0 || count > 1000000) formatError(path, "has an invalid light count " + std::to_string(count));
    for (int64_t i = 0; i < count; ++i) {
        const std::string text = requireMeta<std::string>(meta, kPrefix + directLightKey(std::size_t(i)), path);
        try {
            volume.direct.lights.push_back(parseDirectLight(text));
        } catch (const FormatError& e) {
            formatError(path, "light " + std::to_string(i) + ": " + e.what());
        }
    }
}

/// The direct-light mode and light list, and in occlusion mode the visibility grids of
/// level 0 (docs/format.md, "Direct light").
void readDirect(OpenedFile& f, Volume& volume, const std::string& path) {
    readDirectLights(f, volume, path);
    if (!volume.direct.hasVisibility()) return;
    VolumeLevel& level = volume.levels[0];
    const std::size_t lights = volume.direct.lights.size();
    level.lightVisibility.assign(level.grid.nodeCount() * lights, 0.0f);
    for (std::size_t i = 0; i < lights; ++i) {
        const std::string name = visibilityGridName(i);
        if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
        const std::vector<float> v = readScalarGrid(f, name, level.grid, path);
        for (std::size_t n = 0; n < v.size(); ++n) level.lightVisibility[n * lights + i] = v[n];
    }
    // Shadow edges (shadow_edges.h): optional (files before issue 32 have none), all or none.
    if (!f.file->hasGrid(shadow_edge::distanceGridName(0))) return;
    constexpr int parts = shadow_edge::kFloatsPerLight;
    level.lightShadowEdges.assign(level.grid.nodeCount() * lights * parts, 0.0f);
    for (std::size_t i = 0; i < lights; ++i)
        for (int part = 0; part < parts; ++part) {
            const std::string name = shadow_edge::partGridName(part, i);
            // Files from before the second edge hold distance and width only: no direction, no far side.
            if (part >= shadow_edge::kDirectionX && !f.file->hasGrid(shadow_edge::partGridName(shadow_edge::kFar, 0))) continue;
            if (!f.file->hasGrid(name)) formatError(path, "has shadow edges without grid '" + name + "'");
            const std::vector<float> v = readScalarGrid(f, name, level.grid, path);
            for (std::size_t n = 0; n < v.size(); ++n) level.lightShadowEdges[(n * lights + i) * parts + part] = v[n];
        }
}

/// Reads the optional depth-moment grids of a level (depth_moments.h): all four or an error,
/// with exactly the channel grids' active voxels; values in [0, 1] are checked by validate.
void readDepth(OpenedFile& f, VolumeLevel& out, int level, const std::string& path) {
    VolumeLevel tmp;
    tmp.grid = out.grid;
    tmp.activeNodes = out.activeNodes;
    tmp.windowFirst = out.windowFirst;
    tmp.windowNodes = out.windowNodes;
    tmp.data.assign(out.heldNodes() * depth::kFloatsPerNode, 0.0f);
    for (int c = 0; c < depth::kChannels; ++c) {
        const std::string name = gridNameFor(depth::channelName(c), level);
        if (!f.file->hasGrid(name)) formatError(path, "has depth moments without grid '" + name + "'");
        const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
        if (out.sparse()) {
            Vec3SGrid::Ptr grid = checkSparseChannelGrid(base, out.grid, nullptr, path);
            if (uint64_t(grid->activeVoxelCount()) != out.activeNodes.size() ||
                activeLinear(*grid, out.grid) != out.activeNodes)
                formatError(path, "grid '" + name + "' has other active voxels than the level's channel grids");
            copySparseChannel(*grid, tmp, c, depth::kChannels);
        } else {
            copyChannel(*checkChannelGrid(base, out.grid, path), tmp, c, depth::kChannels);
        }
    }
    out.depth = std::move(tmp.data);
}

VolumeLevel readLevel(OpenedFile& f, const BasisDesc& basis, int level, const std::string& path, bool multiLevel,
                      std::size_t windowFirst, std::size_t windowNodes) {
    VolumeLevel out;
    out.grid = readLevelSpec(*f.meta, level, path);
    const GridSpec& g = out.grid;
    if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin)) {
        formatError(path, "has invalid dimensions, spacing or origin for level " + std::to_string(level));
    }
    if (windowNodes) {  // a dense one-level file's nodes [windowFirst, windowFirst + windowNodes) only
        if (multiLevel || windowFirst + windowNodes > g.nodeCount())
            throw ValueError("a window of nodes beyond level " + std::to_string(level) + " of '" + path + "'");
        out.windowFirst = windowFirst;
        out.windowNodes = windowNodes;
    }
    const int channels = basis.channelCount();
    Vec3SGrid::Ptr first;
    bool sparse = level > 0;  // refined levels; level 0 of a culled multi-level volume (checked by validate)
    for (int c = 0; c < channels; ++c) {
        const std::string name = gridNameFor(basis.channelNames[std::size_t(c)], level);
        if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
        const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
        if (c == 0 && level == 0 && multiLevel) {
            const auto typed = openvdb::gridPtrCast<Vec3SGrid>(base);
            if (typed && typed->activeVoxelCount() < g.nodeCount()) sparse = true;
        }
        if (sparse) {
            Vec3SGrid::Ptr grid = checkSparseChannelGrid(base, g, first.get(), path);
            if (c == 0) {
                first = grid;
                out.activeNodes = activeLinear(*grid, g);
                out.data.assign(out.activeNodes.size() * std::size_t(channels) * 3, 0.0f);
            }
            copySparseChannel(*grid, out, c, channels);
            continue;
        }
        Vec3SGrid::Ptr grid = checkChannelGrid(base, g, path);
        // Allocated only once a grid has confirmed the node count (metadata could be corrupt).
        if (out.data.empty()) out.data.assign(out.heldNodes() * std::size_t(channels) * 3, 0.0f);
        copyChannel(*grid, out, c, channels);
    }
    const std::string validityName = gridNameFor(kValidityName, level);
    if (level == 0 && f.file->hasGrid(validityName)) out.validity = readScalarGrid(f, validityName, out.grid, path);
    if (f.file->hasGrid(gridNameFor(depth::channelName(0), level))) readDepth(f, out, level, path);
    return out;
}

}  // namespace vdblight::vdb_detail
