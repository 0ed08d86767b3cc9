// Conventions shared by the .vdb writer (vdb_write.cpp) and reader (vdb_read.cpp): grid
// names, metadata keys, metadata conversion and the node <-> voxel transforms (docs/format.md).
// Internal to the volume module.
#pragma once

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/grid_index.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace vdb_detail {

using openvdb::Coord;
using openvdb::Vec3SGrid;
using Vec3STree = Vec3SGrid::TreeType;
using LeafT = Vec3STree::LeafNodeType;

const std::string kPrefix = "vdblight:";
constexpr int kLeafDim = int(LeafT::DIM);

inline void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

// ---------------------------------------------------------------------------------------
// Names and metadata keys

inline std::string gridNameFor(const std::string& channel, int level) {
    return level == 0 ? channel : channel + "_L" + std::to_string(level);
}

/// The mask of refined cells of level k (docs/format.md, "Levels").
inline std::string maskNameFor(int level) { return "refined_L" + std::to_string(level); }

inline std::string levelKey(int level, const char* what) {
    return kPrefix + "level" + std::to_string(level) + "_" + what;
}

/// Keys (without prefix) that the writer derives from the volume's structure; they are not
/// part of Volume::meta and a caller may not set them.
inline bool isStructuralKey(const std::string& key) {
    if (key == "format_version" || key == "basis" || key == "channels" || key == "levels") return true;
    if (key == "direct" || key == "direct_lights" || key.compare(0, 13, "direct_light_") == 0) return true;
    // level<digits>_origin, level<digits>_spacing, level<digits>_dims
    if (key.compare(0, 5, "level") != 0) return false;
    std::size_t pos = 5;
    while (pos < key.size() && key[pos] >= '0' && key[pos] <= '9') ++pos;
    const std::string rest = key.substr(pos);
    return pos > 5 && (rest == "_origin" || rest == "_spacing" || rest == "_dims");
}

/// Keys (without prefix) that only tile files carry (tiles.h: tile_index, tile_count, ...).
inline bool isTileKey(const std::string& key) { return key.compare(0, 5, "tile_") == 0; }

inline openvdb::Metadata::Ptr toVdbMeta(const MetaValue& value) {
    if (const auto* s = std::get_if<std::string>(&value)) return std::make_shared<openvdb::StringMetadata>(*s);
    if (const auto* i = std::get_if<int64_t>(&value)) return std::make_shared<openvdb::Int64Metadata>(*i);
    return std::make_shared<openvdb::DoubleMetadata>(std::get<double>(value));
}

/// Converts scalar OpenVDB metadata to a MetaValue; false for other types (vectors, ...).
inline bool fromVdbMeta(const openvdb::Metadata& m, MetaValue& out) {
    const std::string type = m.typeName();
    if (type == "string") out = static_cast<const openvdb::StringMetadata&>(m).value();
    else if (type == "int64") out = int64_t(static_cast<const openvdb::Int64Metadata&>(m).value());
    else if (type == "int32") out = int64_t(static_cast<const openvdb::Int32Metadata&>(m).value());
    else if (type == "bool") out = int64_t(static_cast<const openvdb::BoolMetadata&>(m).value());
    else if (type == "double") out = static_cast<const openvdb::DoubleMetadata&>(m).value();
    else if (type == "float") out = double(static_cast<const openvdb::FloatMetadata&>(m).value());
    else return false;
    return true;
}

inline std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i) out += (i ? "," : "") + names[i];
    return out;
}

inline std::vector<std::string> splitNames(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        out.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return out;
}

inline openvdb::math::Transform::Ptr levelTransform(const GridSpec& g) {
    auto xform = openvdb::math::Transform::createLinearTransform(g.spacing);
    xform->postTranslate(openvdb::Vec3d(g.origin.x, g.origin.y, g.origin.z));
    return xform;
}

/// A mask voxel (i, j, k) is the cell whose lower corner is node (i, j, k): its centre sits
/// half a spacing above that node.
inline openvdb::math::Transform::Ptr maskTransform(const GridSpec& g) {
    auto xform = openvdb::math::Transform::createLinearTransform(g.spacing);
    const double half = 0.5 * g.spacing;
    xform->postTranslate(openvdb::Vec3d(g.origin.x + half, g.origin.y + half, g.origin.z + half));
    return xform;
}

inline Coord unpackCoord(const GridSpec& g, uint64_t linear) {
    const core::Index3 c = core::unflatten(linear, uint64_t(g.nx), uint64_t(g.ny));
    return Coord(c.i, c.j, c.k);
}

/// Name of the optional per-node scalar grid (VolumeLevel::validity; docs/format.md).
const std::string kValidityName = "validity";

/// Direct light (occlusion mode): the visibility grid of listed light i, and the metadata key
/// (without prefix) of light i's description (direct_light.h, docs/format.md).
inline std::string visibilityGridName(std::size_t i) { return "light_visibility_" + std::to_string(i); }
inline std::string directLightKey(std::size_t i) { return "direct_light_" + std::to_string(i); }
/// Tile files (tiles.h): the FloatGrid of the tile's per-node estimated errors (level 0).
const std::string kTileErrorName = "tile_estimated_error";
/// A last-stage tile's pass-0 values (one grid per float of a node, "tile_first_pass_<f>") and
/// errors, for the merge's blend (TileNodeStats::firstPassValues).
const std::string kTileFirstPassPrefix = "tile_first_pass_";
const std::string kTileFirstPassErrorName = "tile_first_pass_error";
using FloatLeafT = openvdb::FloatGrid::TreeType::LeafNodeType;
/// Photon tiles (tiles.h, writePhotonTile): the Int64Grid of one 64-bit word of value v
/// (0..53, the volume's float order) of every node's 128-bit photon sums.
inline std::string photonSumGridName(int v, bool high) {
    return "tile_photon_sum_" + std::to_string(v) + (high ? "_hi" : "_lo");
}

/// Probe stage volumes of `--probe-cache surface` (SurfaceBinSums, surface_bin_sums.h): the Int64Grid of
/// value v (0..41: bin face v / 7, value v % 7) of every cell with samples in that bin; the
/// bins' unit is metadata of grid 0.
inline std::string surfaceBinGridName(int v) { return "surface_bins_" + std::to_string(v); }
const std::string kSurfaceBinUnitKey = "surface_bins_unit";

}  // namespace vdb_detail
}  // namespace vdblight
