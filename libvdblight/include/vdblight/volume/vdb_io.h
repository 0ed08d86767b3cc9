// The volume module's files: writing and reading whole volumes (below), and streaming one
// larger than memory (StreamedVolume, second part).
//
// Reading and writing volumes as .vdb files (the product; specified in docs/format.md).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vdblight/volume/volume.h"

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

// ---------------------------------------------------------------------------------------------
// A .vdb read without loading it: OpenVDB's delayed loading maps the file and reads a leaf
// (8^3 nodes of one grid) only when a lookup first touches one of its nodes, so that a world
// larger than memory can still be queried (docs/scaling.md, "Worlds larger than memory").
//
//   StreamedVolume v("world.vdb");          // header + grid topology, no node values
//   float node[27];
//   v.readNode(10, 4, 7, node);             // pages in the leaves holding node (10, 4, 7)
//
// Lookups on it: makeStreamingQuery (query/query.h).

namespace vdblight {

/// `vdblight query` streams a file at least this large when its kind supports it (and reads
/// it whole below); `query --stream on|off` overrides.
constexpr uint64_t kStreamAboveBytes = 256ull << 20;

class StreamedVolume {
public:
    /// Opens `path` with delayed loading after the checks of readVolume that need no node
    /// values. Throws IoError (unreadable) or FormatError (not a complete vdblight volume).
    explicit StreamedVolume(const std::string& path);
    ~StreamedVolume();
    StreamedVolume(const StreamedVolume&) = delete;
    StreamedVolume& operator=(const StreamedVolume&) = delete;

    /// What readVolume returns except node values: basis, every level's GridSpec (data,
    /// depth, validity and visibility empty), metadata, the direct-light mode and lights.
    const Volume& header() const;
    /// Node (i, j, k) of `level` (inside its box): channelCount() * 3 floats in Volume order
    /// ([channel][rgb], exactly the values readVolume gives; 0 for a node that is not stored).
    /// Thread-safe.
    void readNode(int level, int i, int j, int k, float* out) const;
    void readNode(int i, int j, int k, float* out) const { readNode(0, i, j, k, out); }
    /// The first `channels` channels of readNode only (3 floats each): the other channels'
    /// leaves are not read.
    void readChannels(int level, int i, int j, int k, int channels, float* out) const;
    /// True if node (i, j, k) of `level` is stored (an active voxel; sparse levels, culled nodes).
    bool nodeStored(int level, int i, int j, int k) const;
    /// True if cell (i, j, k) of `level` (lower corner node (i, j, k)) is refined into the next.
    bool cellRefined(int level, int i, int j, int k) const;
    /// True if every level carries depth moments; readDepth then gives depth::kFloatsPerNode floats.
    bool hasDepth() const;
    void readDepth(int level, int i, int j, int k, float* out) const;
    void readDepth(int i, int j, int k, float* out) const { readDepth(0, i, j, k, out); }
    /// True if the volume stores per-light visibility (bake --direct occlusion, single-level
    /// volumes); readVisibility then gives one float per listed light (header().direct.lights)
    /// of level-0 node (i, j, k), the values readVolume puts in lightVisibility.
    bool hasVisibility() const;
    void readVisibility(int i, int j, int k, float* out) const;
    /// True if the volume also stores the lights' shadow edges (shadow_edges.h);
    /// readShadowEdges then gives shadow_edge::kFloatsPerLight floats per listed light of
    /// level-0 node (i, j, k), the values readVolume puts in lightShadowEdges.
    bool hasShadowEdges() const;
    void readShadowEdges(int i, int j, int k, float* out) const;
    /// True if some node stores a second edge (a strip's far side, shadow_edges.h kFar > 0), as
    /// export's edge textures need to know before the first cell. Reads the far sides' leaves
    /// (one float per node and light) up to the first such node.
    bool hasShadowStrips() const;
    /// Leaf buffers (over every grid opened) read from the file so far, and in all.
    uint64_t loadedLeaves() const;
    uint64_t totalLeaves() const;
    /// Bytes the opened grids take in memory now (OpenVDB's memUsage: the topology, a file
    /// reference per leaf still on disk, the values of the leaves read).
    uint64_t residentBytes() const;
    /// Drops the values of every leaf read so far (the file's grids are opened again, the header
    /// object stays): a pass over the whole volume, such as export --cells, keeps its memory to
    /// the leaves of a few cells at the cost of reading the topology again. Not thread-safe:
    /// call it while no lookup reads this volume. Throws IoError / FormatError if the file can
    /// no longer be opened (changed or removed); the volume then reads nothing.
    void releaseLeaves();
    /// Size of the file in bytes.
    uint64_t fileBytes() const { return fileBytes_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    uint64_t fileBytes_ = 0;
};

}  // namespace vdblight
