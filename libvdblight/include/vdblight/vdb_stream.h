// A .vdb read without loading it: OpenVDB's delayed loading maps the file and reads a leaf
// (8^3 nodes of one grid) only when a lookup first touches one of its nodes, so that a world
// larger than memory can still be queried (docs/scaling.md, "Worlds larger than memory").
//
//   StreamedVolume v("world.vdb");          // header + grid topology, no node values
//   float node[27];
//   v.readNode(10, 4, 7, node);             // pages in the leaves holding node (10, 4, 7)
//
// Lookups on it: makeStreamingQuery (query_stream.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "vdblight/volume.h"

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
