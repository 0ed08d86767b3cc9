// What `vdblight info` says about a file (vdb_io.h: volumeInfoText, volumeInfoJson; tiles.h:
// tileInfoText, tileInfoJson): a volume file's basis, direct light, levels, grids and metadata,
// or a tile file's identity, for people and as JSON with a fixed key order for scripts.
#include <cstdio>
#include <sstream>

#include "vdblight/basis.h"
#include "vdblight/direct_light.h"
#include "vdblight/interrupter.h"
#include "vdblight/tiles.h"
#include "vdblight/vdb_io.h"

namespace vdblight {

namespace {
std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        switch (ch) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(ch) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", ch);
                    out += buf;
                } else {
                    out += ch;
                }
        }
    }
    return out + "\"";
}

std::string metaText(const MetaValue& v, bool json) {
    if (auto s = std::get_if<std::string>(&v)) return json ? jsonString(*s) : *s;
    std::ostringstream o;
    o.precision(10);
    if (auto i = std::get_if<int64_t>(&v)) o << *i;
    else o << std::get<double>(v);
    return o.str();
}

std::string vec(const Vec3d& v, bool json) {
    std::ostringstream o;
    o.precision(9);
    o << (json ? "[" : "(") << v.x << ", " << v.y << ", " << v.z << (json ? "]" : ")");
    return o.str();
}

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
            << vec(g.nodeBounds().lo, false) << " - " << vec(g.nodeBounds().hi, false) << "\n";
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
    for (const auto& [key, value] : v.meta) out << "    " << key << " = " << metaText(value, false) << "\n";
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
    std::ostringstream o;
    o << "{\n  \"path\": " << jsonString(f.path) << ",\n  \"file_bytes\": " << f.fileBytes
      << ",\n  \"content_sha256\": " << jsonString(f.hash.sha256) << ",\n  \"header_uuid\": " << jsonString(f.hash.headerUuid)
      << ",\n  \"uuid_from_content\": " << (f.hash.uuidFromContent ? "true" : "false")
      << ",\n  \"basis\": " << jsonString(v.basis.kind) << ",\n  \"levels\": [";
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        const GridSpec& g = v.levels[l].grid;
        o << (l ? ", " : "") << "{\"dims\": [" << g.nx << ", " << g.ny << ", " << g.nz << "], \"nodes\": " << v.levels[l].storedNodes()
          << ", \"refined_cells\": " << v.levels[l].refinedCells.size()
          << ", \"spacing\": " << g.spacing << ", \"origin\": " << vec(g.origin, true)
          << ", \"node_bounds_min\": " << vec(g.nodeBounds().lo, true) << ", \"node_bounds_max\": " << vec(g.nodeBounds().hi, true) << "}";
    }
    o << "],\n  \"grids\": [";
    for (std::size_t i = 0; i < f.grids.size(); ++i) {
        const GridInfo& g = f.grids[i];
        o << (i ? ",\n    " : "\n    ") << "{\"name\": " << jsonString(g.name) << ", \"type\": " << jsonString(g.valueType)
          << ", \"active_voxels\": " << g.activeVoxels << ", \"memory_bytes\": " << g.memoryBytes
          << ", \"level\": " << g.level << ", \"voxel_size\": " << g.voxelSize << "}";
    }
    o << "\n  ],\n  \"metadata\": {";
    bool first = true;
    for (const auto& [key, value] : v.meta) {
        o << (first ? "\n    " : ",\n    ") << jsonString(key) << ": " << metaText(value, true);
        first = false;
    }
    o << "\n  }\n}\n";
    return o.str();
}

std::string tileInfoJson(const TileId& id, const FileInfo& f) {
    std::ostringstream o;
    o << "{\n  \"path\": " << jsonString(f.path) << ",\n  \"file_bytes\": " << f.fileBytes
      << ",\n  \"content_sha256\": " << jsonString(f.hash.sha256) << ",\n  \"tile_index\": " << id.index
      << ",\n  \"tile_count\": " << id.count << ",\n  \"tile_params_hash\": " << jsonString(id.paramsHash) << "\n}\n";
    return o.str();
}

}  // namespace vdblight
