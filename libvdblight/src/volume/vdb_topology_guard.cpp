// A grid's tree topology counts against the bytes it has (vdb_topology_guard.h).
#include "vdb_topology_guard.h"

#include <algorithm>
#include <optional>
#include <type_traits>

#include <openvdb/openvdb.h>

#include "vdblight/core/errors.h"

namespace vdblight::vdb_detail {

namespace {

/// The fewest bytes a root tile and a root child node take in a tree's topology
/// (RootNode::writeTopology): a tile is its origin, its value and its active flag; a child is
/// its origin and then at least its child and value masks (InternalNode::writeTopology writes
/// both whole, then its values, then its children).
struct RootEntryBytes {
    uint64_t value = 0;  ///< the background, written before the counts
    uint64_t tile = 0;
    uint64_t child = 0;
};

/// For a grid type OpenVDB registers by default; nothing for another type (a grid of a type
/// this build does not know cannot be read at all, so it needs no check).
std::optional<RootEntryBytes> rootEntryBytes(const std::string& gridType) {
    if (!openvdb::GridBase::isRegistered(gridType)) return std::nullopt;
    std::optional<RootEntryBytes> bytes;
    openvdb::GridBase::createGrid(gridType)->apply<openvdb::GridTypes>([&](const auto& grid) {
        using RootT = typename std::decay_t<decltype(grid)>::TreeType::RootNodeType;
        using MaskT = typename RootT::ChildNodeType::NodeMaskType;
        constexpr uint64_t origin = 3 * sizeof(openvdb::Int32);
        RootEntryBytes b;
        b.value = sizeof(typename RootT::ValueType);  // also when saved as half floats
        b.tile = origin + b.value + sizeof(bool);
        b.child = origin + 2 * uint64_t(MaskT::memUsage());
        bytes = b;
    });
    return bytes;
}

/// The grid type without the suffix GridDescriptor adds for half floats ("_HalfFloat",
/// io/GridDescriptor.cc; not in OpenVDB's headers).
std::string baseType(const std::string& stored) {
    static const std::string kHalf = "_HalfFloat";
    if (stored.size() > kHalf.size() && stored.compare(stored.size() - kHalf.size(), kHalf.size(), kHalf) == 0)
        return stored.substr(0, stored.size() - kHalf.size());
    return stored;
}

/// Moves `is` from the grid's start to its tree topology (io::Archive::readGrid's order: the
/// compression flags, the metadata, then the transform, which files older than 216 write after
/// the tree). False if the metadata or transform cannot be read: OpenVDB's own read stops
/// there too.
bool seekTopology(std::istream& is, const GridExtent& grid) {
    const uint32_t version = openvdb::io::getFormatVersion(is);
    is.seekg(grid.gridPos, std::ios_base::beg);
    if (version >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) is.ignore(sizeof(uint32_t));
    try {
        openvdb::MetaMap().readMeta(is);  // its lengths are checked (vdb_open.cpp, checkMetaMap)
        if (version < openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) return bool(is);
        // The transform starts with its map's type name, whose length OpenVDB allocates unchecked.
        uint32_t nameBytes = 0;
        const std::streampos at = is.tellg();
        is.read(reinterpret_cast<char*>(&nameBytes), sizeof nameBytes);
        if (!is || int64_t(nameBytes) > grid.endPos - int64_t(is.tellg())) return false;
        is.seekg(at);
        openvdb::math::Transform().read(is);
    } catch (const openvdb::Exception&) {  // e.g. a map type OpenVDB does not know
        return false;
    }
    return bool(is);
}

[[noreturn]] void refuse(const std::string& path, const GridExtent& grid, uint32_t count, const char* what,
                         uint64_t room) {
    throw FormatError("'" + path + "' grid '" + grid.name + "' declares " + std::to_string(count) + " " + what +
                      ", but its topology has room for at most " + std::to_string(room) + " (corrupt file?)");
}

}  // namespace

void checkTreeTopology(std::istream& is, const GridExtent& grid, const std::string& path) {
    // Files older than 213 store the root as masks over a table of the size they give (not
    // counts), and an instance stores no tree.
    if (grid.instance || openvdb::io::getFormatVersion(is) < openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP) return;
    const std::optional<RootEntryBytes> bytes = rootEntryBytes(baseType(grid.type));
    if (!bytes) return;
    const std::streampos start = is.tellg();
    if (!seekTopology(is, grid)) {
        is.clear();
        is.seekg(start);
        return;
    }
    // Tree::readTopology: the buffer count (OpenVDB writes 1, and only warns about another
    // value, which then drives no loop); RootNode::readTopology: the background, then the tile
    // and child counts.
    int32_t buffers = 0;
    uint32_t tiles = 0, children = 0;
    is.read(reinterpret_cast<char*>(&buffers), sizeof buffers);
    is.ignore(std::streamsize(bytes->value));
    is.read(reinterpret_cast<char*>(&tiles), sizeof tiles);
    is.read(reinterpret_cast<char*>(&children), sizeof children);
    const int64_t left = is ? grid.endPos - int64_t(is.tellg()) : 0;
    const bool counted = bool(is);
    is.clear();
    is.seekg(start);
    if (!counted) return;  // the file ends before the counts: OpenVDB's reads of them fail, no loop
    const uint64_t room = uint64_t(std::max<int64_t>(left, 0));
    if (tiles > room / bytes->tile) refuse(path, grid, tiles, "root tiles", room / bytes->tile);
    const uint64_t afterTiles = room - tiles * bytes->tile;
    if (children > afterTiles / bytes->child) refuse(path, grid, children, "root child nodes", afterTiles / bytes->child);
}

}  // namespace vdblight::vdb_detail
