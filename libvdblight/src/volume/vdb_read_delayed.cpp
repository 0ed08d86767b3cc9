// Delayed loading of a vdblight .vdb (vdb_stream.h): the grids' topology is read and checked,
// their leaf values stay in the mapped file until a voxel of the leaf is read.
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include <tbb/task_arena.h>

#include "vdb_delayed.h"
#include "vdb_read_parts.h"
#include "vdblight/basis/depth_moments.h"
#include "basis/shadow_edges.h"

namespace vdblight::vdb_detail {

namespace {

/// openDelayedVolume's work; every grid it reads is also put in `held` as soon as it is read.
DelayedVolumeFile openAndCheck(const std::string& path, std::vector<openvdb::GridBase::Ptr>& held) {
    OpenedFile f = openVolumeFile(path, OpenFor::Delayed);
    const openvdb::MetaMap& meta = *f.meta;
    if (meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count"))
        formatError(path, "is a tile of a bake, not a complete volume: merge the tiles with 'vdblight merge'");
    DelayedVolumeFile out;
    Volume& v = out.header;
    v.basis.kind = requireMeta<std::string>(meta, kPrefix + "basis", path);
    v.basis.channelNames = splitNames(requireMeta<std::string>(meta, kPrefix + "channels", path));
    const int64_t levels = requireMeta<int64_t>(meta, kPrefix + "levels", path);
    if (levels < 1 || levels > 64) formatError(path, "has an invalid level count " + std::to_string(levels));
    for (int l = 0; l < int(levels); ++l) {
        VolumeLevel level;
        level.grid = readLevelSpec(meta, l, path);
        const GridSpec& g = level.grid;
        if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin))
            formatError(path, "has invalid dimensions, spacing or origin for level " + std::to_string(l));
        v.levels.push_back(std::move(level));
    }
    v.meta = userMetadata(meta);
    readDirectLights(f, v, path);
    // Every level's grids: topology in memory, leaf values left in the mapped file until a
    // voxel of the leaf is read. The checks of readLevel / readMask that need no values
    // (active voxel counts, boxes and topologies come from the leaves' masks).
    auto read = [&](const std::string& name) {
        if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
        if (held.size() == held.capacity()) held.reserve(2 * held.capacity() + 64);  // before the grid: no allocation after it
        try {
            held.push_back(f.file->readGrid(name));
            return held.back();
        } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
            throw;
        } catch (const std::exception& e) {
            formatError(path, "grid '" + name + "' cannot be read (truncated or corrupt?): " + e.what());
        }
    };
    for (int l = 0; l < int(levels); ++l) {
        const GridSpec& g = v.levels[std::size_t(l)].grid;
        DelayedLevel level;
        Vec3SGrid::Ptr first;
        bool sparse = l > 0;
        for (std::size_t c = 0; c < v.basis.channelNames.size(); ++c) {
            openvdb::GridBase::Ptr base = read(gridNameFor(v.basis.channelNames[c], l));
            if (c == 0 && l == 0 && levels > 1) {
                const auto typed = openvdb::gridPtrCast<Vec3SGrid>(base);
                if (typed && typed->activeVoxelCount() < g.nodeCount()) sparse = true;  // culled
            }
            Vec3SGrid::Ptr grid = sparse ? checkSparseChannelGrid(base, g, first.get(), path) : checkChannelGrid(base, g, path);
            if (c == 0) first = grid;
            level.channels.push_back(grid);
        }
        if (f.file->hasGrid(gridNameFor(depth::channelName(0), l)))
            for (int c = 0; c < depth::kChannels; ++c) {
                openvdb::GridBase::Ptr base = read(gridNameFor(depth::channelName(c), l));
                Vec3SGrid::Ptr grid = sparse ? checkSparseChannelGrid(base, g, first.get(), path) : checkChannelGrid(base, g, path);
                level.depth.push_back(grid);
            }
        if (l + 1 < int(levels)) {
            const std::string name = maskNameFor(l);
            auto mask = openvdb::gridPtrCast<openvdb::BoolGrid>(read(name));
            if (!mask) formatError(path, "grid '" + name + "' has type other than bool");
            const double half = 0.5 * g.spacing;
            if (!placedAt(mask->transform(), g.origin + Vec3d(half, half, half), g.spacing))
                formatError(path, "grid '" + name + "' has a transform that does not match its level's cells");
            if (!insideBox(mask->evalActiveVoxelBoundingBox(), g.nx - 1, g.ny - 1, g.nz - 1))
                formatError(path, "grid '" + name + "' marks cells outside its level's cell range");
            level.mask = mask;
        }
        out.levels.push_back(std::move(level));
    }
    // bake --direct occlusion: one FloatGrid per listed light on level 0, as readDirect reads them.
    // Their shadow edges (shadow_edges.h), when the file has them: distance and width per light.
    if (v.direct.hasVisibility()) {
        const GridSpec& g = v.levels[0].grid;
        // Files from before the second edge hold distance and width only.
        const std::size_t edgeParts = !f.file->hasGrid(shadow_edge::distanceGridName(0))           ? 0
                                      : f.file->hasGrid(shadow_edge::partGridName(shadow_edge::kFar, 0)) ? shadow_edge::kFloatsPerLight
                                                                                                        : 2;
        for (std::size_t k = 0; k < v.direct.lights.size() * (1 + edgeParts); ++k) {
            const std::size_t i = k % v.direct.lights.size(), part = k / v.direct.lights.size();
            const std::string name = part == 0 ? visibilityGridName(i) : shadow_edge::partGridName(int(part) - 1, i);
            const openvdb::GridBase::Ptr base = read(name);
            auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
            if (!grid) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected float");
            if (!placedAt(grid->transform(), g.origin, g.spacing))
                formatError(path, "grid '" + name + "' has a transform that does not match its level's origin and spacing");
            const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
            if (grid->activeVoxelCount() != g.nodeCount() || box.min() != Coord(0, 0, 0) ||
                box.max() != Coord(g.nx - 1, g.ny - 1, g.nz - 1))
                formatError(path, "grid '" + name + "' does not have exactly one active voxel per node");
            grid->tree().voxelizeActiveTiles();
            (part == 0 ? out.visibility : out.edges).push_back(grid);
        }
    }
    out.file = std::move(f.file);
    return out;
}

/// Frees `grids` after an error, where a destructor that throws would end the process: each
/// grid's tree is emptied by Grid::clear inside a try (an empty tree's destructor allocates
/// nothing: Tree::clear then steals no nodes and runs its parallel_for on empty ranges), in an
/// arena of one thread, which starts no TBB worker; a grid that could not be emptied is kept
/// alive for good (its destructor would call Tree::clear again) rather than destroyed.
void emptyEach(std::vector<openvdb::GridBase::Ptr>& grids) {
    for (openvdb::GridBase::Ptr& grid : grids) {
        if (!grid) continue;
        try {
            grid->clear();
            grid.reset();
        } catch (...) {
        }
    }
}

void freeGridsAfterError(std::vector<openvdb::GridBase::Ptr>& grids) noexcept {
    try {
        tbb::task_arena alone(1);
        alone.execute([&] { emptyEach(grids); });
    } catch (...) {  // the arena could not be made: in the caller's
    }
    emptyEach(grids);
    for (openvdb::GridBase::Ptr& grid : grids)
        if (grid) new (std::nothrow) openvdb::GridBase::Ptr(std::move(grid));  // never destroyed
}

}  // namespace

DelayedVolumeFile openDelayedVolume(const std::string& path) {
    // Out of memory while the grids are read or checked (the checks run TBB, whose allocator
    // throws std::bad_alloc without calling the new-handler, and which throws std::runtime_error
    // when it cannot start a worker thread), the grids read so far must not be destroyed during
    // the unwinding: an OpenVDB tree's destructor allocates its node lists and runs a TBB
    // parallel_for, and a destructor that throws ends the process (std::terminate under
    // `prlimit --as` at 185-187 MB for a 5.2 MB default bake, and at 201 MB for the 40^3 volume
    // of cli_query_stream_test). So `held` keeps every grid until the handler below has given
    // back a reserve set aside here (so that the trees' clean-up finds memory) and freed them
    // where nothing throws.
    constexpr std::size_t kReserveBytes = 1u << 20;
    std::unique_ptr<void, void (*)(void*)> reserve(std::malloc(kReserveBytes), std::free);
    std::vector<openvdb::GridBase::Ptr> held;
    try {
        return openAndCheck(path, held);
    } catch (...) {
        reserve.reset();
        freeGridsAfterError(held);
        throw;
    }
}

}  // namespace vdblight::vdb_detail
