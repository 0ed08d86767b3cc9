// StreamedVolume: nodes read through OpenVDB's delayed loading (vdb_stream.h). The checks
// live in vdb_read.cpp (openDelayedVolume); this file only reads voxels.
#include "vdblight/volume/vdb_io.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <new>

#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "basis/shadow_edges.h"
#include "vdb_conventions.h"
#include "vdb_delayed.h"

namespace vdblight {

using namespace vdb_detail;

struct StreamedVolume::Impl {
    DelayedVolumeFile file;
    struct Level {
        std::vector<const Vec3STree*> channels, depth;
        const openvdb::BoolTree* mask = nullptr;
    };
    std::vector<Level> levels;
    std::vector<const openvdb::FloatTree*> visibility;  ///< per listed light, level 0 (occlusion mode)
    std::vector<const openvdb::FloatTree*> edges;       ///< distances, then widths (shadow_edges.h), or empty
    bool depth = false;
    /// Fills levels, visibility and depth from the opened file's grids.
    void collectTrees() {
        levels.clear();
        visibility.clear();
        depth = !file.levels.empty();
        for (const DelayedLevel& d : file.levels) {
            Level l;
            for (const auto& g : d.channels) l.channels.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
            for (const auto& g : d.depth) l.depth.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
            if (d.mask) l.mask = &openvdb::gridPtrCast<openvdb::BoolGrid>(d.mask)->tree();
            depth = depth && !l.depth.empty();
            levels.push_back(std::move(l));
        }
        for (const auto& g : file.visibility) visibility.push_back(&openvdb::gridPtrCast<openvdb::FloatGrid>(g)->tree());
        edges.clear();
        for (const auto& g : file.edges) edges.push_back(&openvdb::gridPtrCast<openvdb::FloatGrid>(g)->tree());
    }
    std::vector<const openvdb::FloatTree*> floatTrees() const {
        std::vector<const openvdb::FloatTree*> out = visibility;
        out.insert(out.end(), edges.begin(), edges.end());
        return out;
    }
    std::vector<const Vec3STree*> allTrees() const {
        std::vector<const Vec3STree*> out;
        for (const Level& l : levels) {
            out.insert(out.end(), l.channels.begin(), l.channels.end());
            out.insert(out.end(), l.depth.begin(), l.depth.end());
        }
        return out;
    }
};

StreamedVolume::StreamedVolume(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
    impl_->file = openDelayedVolume(path);
    fileBytes_ = uint64_t(std::filesystem::file_size(path));
    impl_->collectTrees();
}

void StreamedVolume::releaseLeaves() {
    // The old grids go first, so that the topology is never held twice; the header object
    // stays (callers hold references to it), only the grids are replaced.
    impl_->levels.clear();
    impl_->visibility.clear();
    impl_->edges.clear();
    impl_->file.levels.clear();
    impl_->file.visibility.clear();
    impl_->file.edges.clear();
    impl_->file.file.reset();
    DelayedVolumeFile again = openDelayedVolume(path_);
    impl_->file.file = std::move(again.file);
    impl_->file.levels = std::move(again.levels);
    impl_->file.visibility = std::move(again.visibility);
    impl_->file.edges = std::move(again.edges);
    impl_->collectTrees();
}

StreamedVolume::~StreamedVolume() = default;

const Volume& StreamedVolume::header() const { return impl_->file.header; }

bool StreamedVolume::hasDepth() const { return impl_->depth; }

namespace {
// Memory that must be free before a leaf is paged in. Blosc decompresses a leaf into buffers
// it mallocs and does not check (libblosc 1.21 dereferences the null pointer a failed malloc
// returns: the process died of SIGSEGV at its memory limit). A leaf's buffers are a few KiB
// (8^3 values, the compressed bytes, Blosc's block and its scratch): when this much can be
// allocated and freed, they fit in the space it leaves, on one thread.
constexpr std::size_t kLeafHeadroom = 64u << 10;

[[noreturn]] void leafOutOfMemory(const std::string& path) {
    throw OutOfMemory("not enough memory left to read the next leaf of '" + path + "'");
}

// Throws OutOfMemory unless kLeafHeadroom bytes can be allocated now. Through operator new,
// so that an application's new-handler sees the failure (vdblight's frees its reserve).
void requireLeafHeadroom(const std::string& path) {
    void* p = ::operator new(kLeafHeadroom, std::nothrow);
    if (!p) leafOutOfMemory(path);
    ::operator delete(p);
}

// The value at c of a tree read with delayed loading: a leaf still in the file is paged in
// (under the mutex of its buffer, so concurrent readers are safe) after the headroom check.
template <class Tree>
typename Tree::ValueType valueAt(const Tree& tree, const Coord& c, const std::string& path) {
    const auto* leaf = tree.probeConstLeaf(c);
    if (!leaf) return tree.getValue(c);  // a tile or the background: nothing to page in
    if (leaf->buffer().isOutOfCore()) requireLeafHeadroom(path);
    try {
        return leaf->getValue(c);
    } catch (const std::bad_alloc&) {  // OpenVDB's own allocations for the leaf
        leafOutOfMemory(path);
    }
}

// Reads voxel (i, j, k) of every tree into out (3 floats each).
void readVoxels(const std::vector<const Vec3STree*>& trees, int i, int j, int k, float* out, const std::string& path,
                std::size_t count = SIZE_MAX) {
    const Coord c(i, j, k);
    for (std::size_t t = 0; t < std::min(count, trees.size()); ++t) {
        const openvdb::Vec3s v = valueAt(*trees[t], c, path);
        out[3 * t] = v.x(), out[3 * t + 1] = v.y(), out[3 * t + 2] = v.z();
    }
}
}  // namespace

void StreamedVolume::readNode(int level, int i, int j, int k, float* out) const {
    readVoxels(impl_->levels.at(std::size_t(level)).channels, i, j, k, out, path_);
}

void StreamedVolume::readChannels(int level, int i, int j, int k, int channels, float* out) const {
    readVoxels(impl_->levels.at(std::size_t(level)).channels, i, j, k, out, path_, std::size_t(std::max(channels, 0)));
}

bool StreamedVolume::nodeStored(int level, int i, int j, int k) const {
    return impl_->levels.at(std::size_t(level)).channels[0]->isValueOn(Coord(i, j, k));  // the mask: no values read
}

bool StreamedVolume::cellRefined(int level, int i, int j, int k) const {
    const openvdb::BoolTree* mask = impl_->levels.at(std::size_t(level)).mask;
    return mask && mask->isValueOn(Coord(i, j, k));
}

void StreamedVolume::readDepth(int level, int i, int j, int k, float* out) const {
    if (!impl_->depth) throw FormatError("this streamed volume has no depth moments");
    readVoxels(impl_->levels.at(std::size_t(level)).depth, i, j, k, out, path_);
}

bool StreamedVolume::hasVisibility() const { return !impl_->visibility.empty(); }

void StreamedVolume::readVisibility(int i, int j, int k, float* out) const {
    if (impl_->visibility.empty()) throw FormatError("this streamed volume stores no light visibility");
    const Coord c(i, j, k);
    for (std::size_t l = 0; l < impl_->visibility.size(); ++l) out[l] = valueAt(*impl_->visibility[l], c, path_);
}

bool StreamedVolume::hasShadowEdges() const { return !impl_->edges.empty(); }

void StreamedVolume::readShadowEdges(int i, int j, int k, float* out) const {
    if (impl_->edges.empty()) throw FormatError("this streamed volume stores no shadow edges");
    const Coord c(i, j, k);
    const std::size_t lights = impl_->visibility.size();
    const std::size_t parts = impl_->edges.size() / lights;  // 2 in files from before the second edge
    for (std::size_t l = 0; l < lights; ++l)
        for (std::size_t part = 0; part < std::size_t(shadow_edge::kFloatsPerLight); ++part)
            out[l * shadow_edge::kFloatsPerLight + part] = part < parts ? valueAt(*impl_->edges[part * lights + l], c, path_) : 0.0f;
}

bool StreamedVolume::hasShadowStrips() const {
    const std::size_t lights = impl_->visibility.size();
    if (lights == 0 || impl_->edges.size() / lights <= std::size_t(shadow_edge::kFar)) return false;  // files before the second edge
    for (std::size_t l = 0; l < lights; ++l) {
        const openvdb::FloatTree& far = *impl_->edges[std::size_t(shadow_edge::kFar) * lights + l];
        for (auto leaf = far.cbeginLeaf(); leaf; ++leaf) {
            if (leaf->buffer().isOutOfCore()) requireLeafHeadroom(path_);
            for (auto v = leaf->cbeginValueOn(); v; ++v)
                if (*v > 0.0f) return true;
        }
        // Active tiles above the leaves (a region of equal values the writer pruned).
        auto tile = far.cbeginValueOn();
        tile.setMaxDepth(tile.getLeafDepth() - 1);
        for (; tile; ++tile)
            if (*tile > 0.0f) return true;
    }
    return false;
}

namespace {
template <class Tree>
uint64_t countLeaves(const std::vector<const Tree*>& trees, bool onlyLoaded) {
    uint64_t n = 0;
    for (const Tree* t : trees)
        for (auto it = t->cbeginLeaf(); it; ++it) n += !onlyLoaded || !it->buffer().isOutOfCore();
    return n;
}
}  // namespace

uint64_t StreamedVolume::loadedLeaves() const {
    return countLeaves(impl_->allTrees(), true) + countLeaves(impl_->floatTrees(), true);
}

uint64_t StreamedVolume::totalLeaves() const {
    return countLeaves(impl_->allTrees(), false) + countLeaves(impl_->floatTrees(), false);
}

uint64_t StreamedVolume::residentBytes() const {
    uint64_t n = 0;
    for (const Vec3STree* t : impl_->allTrees()) n += t->memUsage();
    for (const openvdb::FloatTree* t : impl_->floatTrees()) n += t->memUsage();
    for (const Impl::Level& l : impl_->levels)
        if (l.mask) n += l.mask->memUsage();
    return n;
}

}  // namespace vdblight
