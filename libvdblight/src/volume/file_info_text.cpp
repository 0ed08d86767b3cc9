// What `vdblight info` says about a file (vdb_io.h: volumeInfoText, volumeInfoJson; tiles.h:
// tileInfoText, tileInfoJson): a volume file's basis, direct light, levels, grids and metadata,
// or a tile file's identity, for people and as JSON with a fixed key order for scripts.
#include <sstream>

#include <nlohmann/json.hpp>

#include "vdblight/basis/basis.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {

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

/// The document as `info --json` prints it; a file name or metadata string that is not UTF-8
/// shows U+FFFD.
std::string documentText(const Json& j) { return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n"; }

/// What the channels of a basis hold, for the human-readable listing: the registered basis's
/// own phrase (basis.h), or the irradiance-vector kinds, which the registry does not hold.
std::string describeChannels(const BasisDesc& basis) {
    if (const std::unique_ptr<Basis> b = basisOf(basis)) return " RGB channels: " + b->describe();
    if (basis.isIrradianceVectors()) return " channels: irradiance vectors per direction and colour";
    if (basis.isCompactIrradianceVectors()) return " channels: colour and direction per direction";
    return " channels";
}
}  // namespace

std::string volumeInfoText(const Volume& v, const FileInfo& f) {
    std::ostringstream out;
    out << f.path << ": " << formatBytes(double(f.fileBytes)) << " on disk\n"
        << "  content hash: sha256 " << f.hash.sha256 << " (header UUID " << f.hash.headerUuid
        << (f.hash.uuidFromContent ? ", derived from it" : ", random: not written by this version") << ")\n"
        << "  basis: " << v.basis.kind << " (" << v.basis.channelCount() << describeChannels(v.basis) << ")\n";
    // bake --direct (docs/format.md, "Direct light").
    out << "  direct light: " << directModeName(v.direct.mode);
    if (!v.direct.lights.empty())
        out << ", " << v.direct.lights.size() << " listed light" << (v.direct.lights.size() == 1 ? "" : "s")
            << (v.direct.hasVisibility() ? " with visibility grids" : " (added at run time)");
    out << "\n";
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        const GridSpec& g = v.levels[l].grid;
        out << "  level " << l << ": " << g.nx << " x " << g.ny << " x " << g.nz << " box, "
            << v.levels[l].storedNodes() << (v.levels[l].sparse() ? " active" : "") << " nodes, "
            << v.levels[l].refinedCells.size() << " refined cells, spacing " << g.spacing << ", node bounds "
            << vec(g.nodeBounds().lo) << " - " << vec(g.nodeBounds().hi) << "\n";
    }
    if (v.levels.size() > 1) {  // multi-level: what the sparse topology saves against the dense box
        uint64_t stored = 0;
        for (const VolumeLevel& l : v.levels) stored += l.storedNodes();
        const double dense = double(v.levels.back().grid.nodeCount());
        out << "  nodes: " << stored << " stored vs " << dense << " in a dense box at the finest spacing ("
            << 100.0 * (1.0 - double(stored) / dense) << " % saved); "
            << int64_t(metaNumber(v.meta, "nodes_culled", 0)) << " culled inside closed solids\n";
    }
    out << "  grids:\n";
    for (const GridInfo& g : f.grids)
        out << "    " << g.name << "  " << g.valueType << "  " << g.activeVoxels << " active voxels  "
            << formatBytes(double(g.memoryBytes)) << " in memory\n";
    out << "  metadata (vdblight:*):\n";
    for (const auto& [key, value] : v.meta) out << "    " << key << " = " << metaText(value) << "\n";
    return out.str();
}

std::string tileInfoText(const TileId& id, const FileInfo& f) {
    std::ostringstream out;
    out << f.path << ": tile " << id.index << " of " << id.count << " of a bake (merge with 'vdblight merge'), "
        << formatBytes(double(f.fileBytes)) << " on disk\n"
        << "  parameter hash: " << id.paramsHash << "\n"
        << "  content hash: sha256 " << f.hash.sha256 << "\n  grids:\n";
    for (const GridInfo& g : f.grids)
        out << "    " << g.name << "  " << g.valueType << "  " << g.activeVoxels << " active voxels\n";
    return out.str();
}

std::string volumeInfoJson(const Volume& v, const FileInfo& f) {
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
    return documentText(j);
}

std::string tileInfoJson(const TileId& id, const FileInfo& f) {
    return documentText({{"path", f.path}, {"file_bytes", f.fileBytes}, {"content_sha256", f.hash.sha256},
                         {"tile_index", id.index}, {"tile_count", id.count}, {"tile_params_hash", id.paramsHash}});
}

}  // namespace vdblight
