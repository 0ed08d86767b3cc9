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
    std::vector<const Vec3STree*> channels, depth;
};

StreamedVolume::StreamedVolume(const std::string& path) : impl_(std::make_unique<Impl>()) {
    impl_->file = openDelayedVolume(path);
    fileBytes_ = uint64_t(std::filesystem::file_size(path));
    const Volume& h = impl_->file.header;
    if (h.levels.size() != 1)
        unsupported_ = "it has " + std::to_string(h.levels.size()) + " levels (streaming reads single-level volumes)";
    else if (h.direct.hasVisibility())
        unsupported_ = "it stores per-light visibility (bake --direct occlusion), which streaming does not read";
    for (const auto& g : impl_->file.channels) impl_->channels.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
    for (const auto& g : impl_->file.depth) impl_->depth.push_back(&openvdb::gridPtrCast<Vec3SGrid>(g)->tree());
}

StreamedVolume::~StreamedVolume() = default;

const Volume& StreamedVolume::header() const { return impl_->file.header; }

bool StreamedVolume::hasDepth() const { return !impl_->depth.empty(); }

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

void StreamedVolume::readNode(int i, int j, int k, float* out) const {
    if (!unsupported_.empty()) throw FormatError("cannot read nodes of this streamed volume: " + unsupported_);
    readVoxels(impl_->channels, i, j, k, out);
}

void StreamedVolume::readDepth(int i, int j, int k, float* out) const {
    if (impl_->depth.empty()) throw FormatError("this streamed volume has no depth moments");
    readVoxels(impl_->depth, i, j, k, out);
}

namespace {
uint64_t countLeaves(const std::vector<const Vec3STree*>& trees, bool onlyLoaded) {
    uint64_t n = 0;
    for (const Vec3STree* t : trees)
        for (auto it = t->cbeginLeaf(); it; ++it) n += !onlyLoaded || !it->buffer().isOutOfCore();
    return n;
}
}  // namespace

uint64_t StreamedVolume::loadedLeaves() const {
    return countLeaves(impl_->channels, true) + countLeaves(impl_->depth, true);
}

uint64_t StreamedVolume::totalLeaves() const {
    return countLeaves(impl_->channels, false) + countLeaves(impl_->depth, false);
}

uint64_t StreamedVolume::residentBytes() const {
    uint64_t n = 0;
    for (const auto* trees : {&impl_->channels, &impl_->depth})
        for (const Vec3STree* t : *trees) n += t->memUsage();
    return n;
}

}  // namespace vdblight
