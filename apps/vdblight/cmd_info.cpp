// vdblight info VOLUME: grids, resolution, bounds, node count, bytes and bake metadata.
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app_common.h"
#include "commands.h"
#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::app {

namespace {
// info --json: keys in the order they are added, as the human-readable listing reads.
using Json = nlohmann::ordered_json;

std::string metaText(const MetaValue& v) {
    if (auto s = std::get_if<std::string>(&v)) return *s;
    std::ostringstream o;
    o.precision(10);
    if (auto i = std::get_if<int64_t>(&v)) o << *i;
    else o << std::get<double>(v);
    return o.str();
}
Json metaJson(const MetaValue& v) {
    if (auto s = std::get_if<std::string>(&v)) return *s;
    if (auto i = std::get_if<int64_t>(&v)) return *i;
    return std::get<double>(v);
}

std::string vec(const Vec3d& v) {
    std::ostringstream o;
    o.precision(9);
    o << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return o.str();
}
Json vecJson(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }

/// The document on stdout; a file name or metadata string that is not UTF-8 shows U+FFFD.
void printDocument(const Json& j) {
    std::cout << j.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
}

/// What the channels of a basis hold, for the human-readable listing: the registered basis's
/// own phrase (basis.h), or the irradiance-vector kinds, which the registry does not hold.
std::string describeChannels(const BasisDesc& basis) {
    if (const std::unique_ptr<Basis> b = basisOf(basis)) return " RGB channels: " + b->describe();
    if (basis.isIrradianceVectors()) return " channels: irradiance vectors per direction and colour";
    if (basis.isCompactIrradianceVectors()) return " channels: colour and direction per direction";
    return " channels";
}

void printHuman(const Volume& v, const FileInfo& f) {
    std::cout << f.path << ": " << formatBytes(double(f.fileBytes)) << " on disk\n"
              << "  content hash: sha256 " << f.hash.sha256 << " (header UUID " << f.hash.headerUuid
              << (f.hash.uuidFromContent ? ", derived from it" : ", random: not written by this version") << ")\n"
              << "  basis: " << v.basis.kind << " (" << v.basis.channelCount() << describeChannels(v.basis) << ")\n";
    // bake --direct (docs/format.md, "Direct light").
    std::cout << "  direct light: " << directModeName(v.direct.mode);
    if (!v.direct.lights.empty())
        std::cout << ", " << v.direct.lights.size() << " listed light" << (v.direct.lights.size() == 1 ? "" : "s")
                  << (v.direct.hasVisibility() ? " with visibility grids" : " (added at run time)");
    std::cout << "\n";
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        const GridSpec& g = v.levels[l].grid;
        std::cout << "  level " << l << ": " << g.nx << " x " << g.ny << " x " << g.nz << " box, "
                  << v.levels[l].storedNodes() << (v.levels[l].sparse() ? " active" : "") << " nodes, "
                  << v.levels[l].refinedCells.size() << " refined cells, spacing " << g.spacing << ", node bounds " << vec(g.nodeBounds().lo) << " - "
                  << vec(g.nodeBounds().hi) << "\n";
    }
    if (v.levels.size() > 1) {  // multi-level: what the sparse topology saves against the dense box
        uint64_t stored = 0;
        for (const VolumeLevel& l : v.levels) stored += l.storedNodes();
        const double dense = double(v.levels.back().grid.nodeCount());
        std::cout << "  nodes: " << stored << " stored vs " << dense << " in a dense box at the finest spacing ("
                  << 100.0 * (1.0 - double(stored) / dense) << " % saved); "
                  << int64_t(metaNumber(v.meta, "nodes_culled", 0)) << " culled inside closed solids\n";
    }
    std::cout << "  grids:\n";
    for (const GridInfo& g : f.grids)
        std::cout << "    " << g.name << "  " << g.valueType << "  " << g.activeVoxels << " active voxels  "
                  << formatBytes(double(g.memoryBytes)) << " in memory\n";
    std::cout << "  metadata (vdblight:*):\n";
    for (const auto& [key, value] : v.meta) std::cout << "    " << key << " = " << metaText(value) << "\n";
}

void printJson(const Volume& v, const FileInfo& f) {
    Json j;
    j["path"] = f.path;
    j["file_bytes"] = f.fileBytes;
    j["content_sha256"] = f.hash.sha256;
    j["header_uuid"] = f.hash.headerUuid;
    j["uuid_from_content"] = f.hash.uuidFromContent;
    j["basis"] = v.basis.kind;
    Json levels = Json::array();
    for (const VolumeLevel& level : v.levels) {
        const GridSpec& g = level.grid;
        levels.push_back({{"dims", {g.nx, g.ny, g.nz}}, {"nodes", level.storedNodes()},
                          {"refined_cells", level.refinedCells.size()}, {"spacing", g.spacing},
                          {"origin", vecJson(g.origin)}, {"node_bounds_min", vecJson(g.nodeBounds().lo)},
                          {"node_bounds_max", vecJson(g.nodeBounds().hi)}});
    }
    j["levels"] = std::move(levels);
    Json grids = Json::array();
    for (const GridInfo& g : f.grids)
        grids.push_back({{"name", g.name}, {"type", g.valueType}, {"active_voxels", g.activeVoxels},
                         {"memory_bytes", g.memoryBytes}, {"level", g.level}, {"voxel_size", g.voxelSize}});
    j["grids"] = std::move(grids);
    Json meta = Json::object();
    for (const auto& [key, value] : v.meta) meta[key] = metaJson(value);
    j["metadata"] = std::move(meta);
    printDocument(j);
}
/// A tile of a bake (bake --tiles): its identity, grids and content hash.
void printTile(const std::string& path, const TileId& id, bool json) {
    const FileInfo f = inspectVolumeFile(path);
    if (json) {
        printDocument({{"path", path}, {"file_bytes", f.fileBytes}, {"content_sha256", f.hash.sha256},
                       {"tile_index", id.index}, {"tile_count", id.count}, {"tile_params_hash", id.paramsHash}});
        return;
    }
    std::cout << path << ": tile " << id.index << " of " << id.count << " of a bake (merge with 'vdblight merge'), "
              << formatBytes(double(f.fileBytes)) << " on disk\n"
              << "  parameter hash: " << id.paramsHash << "\n"
              << "  content hash: sha256 " << f.hash.sha256 << "\n  grids:\n";
    for (const GridInfo& g : f.grids)
        std::cout << "    " << g.name << "  " << g.valueType << "  " << g.activeVoxels << " active voxels\n";
}
}  // namespace

void addInfoCommand(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand("info", "Describe a baked volume: grids, resolution, bounds, metadata");
    cmd->add_option("volume", *path, "Volume (.vdb)")->required();
    cmd->add_flag("--json", *json, "Machine-readable JSON");
    cmd->callback([path, json] {
        bool prt = false;  // a PRT file holds samples and transfer, not a volume
        try {
            prt = isPrtFile(*path);
        } catch (const Error&) {
        }  // readVolume below reports unreadable files as before
        if (prt) return printPrtInfo(*path);
        TileId tile;
        if (readTileId(*path, tile)) return printTile(*path, tile, *json);
        ContentHash hash;  // the damage check's, reused: the file is hashed once
        const Volume volume = readVolume(*path, &hash);
        const FileInfo info = inspectVolumeFile(*path, &hash);
        if (*json) printJson(volume, info);
        else printHuman(volume, info);
    });
}

}  // namespace vdblight::app
