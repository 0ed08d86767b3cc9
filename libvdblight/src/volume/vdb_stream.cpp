// StreamedVolume: nodes read through OpenVDB's delayed loading (vdb_stream.h). The checks
// live in vdb_read.cpp (openDelayedVolume); this file only reads voxels.
#include "vdblight/vdb_stream.h"

#include <filesystem>

#include "vdblight/depth_moments.h"
#include "vdblight/errors.h"
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
    bool depth = false;
    std::vector<const Vec3STree*> allTrees() const {
        std::vector<const Vec3STree*> out;
        for (const Level& l : levels) {
            out.insert(out.end(), l.channels.begin(), l.channels.end());
            out.insert(out.end(), l.depth.begin(), l.depth.end());
        }
        return out;
    }
};

StreamedVolume::StreamedVolume(const std::string& path) : impl_(std::make_unique<Impl>()) {
    impl_->file = openDelayedVolume(path);
    fileBytes_ = uint64_t(std::filesystem::file_size(path));
    const Volume& h = impl_->file.header;
    if (h.direct.hasVisibility())
        unsupported_ = "it stores per-light visibility (bake --direct occlusion), which streaming does not read";
    impl_->depth = !impl_->file.levels.empty();
    for (const DelayedLevel& d : impl_->file.levels) {
        Impl::Level l;
        for (const auto& g : d.channels) l.channels.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
        for (const auto& g : d.depth) l.depth.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
        if (d.mask) l.mask = &openvdb::gridPtrCast<openvdb::BoolGrid>(d.mask)->tree();
        impl_->depth = impl_->depth && !l.depth.empty();
        impl_->levels.push_back(std::move(l));
    }
}

StreamedVolume::~StreamedVolume() = default;

const Volume& StreamedVolume::header() const { return impl_->file.header; }

bool StreamedVolume::hasDepth() const { return impl_->depth; }

namespace {
// Reads voxel (i, j, k) of every tree into out (3 floats each). A tree's getValue pages in
// the leaf under the mutex of its buffer, so concurrent readers are safe.
void readVoxels(const std::vector<const Vec3STree*>& trees, int i, int j, int k, float* out) {
    const Coord c(i, j, k);
    for (std::size_t t = 0; t < trees.size(); ++t) {
        const openvdb::Vec3s v = trees[t]->getValue(c);
        out[3 * t] = v.x(), out[3 * t + 1] = v.y(), out[3 * t + 2] = v.z();
    }
}
}  // namespace

void StreamedVolume::readNode(int level, int i, int j, int k, float* out) const {
    if (!unsupported_.empty()) throw FormatError("cannot read nodes of this streamed volume: " + unsupported_);
    readVoxels(impl_->levels.at(std::size_t(level)).channels, i, j, k, out);
}

bool StreamedVolume::nodeStored(int level, int i, int j, int k) const {
    if (!unsupported_.empty()) throw FormatError("cannot read nodes of this streamed volume: " + unsupported_);
    return impl_->levels.at(std::size_t(level)).channels[0]->isValueOn(Coord(i, j, k));  // the mask: no values read
}

bool StreamedVolume::cellRefined(int level, int i, int j, int k) const {
    if (!unsupported_.empty()) throw FormatError("cannot read nodes of this streamed volume: " + unsupported_);
    const openvdb::BoolTree* mask = impl_->levels.at(std::size_t(level)).mask;
    return mask && mask->isValueOn(Coord(i, j, k));
}

void StreamedVolume::readDepth(int level, int i, int j, int k, float* out) const {
    if (!impl_->depth) throw FormatError("this streamed volume has no depth moments");
    readVoxels(impl_->levels.at(std::size_t(level)).depth, i, j, k, out);
}

namespace {
uint64_t countLeaves(const std::vector<const Vec3STree*>& trees, bool onlyLoaded) {
    uint64_t n = 0;
    for (const Vec3STree* t : trees)
        for (auto it = t->cbeginLeaf(); it; ++it) n += !onlyLoaded || !it->buffer().isOutOfCore();
    return n;
}
}  // namespace

uint64_t StreamedVolume::loadedLeaves() const { return countLeaves(impl_->allTrees(), true); }

uint64_t StreamedVolume::totalLeaves() const { return countLeaves(impl_->allTrees(), false); }

uint64_t StreamedVolume::residentBytes() const {
    uint64_t n = 0;
    for (const Vec3STree* t : impl_->allTrees()) n += t->memUsage();
    for (const Impl::Level& l : impl_->levels)
        if (l.mask) n += l.mask->memUsage();
    return n;
}

}  // namespace vdblight
