// Bins / moment lookup: descend through refined cells, pick (or blend) bins, trilinear in space.
#include "vdblight/bins_lookup.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/grid_index.h"
#include "depth_weights.h"
#include "lattice_locate.h"
#include "vdblight/errors.h"
#include "vdblight/layout_levels.h"

namespace vdblight {

namespace {
using query_detail::positionIn;
using query_detail::splitCell;
}  // namespace

bool BinsLookup::accepts(const Volume& volume) {
    bins::BasisSpec spec;
    return bins::specFromVolume(volume.basis, spec);
}

BinsLookup::BinsLookup(const Volume& volume, OutsidePolicy outside, bool interpolateBins)
    : interpolateBins_(interpolateBins), outside_(outside) {
    if (!bins::specFromVolume(volume.basis, spec_))
        throw FormatError("volume basis '" + volume.basis.kind + "' is not a bins or moment basis");
    const VolumeLevel& l0 = volume.levels.at(0);
    if (l0.sparse()) throw FormatError("bins / moment volumes with culled (inactive) level-0 nodes are not supported");
    grid_ = l0.grid;
    K_ = volume.refineFactor();
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    floatsPerNode_ = std::size_t(spec_.binCount()) * 3;
    levels_.resize(volume.levels.size());
    for (std::size_t l = 0; l < volume.levels.size(); ++l) levels_[l].data = volume.levels[l].data;
    hasDepth_ = depthWeights_ = volume.hasDepth();
    for (std::size_t l = 0; l < volume.levels.size() && hasDepth_; ++l) levels_[l].depth = volume.levels[l].depth;
    if (volume.levels.size() == 1 || grid_.nx < 2 || grid_.ny < 2 || grid_.nz < 2) return;

    const int K = K_, side = K + 1;
    levels_[0].child = query_detail::levelZeroChildren(grid_, l0.refinedCells);
    for (std::size_t l = 1; l < volume.levels.size(); ++l) {
        const VolumeLevel& parent = volume.levels[l - 1];
        const VolumeLevel& fine = volume.levels[l];
        const GridSpec& pg = parent.grid;
        Level& out = levels_[l];
        const std::size_t bricks = parent.refinedCells.size();
        out.nodes.resize(bricks * std::size_t(side * side * side));
        if (l + 1 < volume.levels.size()) out.child.resize(bricks * std::size_t(K * K * K));
        for (std::size_t b = 0; b < bricks; ++b) {
            const core::Index3 parentCell = core::unflatten(parent.refinedCells[b], uint64_t(pg.nx), uint64_t(pg.ny));
            const int pi = parentCell.i, pj = parentCell.j, pk = parentCell.k;
            for (int w = 0; w < side; ++w)
                for (int v = 0; v < side; ++v)
                    for (int u = 0; u < side; ++u) {
                        const uint64_t linear = fine.grid.index(pi * K + u, pj * K + v, pk * K + w);
                        const int64_t at = findNode(fine, linear);
                        if (at < 0) throw FormatError("level " + std::to_string(l) + " misses a node of a refined cell");
                        out.nodes[b * side * side * side + u + side * (v + side * std::size_t(w))] = uint32_t(at);
                        if (out.child.empty() || u == K || v == K || w == K) continue;
                        out.child[b * K * K * K + u + K * (v + K * std::size_t(w))] =
                            int32_t(positionIn(fine.refinedCells, linear));
                    }
        }
    }
}

int BinsLookup::binWeights(const Vec3f& d, int channels[4], float weights[4]) const {
    const int R = spec_.resolution;
    int h;
    float u, v;
    bins::directionToSquare(d, h, u, v);
    if (!interpolateBins_) {
        const int iu = std::max(0, std::min(int(u * float(R)), R - 1));
        const int iv = std::max(0, std::min(int(v * float(R)), R - 1));
        channels[0] = bins::channel(R, h, iu, iv);
        weights[0] = 1.0f;
        return 1;
    }
    const float gu = u * float(R) - 0.5f, gv = v * float(R) - 0.5f;
    const int iu0 = int(std::floor(gu)), iv0 = int(std::floor(gv));
    const float fu = gu - float(iu0), fv = gv - float(iv0);
    int count = 0;
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            // Across an edge of the square (the equator) lies the other hemisphere's border bin
            // at the mirrored position; across a corner, both edges: back to this hemisphere.
            int iu = iu0 + a, iv = iv0 + b, hh = h;
            if (iu < 0 || iu >= R) hh = 1 - hh, iu = std::max(0, std::min(iu, R - 1));
            if (iv < 0 || iv >= R) hh = 1 - hh, iv = std::max(0, std::min(iv, R - 1));
            channels[count] = bins::channel(R, hh, iu, iv);
            weights[count] = (a ? fu : 1.0f - fu) * (b ? fv : 1.0f - fv);
            ++count;
        }
    return count;
}

template <class T>
const BinsLookup::Level& BinsLookup::locate(const T g[3], std::size_t corner[8], float weight[8]) const {
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
    if (depthWeights_) {  // visibility-aware interpolation (depth_weights.h)
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = level->depth.data() + corner[c] * depth::kFloatsPerNode;
        query_detail::weightByDepth(weight, depth, float(f[0]), float(f[1]), float(f[2]));
    }
    return *level;
}

Rgb BinsLookup::irradiance(const Vec3f& x, const Vec3f& d) const {
    const Vec3f gv = (x - origin_) * invSpacing_;
    query_detail::checkInside(gv, grid_, x, outside_);
    const float g[3] = {gv.x, gv.y, gv.z};
    std::size_t corner[8];
    float w[8];
    const Level& level = locate(g, corner, w);
    int channels[4];
    float bw[4];
    const int nb = binWeights(d, channels, bw);
    Rgb e{0, 0, 0};
    for (int c = 0; c < 8; ++c) {
        const float* p = level.data.data() + corner[c] * floatsPerNode_;
        for (int b = 0; b < nb; ++b) {
            const float* q = p + 3 * channels[b];
            e += Rgb(q[0], q[1], q[2]) * (w[c] * bw[b]);
        }
    }
    return e;
}

void BinsLookup::binValues(const Vec3d& x, float* out) const {
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

Rgbd referenceBinsLookup(const Volume& volume, const Vec3d& x, const Vec3f& d) {
    bins::BasisSpec spec;
    if (!bins::specFromVolume(volume.basis, spec)) throw FormatError("not a bins or moment volume");
    int cell[3];
    double frac[3];
    const std::size_t l = finestCellAt(volume.levels, volume.refineFactor(), x, cell, frac);
    const VolumeLevel& level = volume.levels[l];
    const int dims[3] = {level.grid.nx, level.grid.ny, level.grid.nz};  // a one-node axis stays one node
    const int bin = bins::binOf(spec.resolution, d);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        int c[3];
        double w = 1.0;
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            if (dims[a] < 2 && bit) w = 0.0;
            c[a] = cell[a] + (dims[a] < 2 ? 0 : bit);
            w *= bit ? frac[a] : 1.0 - frac[a];
        }
        if (w == 0.0) continue;
        const int64_t at = findNode(level, level.grid.index(c[0], c[1], c[2]));
        if (at < 0) throw FormatError("lookup would read a node of level " + std::to_string(l) + " that was not baked");
        const float* p = level.nodeData(std::size_t(at), volume.basis.channelCount()) + 3 * bin;
        e += Rgbd(p[0], p[1], p[2]) * w;
    }
    return e;
}

}  // namespace vdblight
