// Opening a vdblight .vdb file: readable, not truncated, not damaged (content hash), a
// vdblight volume of a format version this build reads (vdb_read_parts.h).
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <new>
#include <fstream>

#include "vdb_read_parts.h"
#include "vdb_topology_guard.h"

namespace vdblight {
namespace vdb_detail {

namespace fs = std::filesystem;

[[noreturn]] void formatError(const std::string& path, const std::string& what) {
    throw FormatError("'" + path + "' " + what);
}

/// Reads grid `name` of the file; FormatError naming the file if it cannot be read.
openvdb::GridBase::Ptr readGridChecked(OpenedFile& f, const std::string& name, const std::string& path) {
    try {
        return f.file->readGrid(name);
    } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
        throw;
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

namespace {

/// Reads the grid table of a .vdb the way io::File::open does, but with every read checked,
/// to find where the last grid's data ends. OpenVDB itself reads a file that lacks its last
/// bytes without complaint (leaving garbage in the last leaves), so the reader compares this
/// end with the file size. It also checks each grid's metadata lengths and tree topology counts
/// (vdb_topology_guard.h), which OpenVDB trusts.
class GridTableScanner : public openvdb::io::Archive {
public:
    explicit GridTableScanner(std::string path) : path_(std::move(path)) {}

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
            GridExtent grid;
            grid.name = readString(is);  // unique name
            grid.type = readString(is);
            if (openvdb::io::getFormatVersion(is) >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING)
                grid.instance = !readString(is).empty();  // the instance parent's name
            int64_t offsets[3] = {0, 0, 0};  // grid, blocks, end
            is.read(reinterpret_cast<char*>(offsets), sizeof offsets);
            if (!is) throw std::runtime_error("grid table ends early");
            if (offsets[0] < 0 || offsets[0] > fileBytes || offsets[2] < offsets[0])
                throw std::runtime_error("grid table is corrupt");
            end = std::max(end, offsets[2]);
            grid.gridPos = offsets[0];
            grid.endPos = std::min(offsets[2], fileBytes);
            const std::streampos next = is.tellg();
            is.seekg(offsets[0], std::ios_base::beg);  // the grid: compression flags, then its metadata
            if (openvdb::io::getFormatVersion(is) >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) is.ignore(4);
            checkMetaMap(is, fileBytes);
            checkTreeTopology(is, grid, path_);
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

    static std::string readString(std::istream& is) {
        uint32_t size = 0;
        is.read(reinterpret_cast<char*>(&size), sizeof size);
        if (!is || size > (1u << 20)) throw std::runtime_error("grid table ends early or is corrupt");
        std::string s(size, '\0');
        is.read(s.data(), std::streamsize(size));
        return s;
    }

    std::string path_;  ///< for the topology guard's message
};

}  // namespace

void checkNotTruncated(const std::string& path) {
    std::ifstream is(path, std::ios::binary);
    const auto bytes = int64_t(fs::file_size(path));
    int64_t end = 0;
    try {
        end = GridTableScanner(path).dataEnd(is, bytes);
    } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
        throw;
    } catch (const FormatError&) {  // the topology guard's, which names the file and the grid
        throw;
    } catch (const std::exception& e) {
        formatError(path, std::string("is not a readable .vdb file (truncated or corrupt?): ") + e.what());
    }
    if (end > bytes) {
        formatError(path, "is truncated: its grids end at byte " + std::to_string(end) + " but it has only " +
                              std::to_string(bytes) + " bytes");
    }
}

namespace {

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

}  // namespace

OpenedFile openVolumeFile(const std::string& path, OpenFor purpose, const ContentHash* knownHash) {
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
    } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
        throw;
    } catch (const std::exception& e) {
        // Mapping the file for delayed loading fails with ENOMEM under a low RLIMIT_AS: the
        // process's limit, not the file, is at fault (OpenVDB passes on only the message).
        if (std::strstr(e.what(), std::strerror(ENOMEM)))
            throw OutOfMemory("'" + path + "' could not be opened: " + e.what());
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

}  // namespace vdb_detail

ContentHash fileContentHash(const std::string& path) {
    vdb_detail::checkReadable(path);
    vdb_detail::FileDigest d;
    try {
        d = vdb_detail::digestVdbFile(path);
    } catch (const std::bad_alloc&) {  // out of memory, not a corrupt file
        throw;
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

}  // namespace vdblight
