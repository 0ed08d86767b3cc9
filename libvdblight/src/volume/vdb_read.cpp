// .vdb file -> Volume, with every structural fact checked (docs/format.md), and the grid
// listing behind `vdblight info`.
#include "vdblight/vdb_io.h"
#include <fcntl.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <tbb/parallel_for.h>
#include "vdblight/depth_moments.h"
#include "vdblight/errors.h"
#include "vdb_conventions.h"
#include "content_hash.h"
#include "tile_io.h"
#include "vdblight/irradiance_vectors.h"
#include "vdblight/photon_sums.h"
#include "vdb_delayed.h"

namespace vdblight {
namespace {
using namespace vdb_detail;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Reading

/// An opened vdblight file whose header and file metadata have been checked.
struct OpenedFile {
    std::unique_ptr<openvdb::io::File> file;
    openvdb::MetaMap::Ptr meta;
    int64_t version = 0;
    ContentHash hash;  ///< set when opened for Data: the hash the damage check computed (or was given)
};

[[noreturn]] void formatError(const std::string& path, const std::string& what) {
    throw FormatError("'" + path + "' " + what);
}

/// Reads grid `name` of the file; FormatError naming the file if it cannot be read.
openvdb::GridBase::Ptr readGridChecked(OpenedFile& f, const std::string& name, const std::string& path) {
    try {
        return f.file->readGrid(name);
    } catch (const std::exception& e) {
        formatError(path, "grid '" + name + "' cannot be read (truncated or corrupt?): " + e.what());
    }
}

void checkReadable(const std::string& path) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) throw IoError("cannot read '" + path + "': no such file");
    if (fs::is_directory(status)) throw IoError("cannot read '" + path + "': is a directory");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw IoError("cannot read '" + path + "': " + std::strerror(errno));
}

/// Reads the grid table of a .vdb the way io::File::open does, but with every read checked,
/// to find where the last grid's data ends. OpenVDB itself reads a file that lacks its last
/// bytes without complaint (leaving garbage in the last leaves), so the reader compares this
/// end with the file size.
class GridTableScanner : public openvdb::io::Archive {
public:
    /// Byte offset just past the last grid (0 if the file has no grid offsets).
    int64_t dataEnd(std::istream& is, int64_t fileBytes) {
        readHeader(is);
        auto streamMeta = std::make_shared<openvdb::io::StreamMetadata>();  // as io::File::open does
        streamMeta->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(is, streamMeta, /*transfer=*/false);
        setFormatVersion(is);
        setLibraryVersion(is);
        setDataCompression(is);
        checkMetaMap(is, fileBytes);
        openvdb::MetaMap().readMeta(is);
        if (!is) throw std::runtime_error("cannot read the file metadata");
        // Without grid offsets (an io::Stream file) OpenVDB reads each grid's descriptor and
        // data in one pass, lengths unchecked (fuzz_vdb: a name length of gigabytes); vdblight
        // and io::File (Houdini, Blender, pyopenvdb) always write the offsets.
        if (!inputHasGridOffsets())
            throw std::runtime_error("it has no grid offsets (written as a stream?), which this reader needs");
        const int32_t count = readGridCount(is);
        if (!is || count < 0) throw std::runtime_error("cannot read the grid count");
        int64_t end = 0;
        for (int32_t n = 0; n < count; ++n) {
            skipString(is);  // unique name
            skipString(is);  // type
            if (openvdb::io::getFormatVersion(is) >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) skipString(is);
            int64_t offsets[3] = {0, 0, 0};  // grid, blocks, end
            is.read(reinterpret_cast<char*>(offsets), sizeof offsets);
            if (!is) throw std::runtime_error("grid table ends early");
            if (offsets[0] < 0 || offsets[0] > fileBytes || offsets[2] < offsets[0])
                throw std::runtime_error("grid table is corrupt");
            end = std::max(end, offsets[2]);
            const std::streampos next = is.tellg();
            is.seekg(offsets[0], std::ios_base::beg);  // the grid: compression flags, then its metadata
            if (openvdb::io::getFormatVersion(is) >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) is.ignore(4);
            checkMetaMap(is, fileBytes);
            is.seekg(next);
            is.seekg(offsets[2], std::ios_base::beg);
        }
        return end;
    }

private:
    /// Checks that every length in the metadata map at the stream's position (count, then per
    /// entry name, type name and value, each length-prefixed) fits in the file, leaving the
    /// stream where it was: OpenVDB allocates each length it reads before reading the bytes, so
    /// a corrupt length would otherwise allocate gigabytes.
    static void checkMetaMap(std::istream& is, int64_t fileBytes) {
        const std::streampos start = is.tellg();
        int32_t count = 0;
        is.read(reinterpret_cast<char*>(&count), sizeof count);
        if (!is || count < 0 || count > fileBytes) throw std::runtime_error("metadata is corrupt");
        auto skip = [&](uint32_t size) {
            if (!is || int64_t(size) > fileBytes - int64_t(is.tellg())) throw std::runtime_error("metadata is corrupt");
            is.seekg(std::streamoff(size), std::ios_base::cur);
        };
        for (int32_t n = 0; n < count; ++n) {
            uint32_t size = 0;
            is.read(reinterpret_cast<char*>(&size), sizeof size);  // name
            skip(size);
            is.read(reinterpret_cast<char*>(&size), sizeof size);  // type name
            if (!is || int64_t(size) > fileBytes - int64_t(is.tellg())) throw std::runtime_error("metadata is corrupt");
            std::string typeName(size, '\0');
            is.read(typeName.data(), std::streamsize(size));
            is.read(reinterpret_cast<char*>(&size), sizeof size);  // value
            // OpenVDB reads a fixed-size type as sizeof(value) bytes whatever length the file
            // gives, so a length that disagrees would put its parse out of step with this check
            // (and its next length would come from inside a value, found by fuzz_vdb): refuse it.
            const uint32_t fixed = fixedMetadataSize(typeName);
            if (is && fixed != 0 && size != fixed) throw std::runtime_error("metadata is corrupt");
            skip(size);
        }
        if (!is) throw std::runtime_error("metadata is corrupt");
        is.seekg(start);
    }

    /// The byte size OpenVDB reads for a fixed-size metadata type, 0 for variable-size and
    /// unknown types (those are read by the length the file gives).
    static uint32_t fixedMetadataSize(const std::string& type) {
        static const std::pair<const char*, uint32_t> kSizes[] = {
            {"bool", 1},   {"int32", 4},  {"int64", 8},  {"float", 4},  {"double", 8}, {"vec2i", 8},
            {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
            {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}};
        for (const auto& [name, bytes] : kSizes)
            if (type == name) return bytes;
        return 0;
    }

    static void skipString(std::istream& is) {
        uint32_t size = 0;
        is.read(reinterpret_cast<char*>(&size), sizeof size);
        if (!is || size > (1u << 20)) throw std::runtime_error("grid table ends early or is corrupt");
        is.ignore(size);
    }
};

void checkNotTruncated(const std::string& path) {
    std::ifstream is(path, std::ios::binary);
    const auto bytes = int64_t(fs::file_size(path));
    int64_t end = 0;
    try {
        end = GridTableScanner().dataEnd(is, bytes);
    } catch (const std::exception& e) {
        formatError(path, std::string("is not a readable .vdb file (truncated or corrupt?): ") + e.what());
    }
    if (end > bytes) {
        formatError(path, "is truncated: its grids end at byte " + std::to_string(end) + " but it has only " +
                              std::to_string(bytes) + " bytes");
    }
}

template <typename T>
T requireMeta(const openvdb::MetaMap& meta, const std::string& key, const std::string& path) {
    auto m = meta.getMetadata<openvdb::TypedMetadata<T>>(key);
    if (!m) {
        formatError(path, "has no metadata " + key + " of type " + openvdb::TypedMetadata<T>::staticTypeName());
    }
    return m->value();
}

/// How much of a file a reader will let OpenVDB parse.
enum class OpenFor {
    Data,      ///< every grid's node data: the content hash is checked first (checkNotDamaged)
    Metadata,  ///< only the metadata and grid descriptors
    Delayed,   ///< delayed loading (vdb_stream.h): hashing the whole file is what it avoids
};

/// Refuses a file whose header holds a content-derived UUID that its content does not give:
/// it changed after it was written (a bad copy, a disk error, an edit). The check comes before
/// OpenVDB parses any node data because OpenVDB 10 reads a corrupt leaf's blosc block past the
/// end of its buffer (tests/fuzz/known_crashes.txt). It costs one SHA-256 pass over the file;
/// a file with another writer's (random) UUID cannot be checked this way (docs/format.md).
void checkNotDamaged(const std::string& path, const ContentHash& hash) {
    if (hash.damaged)
        formatError(path, "is damaged: its content no longer gives the UUID stamped in its header when it was "
                          "written (changed or corrupted since; copy or bake it again)");
}

/// `knownHash` (purpose Data): the file's content hash if the caller has it, else it is computed.
OpenedFile openVolumeFile(const std::string& path, OpenFor purpose, const ContentHash* knownHash = nullptr) {
    initOpenVdb();
    checkReadable(path);
    checkNotTruncated(path);
    OpenedFile f;
    if (purpose == OpenFor::Data) {
        f.hash = knownHash ? *knownHash : fileContentHash(path);
        checkNotDamaged(path, f.hash);
    }
    const bool delayLoad = purpose == OpenFor::Delayed;
    f.file = std::make_unique<openvdb::io::File>(path);
    try {
        // Delayed loading (vdb_stream.h) maps the file and must not copy it first (OpenVDB
        // copies files below a size to a temporary file unless told not to).
        if (delayLoad) f.file->setCopyMaxBytes(0);
        f.file->open(delayLoad);
        f.meta = f.file->getMetadata();
    } catch (const std::exception& e) {
        formatError(path, std::string("is not a readable .vdb file (truncated or corrupt?): ") + e.what());
    }
    if (auto kind = f.meta->getMetadata<openvdb::StringMetadata>(kPrefix + "kind"); kind && kind->value() == "prt") {
        formatError(path, "is a PRT file, not a vdblight volume (make one with 'vdblight prt relight --volume-out')");
    }
    openvdb::Metadata::Ptr version = (*f.meta)[kPrefix + "format_version"];
    MetaValue v;
    if (!version || !fromVdbMeta(*version, v) || std::holds_alternative<std::string>(v)) {
        formatError(path, "is not a vdblight volume (no vdblight:format_version metadata)");
    }
    if (const double* d = std::get_if<double>(&v)) {  // a double beyond int64 (or NaN) must not be cast
        if (!(*d >= 1 && *d <= double(kFormatVersion)))
            formatError(path, "has format version " + std::to_string(*d) + "; this build reads versions 1 to " +
                                  std::to_string(kFormatVersion));
        f.version = int64_t(*d);
    } else {
        f.version = std::get<int64_t>(v);
    }
    if (f.version > kFormatVersion || f.version < 1) {
        formatError(path, "has format version " + std::to_string(f.version) + "; this build reads versions 1 to " +
                              std::to_string(kFormatVersion));
    }
    return f;
}

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
void copyChannel(const Vec3SGrid& grid, VolumeLevel& level, int channel, int channels) {
    std::vector<const LeafT*> leaves;
    leaves.reserve(grid.tree().leafCount());
    for (auto it = grid.tree().cbeginLeaf(); it; ++it) leaves.push_back(it.getLeaf());
    const GridSpec& g = level.grid;
    tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t n) {
        for (auto v = leaves[n]->cbeginValueOn(); v; ++v) {
            const Coord c = v.getCoord();
            float* out = level.data.data() + (g.index(c.x(), c.y(), c.z()) * channels + channel) * 3;
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
std::vector<float> readScalarGrid(OpenedFile& f, const std::string& name, const GridSpec& g, const std::string& path) {
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
}

/// Reads the optional depth-moment grids of a level (depth_moments.h): all four or an error,
/// with exactly the channel grids' active voxels; values in [0, 1] are checked by validate.
void readDepth(OpenedFile& f, VolumeLevel& out, int level, const std::string& path) {
    VolumeLevel tmp;
    tmp.grid = out.grid;
    tmp.activeNodes = out.activeNodes;
    tmp.data.assign(out.storedNodes() * depth::kFloatsPerNode, 0.0f);
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

VolumeLevel readLevel(OpenedFile& f, const BasisDesc& basis, int level, const std::string& path, bool multiLevel) {
    VolumeLevel out;
    out.grid = readLevelSpec(*f.meta, level, path);
    const GridSpec& g = out.grid;
    if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin)) {
        formatError(path, "has invalid dimensions, spacing or origin for level " + std::to_string(level));
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
        if (out.data.empty()) out.data.assign(g.nodeCount() * std::size_t(channels) * 3, 0.0f);
        copyChannel(*grid, out, c, channels);
    }
    const std::string validityName = gridNameFor(kValidityName, level);
    if (level == 0 && f.file->hasGrid(validityName)) out.validity = readScalarGrid(f, validityName, out.grid, path);
    if (f.file->hasGrid(gridNameFor(depth::channelName(0), level))) readDepth(f, out, level, path);
    return out;
}

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
static Volume readVolumeFile(const std::string& path, bool stage, const ContentHash* knownHash, ContentHash* hash) {
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
    for (int l = 0; l < int(levels); ++l) volume.levels.push_back(readLevel(f, volume.basis, l, path, levels > 1));
    if (levels > 1)
        for (int l = 0; l + 1 < int(levels); ++l) readMask(f, volume.levels[std::size_t(l)], l, path);
    volume.meta = userMetadata(meta);
    readDirect(f, volume, path);
    try {
        volume.validate();
    } catch (const FormatError& e) {
        formatError(path, std::string("is inconsistent: ") + e.what());
    }
    return volume;
}

Volume readVolume(const std::string& path, ContentHash* hash) { return readVolumeFile(path, false, nullptr, hash); }

Volume readProbeStage(const std::string& path, const ContentHash* knownHash) {
    Volume v = readVolumeFile(path, true, knownHash, nullptr);
    if (v.basis.kind != probeStageBasis().kind || v.levels.size() != 1)
        throw FormatError("'" + path + "' is a probe stage file of another kind (basis " + v.basis.kind + ")");
    return v;
}

namespace vdb_detail {

DelayedVolumeFile openDelayedVolume(const std::string& path) {
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
    if (v.direct.hasVisibility()) {  // the caller refuses this kind
        out.file = std::move(f.file);
        return out;
    }
    // Every level's grids: topology in memory, leaf values left in the mapped file until a
    // voxel of the leaf is read. The checks of readLevel / readMask that need no values
    // (active voxel counts, boxes and topologies come from the leaves' masks).
    auto read = [&](const std::string& name) {
        if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
        try {
            return f.file->readGrid(name);
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
    out.file = std::move(f.file);
    return out;
}

namespace {
/// The rest of a photon tile (writePhotonTile) after its identity: level 0's grid, the
/// metadata and the 128-bit sums from their Int64Grids (every node an active voxel).
void readPhotonTile(OpenedFile& f, TileFile& t, const std::string& path) {
    const openvdb::MetaMap& meta = *f.meta;
    Volume& v = t.part;
    VolumeLevel level;
    level.grid = readLevelSpec(meta, 0, path);
    const GridSpec& g = level.grid;
    if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin))
        formatError(path, "has invalid dimensions, spacing or origin for level 0");
    v.levels.push_back(level);
    v.meta = userMetadata(meta);
    t.denseLevels = {1};
    auto sums = std::make_shared<PhotonSums>();
    sums->grid = g;
    sums->exponent = int(requireMeta<int64_t>(meta, kPrefix + "tile_photon_exponent", path));
    const int64_t first = requireMeta<int64_t>(meta, kPrefix + "tile_photon_first_batch", path);
    const int64_t end = requireMeta<int64_t>(meta, kPrefix + "tile_photon_end_batch", path);
    const int64_t batches = requireMeta<int64_t>(meta, kPrefix + "tile_photon_batches", path);
    if (first < 0 || end <= first || batches < end) formatError(path, "has an invalid run of photon batches");
    sums->firstBatch = uint64_t(first), sums->endBatch = uint64_t(end), sums->batches = uint64_t(batches);
    t.photonCompact = requireMeta<int64_t>(meta, kPrefix + "tile_photon_compact", path) != 0;
    const std::size_t count = g.nodeCount() * iv::kFloatsPerNode;
    std::vector<uint64_t> words[2] = {std::vector<uint64_t>(count), std::vector<uint64_t>(count)};  // hi, lo
    const PhotonSumLayout layout(g);
    for (int w = 0; w < 2 * iv::kFloatsPerNode; ++w) {
        const int value = w / 2, d = value / 9, component = value % 9;
        const bool high = w % 2 == 0;
        const std::string name = photonSumGridName(value, high);
        if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
        const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
        auto grid = openvdb::gridPtrCast<openvdb::Int64Grid>(base);
        if (!grid) formatError(path, "grid '" + name + "' has type " + base->valueType() + ", expected int64");
        if (!placedAt(grid->transform(), g.origin, g.spacing))
            formatError(path, "grid '" + name + "' has a transform that does not match its level's origin and spacing");
        grid->tree().voxelizeActiveTiles();
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        if (grid->activeVoxelCount() != g.nodeCount() || box.min() != Coord(0, 0, 0) ||
            box.max() != Coord(g.nx - 1, g.ny - 1, g.nz - 1))
            formatError(path, "grid '" + name + "' does not have exactly one active voxel per node");
        std::vector<uint64_t>& out = words[high ? 0 : 1];
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const Coord c = it.getCoord();
            out[layout.offset(d, c.x(), c.y(), c.z()) + std::size_t(component)] = uint64_t(*it);
        }
    }
    // Two's complement words (writePhotonTile): value = hi * 2^64 + (unsigned) lo.
    sums->values.resize(count);
    for (std::size_t n = 0; n < count; ++n)
        sums->values[n] = PhotonFixed(((unsigned __int128)words[0][n] << 64) | words[1][n]);
    t.photon = std::move(sums);
}
}  // namespace

TileFile readTileFile(const std::string& path) {
    OpenedFile f = openVolumeFile(path, OpenFor::Data);
    const openvdb::MetaMap& meta = *f.meta;
    if (!meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count"))
        formatError(path, "is not a tile (no vdblight:tile_count): a complete volume or another file");
    TileFile t;
    t.id.index = int(requireMeta<int64_t>(meta, kPrefix + "tile_index", path));
    t.id.count = int(requireMeta<int64_t>(meta, kPrefix + "tile_count", path));
    t.id.paramsHash = requireMeta<std::string>(meta, kPrefix + "tile_params_hash", path);
    t.halfFloat = requireMeta<int64_t>(meta, kPrefix + "tile_half_float", path) != 0;
    t.reproducible = requireMeta<int64_t>(meta, kPrefix + "tile_reproducible", path) != 0;
    Volume& v = t.part;
    v.basis.kind = requireMeta<std::string>(meta, kPrefix + "basis", path);
    v.basis.channelNames = splitNames(requireMeta<std::string>(meta, kPrefix + "channels", path));
    const int64_t levels = requireMeta<int64_t>(meta, kPrefix + "levels", path);
    if (levels < 1 || levels > 64) formatError(path, "has an invalid level count " + std::to_string(levels));
    if (meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_photon_sums")) {
        readPhotonTile(f, t, path);
        return t;
    }
    const std::vector<std::string> dense = splitNames(requireMeta<std::string>(meta, kPrefix + "tile_dense_levels", path));
    if (dense.size() != std::size_t(levels)) formatError(path, "has a tile_dense_levels entry per level missing");
    const int channels = v.basis.channelCount();
    for (int l = 0; l < int(levels); ++l) {
        t.denseLevels.push_back(dense[std::size_t(l)] == "1" ? 1 : 0);
        VolumeLevel out;
        out.grid = readLevelSpec(meta, l, path);
        const GridSpec& g = out.grid;
        if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin))
            formatError(path, "has invalid dimensions, spacing or origin for level " + std::to_string(l));
        Vec3SGrid::Ptr first;
        for (int c = 0; c < channels; ++c) {
            const std::string name = gridNameFor(v.basis.channelNames[std::size_t(c)], l);
            if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
            const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
            Vec3SGrid::Ptr grid = checkPlacedChannel(base, g, path);
            grid->tree().voxelizeActiveTiles();
            if (!insideBox(grid->evalActiveVoxelBoundingBox(), g.nx, g.ny, g.nz))
                formatError(path, "grid '" + name + "' has active voxels outside its level's node box");
            if (first && !grid->tree().hasSameTopology(first->tree()))
                formatError(path, "grid '" + name + "' has other active voxels than the first channel of its level");
            if (c == 0) {
                first = grid;
                out.activeNodes = activeLinear(*grid, g);
                out.data.assign(out.activeNodes.size() * std::size_t(channels) * 3, 0.0f);
            }
            copySparseChannel(*grid, out, c, channels);
        }
        v.levels.push_back(std::move(out));
    }
    if (levels > 1)
        for (int l = 0; l + 1 < int(levels); ++l) readMask(f, v.levels[std::size_t(l)], l, path);
    v.meta = userMetadata(meta);
    t.depth = metaNumber(v.meta, "tile_depth", 0) != 0;
    t.visibility = metaNumber(v.meta, "tile_visibility", 0) != 0;
    t.error = metaNumber(v.meta, "tile_estimated_error", 0) != 0;
    if ((t.visibility || t.error) && levels != 1) formatError(path, "has per-node visibility or errors on several levels");
    // Depth moments, light visibility and errors of the tile's nodes (none on a level
    // without nodes in this tile).
    for (int l = 0; l < int(levels) && t.depth; ++l)
        if (!v.levels[std::size_t(l)].activeNodes.empty()) readDepth(f, v.levels[std::size_t(l)], l, path);
    readDirectLights(f, v, path);
    VolumeLevel& level0 = v.levels[0];
    if (t.visibility && !level0.activeNodes.empty()) {
        if (!v.direct.hasVisibility()) formatError(path, "has light visibility but no occlusion-mode lights");
        const std::size_t lights = v.direct.lights.size();
        level0.lightVisibility.assign(level0.activeNodes.size() * lights, 0.0f);
        for (std::size_t i = 0; i < lights; ++i) {
            const std::vector<float> values = readSparseScalar(f, visibilityGridName(i), level0, path);
            for (std::size_t n = 0; n < values.size(); ++n) level0.lightVisibility[n * lights + i] = values[n];
        }
    }
    if (t.error && !level0.activeNodes.empty()) t.estimatedError = readSparseScalar(f, kTileErrorName, level0, path);
    return t;
}

}  // namespace vdb_detail

bool readTileId(const std::string& path, TileId& id) {
    OpenedFile f = openVolumeFile(path, OpenFor::Metadata);
    const openvdb::MetaMap& meta = *f.meta;
    if (!meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count")) return false;
    id.index = int(requireMeta<int64_t>(meta, kPrefix + "tile_index", path));
    id.count = int(requireMeta<int64_t>(meta, kPrefix + "tile_count", path));
    id.paramsHash = requireMeta<std::string>(meta, kPrefix + "tile_params_hash", path);
    return true;
}

ContentHash fileContentHash(const std::string& path) {
    checkReadable(path);
    vdb_detail::FileDigest d;
    try {
        d = digestVdbFile(path);
    } catch (const std::exception& e) {
        throw FormatError(e.what());
    }
    ContentHash h;
    h.sha256 = d.sha256;
    h.headerUuid = d.headerUuid;
    h.uuidFromContent = d.headerUuid == d.contentUuid;
    h.damaged = !h.uuidFromContent && vdb_detail::looksContentDerived(d.headerUuid);
    return h;
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
