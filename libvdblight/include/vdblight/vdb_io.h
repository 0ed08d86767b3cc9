// Reading and writing volumes as .vdb files (the product; specified in docs/format.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/volume.h"

namespace vdblight {

struct WriteOptions {
    bool halfFloat = false;  ///< store grids as 16-bit floats (half the bytes)
    /// Leave out the metadata that changes from run to run of the same bake (the keys of
    /// runSpecificMetadataKeys: wall-clock seconds, thread count), so that the same inputs,
    /// parameters and seed give the same file bytes on any machine and thread count
    /// (docs/format.md, "Reproducible files"). The header UUID is derived from the content
    /// either way.
    bool reproducible = true;
};

/// Metadata keys (without prefix) that describe a run rather than its result: "bake_seconds",
/// "threads". WriteOptions::reproducible leaves them out of the file.
const std::vector<std::string>& runSpecificMetadataKeys();

/// Writes `volume` to `path` atomically: a temporary file in the same directory is
/// written, flushed and renamed, so a failure or interruption never leaves a partial
/// file at `path`. Throws IoError (unwritable path or directory; no file is left behind) or
/// ValueError (invalid volume, NaN/Inf values, values beyond +-65504 with halfFloat, or a
/// metadata key the writer sets itself: format_version, basis, channels, levels, level<k>_*).
void writeVolume(const Volume& volume, const std::string& path, const WriteOptions& options = {});

/// The content hash of a .vdb file: SHA-256 of every byte except the 36-byte header UUID
/// that OpenVDB fills in. writeVolume replaces that UUID by one derived from this hash, so
/// equal hashes mean equal files (docs/format.md, "Reproducible files").
struct ContentHash {
    std::string sha256;       ///< 64 hex digits
    std::string headerUuid;   ///< the UUID in the file's header
    bool uuidFromContent = false;  ///< headerUuid is the one the hash gives (false: another writer)
    /// headerUuid has the shape this writer derives from content (docs/format.md) but is not
    /// the one this content gives: the file changed after it was written (damaged, truncated).
    bool damaged = false;
};

/// Hashes a .vdb file. Throws IoError (unreadable) or FormatError (not an OpenVDB file).
ContentHash fileContentHash(const std::string& path);

/// Reads a volume written by writeVolume. Throws IoError (missing/unreadable) or
/// FormatError (truncated or corrupt file, not a vdblight volume, unsupported format
/// version, missing or inconsistent grids). Volume::meta gets every vdblight: file metadata
/// entry except the structural keys, prefix stripped. `hash`, if given, receives the file's
/// content hash, which the check for damaged files computes anyway (so `info` hashes once).
Volume readVolume(const std::string& path, ContentHash* hash = nullptr);

/// What `vdblight info` prints about one grid of a file.
struct GridInfo {
    std::string name;
    std::string valueType;     ///< OpenVDB type name, e.g. "vec3s"
    uint64_t activeVoxels = 0;
    uint64_t memoryBytes = 0;  ///< in-memory size reported by OpenVDB
    int level = 0;
    double voxelSize = 0;
};

struct FileInfo {
    std::string path;
    uint64_t fileBytes = 0;
    std::vector<GridInfo> grids;
    ContentHash hash;
};

/// Lists the grids of a vdblight .vdb, by level then channel (same errors as readVolume).
/// `knownHash`: the file's content hash if the caller has it already (readVolume's), else it
/// is computed here.
FileInfo inspectVolumeFile(const std::string& path, const ContentHash* knownHash = nullptr);

/// What `vdblight info` lists of a volume file: size, content hash, basis, direct light,
/// levels, grids and metadata; volumeInfoJson: the same as one JSON object, keys in a fixed order.
std::string volumeInfoText(const Volume& volume, const FileInfo& info);
std::string volumeInfoJson(const Volume& volume, const FileInfo& info);

}  // namespace vdblight
