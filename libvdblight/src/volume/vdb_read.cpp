// .vdb file -> Volume, with every structural fact checked (docs/format.md), and the grid
// listing behind `vdblight info`. The pieces are in vdb_read_parts.h.
#include <algorithm>
#include <climits>
#include <filesystem>
#include <new>

#include "vdb_read_parts.h"
#include "vdb_surface_bins.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {
using namespace vdb_detail;
namespace fs = std::filesystem;

/// GridInfo from a grid's metadata (loading the grid only if it lacks OpenVDB's statistics).
GridInfo describeGrid(openvdb::io::File& file, const openvdb::GridBase& grid) {
    GridInfo g;
    g.name = grid.getName();
    g.valueType = grid.valueType();
    const auto voxels = grid.getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_VOXEL_COUNT);
    const auto bytes = grid.getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_MEM_BYTES);
    if (voxels && bytes) {
        g.activeVoxels = uint64_t(voxels->value());
        g.memoryBytes = uint64_t(bytes->value());
    } else {
        const openvdb::GridBase::Ptr full = file.readGrid(g.name);
        g.activeVoxels = full->activeVoxelCount();
        g.memoryBytes = full->memUsage();
    }
    const auto level = grid.getMetadata<openvdb::Int64Metadata>(kPrefix + "level");
    g.level = level ? int(level->value()) : 0;
    g.voxelSize = grid.transform().voxelSize().x();
    return g;
}

}  // namespace

/// readVolume, and readProbeStage with `stage`; `hash` receives the file's content hash.
static Volume readVolumeFile(const std::string& path, bool stage, const ContentHash* knownHash, ContentHash* hash,
                             NodeWindow window = {}) {
    OpenedFile f = openVolumeFile(path, OpenFor::Data, knownHash);
    if (hash) *hash = f.hash;
    const openvdb::MetaMap& meta = *f.meta;
    const auto probeStage = meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "probe_stage");
    if (probeStage && !stage)
        formatError(path, "is stage " + std::to_string(probeStage->value()) + " of a staged bake (the reflected light of "
                          "a probe-to-probe pass), not a volume to look up: bake the next stage's tiles with "
                          "--stage-input " + path);
    if (!probeStage && stage)
        formatError(path, "is no probe stage file (no vdblight:probe_stage): give the merged tiles of the stage before");
    if (auto count = meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count")) {
        const auto index = meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_index");
        formatError(path, "is tile " + std::to_string(index ? index->value() : -1) + " of " +
                              std::to_string(count->value()) + " of a bake, not a complete volume: merge the tiles with "
                              "'vdblight merge TILES... -o OUT.vdb'");
    }
    Volume volume;
    volume.basis.kind = requireMeta<std::string>(meta, kPrefix + "basis", path);
    volume.basis.channelNames = splitNames(requireMeta<std::string>(meta, kPrefix + "channels", path));
    const int64_t levels = requireMeta<int64_t>(meta, kPrefix + "levels", path);
    if (levels < 1 || levels > 64) formatError(path, "has an invalid level count " + std::to_string(levels));
    for (int l = 0; l < int(levels); ++l)
        volume.levels.push_back(readLevel(f, volume.basis, l, path, levels > 1, window.first, window.count));
    if (levels > 1)
        for (int l = 0; l + 1 < int(levels); ++l) readMask(f, volume.levels[std::size_t(l)], l, path);
    volume.meta = userMetadata(meta);
    readDirect(f, volume, path);
    if (stage) readSurfaceBins(f, volume, path);
    try {
        volume.validate();
    } catch (const FormatError& e) {
        formatError(path, std::string("is inconsistent: ") + e.what());
    }
    return volume;
}

Volume readVolume(const std::string& path, ContentHash* hash) { return readVolumeFile(path, false, nullptr, hash); }

Volume readProbeStage(const std::string& path, const ContentHash* knownHash, NodeWindow window) {
    Volume v = readVolumeFile(path, true, knownHash, nullptr, window);
    if (!v.basis.sameKind(probeStageBasis()) || v.levels.size() != 1)
        throw FormatError("'" + path + "' is a probe stage file of another kind (basis " + v.basis.kind + ")");
    return v;
}

FileInfo inspectVolumeFile(const std::string& path, const ContentHash* knownHash) {
    OpenedFile f = openVolumeFile(path, OpenFor::Metadata);
    FileInfo info;
    info.path = path;
    info.hash = knownHash ? *knownHash : fileContentHash(path);
    info.fileBytes = uint64_t(fs::file_size(path));
    std::vector<std::pair<int64_t, GridInfo>> grids;  // (channel, info), to sort
    try {
        const openvdb::GridPtrVecPtr all = f.file->readAllGridMetadata();  // keep alive while iterating
        for (const openvdb::GridBase::Ptr& grid : *all) {
            const auto channel = grid->getMetadata<openvdb::Int64Metadata>(kPrefix + "channel");
            grids.emplace_back(channel ? channel->value() : INT64_MAX, describeGrid(*f.file, *grid));
        }
    } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
        throw;
    } catch (const std::exception& e) {
        formatError(path, std::string("has unreadable grids: ") + e.what());
    }
    std::stable_sort(grids.begin(), grids.end(), [](const auto& a, const auto& b) {
        return std::make_pair(a.second.level, a.first) < std::make_pair(b.second.level, b.first);
    });
    for (auto& entry : grids) info.grids.push_back(std::move(entry.second));
    return info;
}

}  // namespace vdblight
