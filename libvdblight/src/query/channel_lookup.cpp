// The generic lookup of registry bases: descend through refined cells, trilinear in space,
// the basis's terms for the direction.
#include "query/channel_lookup.h"

#include "basis/sh.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "brick_tables.h"
#include "depth_weights.h"
#include "lattice_locate.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {
using query_detail::positionIn;
using query_detail::splitCell;
}  // namespace

bool ChannelLookup::accepts(const Volume& volume) {
    return !volume.levels.empty() && !volume.levels[0].sparse() && basisOf(volume.basis) != nullptr;
}

namespace {
std::unique_ptr<Basis> registeredBasis(const Volume& volume) {
    std::unique_ptr<Basis> basis = basisOf(volume.basis);
    if (!basis) throw FormatError("volume basis '" + volume.basis.kind + "' is not a registered basis");
    return basis;
}
}  // namespace

ChannelLookup::ChannelLookup(const Volume& volume, OutsidePolicy outside)
    : ChannelLookup(volume, outside, registeredBasis(volume)) {}

ChannelLookup::ChannelLookup(const Volume& volume, OutsidePolicy outside, std::unique_ptr<Basis> basis)
    : basis_(std::move(basis)), outside_(outside) {
    if (basis_->channelCount() != volume.basis.channelCount())
        throw FormatError("basis '" + basis_->desc().kind + "' has " + std::to_string(basis_->channelCount()) +
                          " channels, the volume " + std::to_string(volume.basis.channelCount()));
    if (basis_->maxTerms() > kMaxTerms)
        throw FormatError("basis '" + basis_->desc().kind + "' evaluates more than " + std::to_string(kMaxTerms) + " terms");
    const VolumeLevel& l0 = volume.levels.at(0);
    if (l0.sparse())
        throw FormatError("'" + volume.basis.kind + "' volumes with culled (inactive) level-0 nodes are not supported");
    grid_ = l0.grid;
    K_ = volume.refineFactor();
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    floatsPerNode_ = basis_->floatsPerNode();
    levels_.resize(volume.levels.size());
    for (std::size_t l = 0; l < volume.levels.size(); ++l) levels_[l].data = volume.levels[l].data;
    hasDepth_ = depthWeights_ = volume.hasDepth();
    if (hasDepth_) levels_.back().depth = volume.levels.back().depth;  // the finest only: depthWeightsApplyAt
    if (volume.levels.size() == 1 || grid_.nx < 2 || grid_.ny < 2 || grid_.nz < 2) return;

    levels_[0].child = query_detail::levelZeroChildren(grid_, l0.refinedCells);
    for (std::size_t l = 1; l < volume.levels.size(); ++l) {
        query_detail::BrickTable t =
            query_detail::brickTable(volume.levels[l - 1], volume.levels[l], K_, l + 1 < volume.levels.size());
        Level& out = levels_[l];
        out.nodes.resize(t.nodeAt.size());
        for (std::size_t s = 0; s < t.nodeAt.size(); ++s) {
            if (t.nodeAt[s] < 0) throw FormatError("level " + std::to_string(l) + " misses a node of a refined cell");
            out.nodes[s] = uint32_t(t.nodeAt[s]);
        }
        out.child = std::move(t.child);
    }
}

template <class T>
const ChannelLookup::Level& ChannelLookup::locate(const T g[3], std::size_t corner[8], float weight[8]) const {
    int i = 0, j = 0, k = 0;
    T f[3] = {0, 0, 0};
    const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    int* idx[3] = {&i, &j, &k};
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 2) continue;  // a flat axis: one node, no interpolation
        splitCell(g[a], dims[a], *idx[a], f[a]);
    }
    const query_detail::LeafCell leaf = query_detail::descendLevels(levels_, grid_, K_, i, j, k, f);
    const Level* level = &levels_[leaf.level];
    if (leaf.level == 0) {
        const int di = grid_.nx > 1, dj = grid_.ny > 1, dk = grid_.nz > 1;
        for (int c = 0; c < 8; ++c)
            corner[c] = grid_.index(i + (c & 1) * di, j + ((c >> 1) & 1) * dj, k + (c >> 2) * dk);
    } else {
        const int side = K_ + 1;
        const uint32_t* nodes = level->nodes.data() + std::size_t(leaf.brick) * side * side * side;
        for (int c = 0; c < 8; ++c) corner[c] = nodes[(i + (c & 1)) + side * ((j + ((c >> 1) & 1)) + side * (k + (c >> 2)))];
    }
    const T wx[2] = {1 - f[0], f[0]}, wy[2] = {1 - f[1], f[1]}, wz[2] = {1 - f[2], f[2]};
    for (int c = 0; c < 8; ++c) weight[c] = float(wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2]);
    // Visibility-aware interpolation (depth_weights.h), in cells of the finest level only.
    if (depthWeights_ && query_detail::depthWeightsApplyAt(leaf.level, levels_.size())) {
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = level->depth.data() + corner[c] * depth::kFloatsPerNode;
        query_detail::weightByDepth(weight, depth, float(f[0]), float(f[1]), float(f[2]));
    }
    return *level;
}

Rgb ChannelLookup::irradiance(const Vec3f& x, const Vec3f& d) const {
    int channels[kMaxTerms];
    float bw[kMaxTerms];
    const int nb = basis_->terms(d, channels, bw);
    return sumTerms(x, channels, bw, nb);
}

Rgb ChannelLookup::sumTerms(const Vec3f& x, const int* channels, const float* bw, int nb) const {
    const Vec3f gv = (x - origin_) * invSpacing_;
    query_detail::checkInside(gv, grid_, x, outside_);
    const float g[3] = {gv.x, gv.y, gv.z};
    std::size_t corner[8];
    float w[8];
    const Level& level = locate(g, corner, w);
    const float* p[8];
    for (int c = 0; c < 8; ++c) p[c] = level.data.data() + corner[c] * floatsPerNode_;
    // Each term's channel blended over the corners first: nb short sums that do not depend on
    // each other, instead of one chain of 8 * nb additions (the lookup's latency with sh:4's
    // 18 terms; vdblight_bench "query sh:4").
    Rgb e{0, 0, 0};
    for (int b = 0; b < nb; ++b) {
        const int f = 3 * channels[b];
        Rgb t{0, 0, 0};
        for (int c = 0; c < 8; ++c) t += Rgb(p[c][f], p[c][f + 1], p[c][f + 2]) * w[c];
        e += t * bw[b];
    }
    return e;
}

void ChannelLookup::channelValues(const Vec3d& x, float* out) const {
    std::size_t corner[8];
    float w[8];
    // In double, so that at a node position the weights are exactly 0 and 1 (the node's values).
    const double g[3] = {(x.x - grid_.origin.x) / grid_.spacing, (x.y - grid_.origin.y) / grid_.spacing,
                         (x.z - grid_.origin.z) / grid_.spacing};
    const Level& level = locate(g, corner, w);
    std::fill(out, out + floatsPerNode_, 0.0f);
    for (int c = 0; c < 8; ++c) {
        const float* p = level.data.data() + corner[c] * floatsPerNode_;
        for (std::size_t f = 0; f < floatsPerNode_; ++f) out[f] += w[c] * p[f];
    }
}

void ChannelLookup::shRadiance(const Vec3d& x, Rgb out[9]) const {
    if (basis_->shCoefficients() < sh::kCoeffs) VolumeLookup::shRadiance(x, out);  // throws
    thread_local std::vector<float> values;
    values.resize(floatsPerNode_);
    channelValues(x, values.data());
    for (int j = 0; j < sh::kCoeffs; ++j) out[j] = Rgb(values[3 * j], values[3 * j + 1], values[3 * j + 2]);
}

}  // namespace vdblight
