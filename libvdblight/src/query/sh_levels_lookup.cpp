// Multi-level SH order-2 lookup: descend through refined cells, interpolate in the finest.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "brick_tables.h"
#include "depth_weights.h"
#include "lattice_locate.h"
#include "sh_trilinear.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "query/query_levels.h"
#include "basis/sh.h"

namespace vdblight {

namespace {
constexpr int kFloats = query_detail::kShFloats;
using query_detail::positionIn;

/// Copies one node's coefficients with the cosine-lobe constants A_l folded in.
void copyFolded(const float* src, float* dst) {
    for (int f = 0; f < kFloats; ++f) dst[f] = src[f] * float(sh::kCosineLobe[sh::bandOf(f / 3)]);
}
}  // namespace

bool ShLevelsLookup::accepts(const Volume& volume) { return volume.basis.isSh2() && volume.levels.size() > 1; }

ShLevelsLookup::ShLevelsLookup(const Volume& volume, OutsidePolicy outside) : outside_(outside) {
    const VolumeLevel& l0 = volume.levels[0];
    grid_ = l0.grid;
    K_ = volume.refineFactor();
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    const int K = K_, side = K + 1;
    levels_.resize(volume.levels.size());

    // Culled volumes (solid_cull.h): inactive nodes are stored as zeros and every leaf cell
    // with an inactive corner gets the child value kCulled (the lookup returns 0 there).
    levels_[0].nodes.assign(grid_.nodeCount() * kFloats, 0.0f);
    std::vector<char> present(grid_.nodeCount(), l0.sparse() ? 0 : 1);
    hasDepth_ = volume.hasDepth();
    depthWeights_ = hasDepth_;
    constexpr int kDepth = depth::kFloatsPerNode;
    // Only the finest level's depth is read (depthWeightsApplyAt).
    const bool depthAt0 = hasDepth_ && query_detail::depthWeightsApplyAt(0, volume.levels.size());
    if (depthAt0) levels_[0].depth.assign(grid_.nodeCount() * kDepth, 1.0f);
    for (std::size_t n = 0; n < l0.storedNodes(); ++n) {
        const std::size_t linear = l0.sparse() ? std::size_t(l0.activeNodes[n]) : n;
        copyFolded(l0.nodeData(n, sh::kCoeffs), &levels_[0].nodes[linear * kFloats]);
        if (depthAt0) std::copy_n(l0.nodeDepth(n), kDepth, &levels_[0].depth[linear * kDepth]);
        present[linear] = 1;
    }
    levels_[0].child = query_detail::levelZeroChildren(grid_, l0.refinedCells);
    for (int k = 0; k < grid_.nz - 1; ++k)  // unrefined cells with a culled corner
        for (int j = 0; j < grid_.ny - 1; ++j)
            for (int i = 0; i < grid_.nx - 1; ++i) {
                int32_t& child = levels_[0].child[i + std::size_t(grid_.nx - 1) * (j + std::size_t(grid_.ny - 1) * k)];
                for (int c = 0; c < 8 && child < 0; ++c)
                    if (!present[grid_.index(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2))]) child = kCulled;
            }

    const bool culled = metaString(volume.meta, "culling") == "solid-regions";
    for (std::size_t l = 1; l < volume.levels.size(); ++l) {
        const VolumeLevel& fine = volume.levels[l];
        // A culled volume's finest level also needs a child table: for its kCulled markers.
        query_detail::BrickTable t =
            query_detail::brickTable(volume.levels[l - 1], fine, K, l + 1 < volume.levels.size() || culled);
        Level& out = levels_[l];
        const std::size_t slots = t.nodeAt.size(), perBrick = std::size_t(side * side * side);
        out.nodes.assign(slots * kFloats, 0.0f);
        const bool depthAtL = hasDepth_ && query_detail::depthWeightsApplyAt(l, volume.levels.size());
        if (depthAtL) out.depth.assign(slots * kDepth, 1.0f);
        for (std::size_t s = 0; s < slots; ++s) {
            const int64_t at = t.nodeAt[s];
            if (at < 0 && !culled) throw FormatError("level " + std::to_string(l) + " misses a node of a refined cell");
            if (at < 0) continue;
            copyFolded(fine.nodeData(std::size_t(at), sh::kCoeffs), &out.nodes[s * kFloats]);
            if (depthAtL) std::copy_n(fine.nodeDepth(std::size_t(at)), kDepth, &out.depth[s * kDepth]);
        }
        out.child = std::move(t.child);
        if (!culled) continue;
        for (std::size_t b = 0; b < slots / perBrick; ++b) {
            const int64_t* brick = &t.nodeAt[b * perBrick];
            for (int w = 0; w < K; ++w)
                for (int v = 0; v < K; ++v)
                    for (int u = 0; u < K; ++u) {
                        int32_t& child = out.child[b * K * K * K + u + K * (v + K * std::size_t(w))];
                        for (int c = 0; c < 8 && child < 0; ++c)
                            if (brick[(u + (c & 1)) + side * ((v + ((c >> 1) & 1)) + side * std::size_t(w + (c >> 2)))] < 0)
                                child = kCulled;
                    }
        }
    }
}

template <typename Visit>
void ShLevelsLookup::descend(const Vec3f& x, Visit visit) const {
    const Vec3f g = (x - origin_) * invSpacing_;
    query_detail::checkInside(g, grid_, x, outside_);
    int i, j, k;
    float f[3];
    query_detail::splitCell(g.x, grid_.nx, i, f[0]);
    query_detail::splitCell(g.y, grid_.ny, j, f[1]);
    query_detail::splitCell(g.z, grid_.nz, k, f[2]);
    const query_detail::LeafCell leaf = query_detail::descendLevels(levels_, grid_, K_, i, j, k, f);
    if (leaf.stop == kCulled) {
        visit(int(leaf.level), nullptr, 0, 0, 0, f[0], f[1], f[2]);
        return;
    }
    if (leaf.level == 0) {
        const std::size_t sx = kFloats, sy = std::size_t(grid_.nx) * kFloats, sz = std::size_t(grid_.ny) * sy;
        visit(0, levels_[0].nodes.data() + grid_.index(i, j, k) * kFloats, sx, sy, sz, f[0], f[1], f[2]);
        return;
    }
    const int side = K_ + 1;
    const std::size_t sx = kFloats, sy = std::size_t(side) * kFloats, sz = std::size_t(side) * sy;
    const float* base = levels_[leaf.level].nodes.data() +
                        (std::size_t(leaf.brick) * side * side * side + i + side * (j + std::size_t(side) * k)) * kFloats;
    visit(int(leaf.level), base, sx, sy, sz, f[0], f[1], f[2]);
}

Rgb ShLevelsLookup::irradiance(const Vec3f& x, const Vec3f& n) const {
    float y[sh::kCoeffs];
    sh::evalUnrolled(n, y);
    Rgb e;
    descend(x, [&](int l, const float* base, std::size_t sx, std::size_t sy, std::size_t sz, float fx, float fy, float fz) {
        const Level& level = levels_[std::size_t(l)];
        const float* depthBase =
            base && depthWeights_ && query_detail::depthWeightsApplyAt(std::size_t(l), levels_.size())
                ? level.depth.data() + std::size_t(base - level.nodes.data()) / kFloats * depth::kFloatsPerNode
                : nullptr;
        e = base ? query_detail::interpolateSh(base, sx, sy, sz, fx, fy, fz, y, depthBase) : Rgb(0, 0, 0);
    });
    return e;
}

bool ShLevelsLookup::inCulledCell(const Vec3f& x) const {
    bool culled = false;
    descend(x, [&](int, const float* base, std::size_t, std::size_t, std::size_t, float, float, float) { culled = !base; });
    return culled;
}

void ShLevelsLookup::shRadiance(const Vec3d& x, Rgb out[9]) const {
    // The same descent as descend(), in double, with coordinates within 1e-9 of a node
    // snapped onto it at every level, so that a lattice point on a node reads that node.
    const auto snap = [](double g) { return std::fabs(g - std::round(g)) < 1e-9 ? std::round(g) : g; };
    int cell[3];
    double frac[3];
    query_detail::locateExact(grid_, x, outside_, cell, frac);  // snapped onto nodes within 1e-9
    const float* base = levels_[0].nodes.data() + grid_.index(cell[0], cell[1], cell[2]) * kFloats;
    std::size_t sx = kFloats, sy = std::size_t(grid_.nx) * kFloats, sz = std::size_t(grid_.ny) * sy;
    int32_t brick = levels_[0].child[cell[0] + std::size_t(grid_.nx - 1) * (cell[1] + std::size_t(grid_.ny - 1) * cell[2])];
    const int K = K_, side = K + 1;
    const auto culledCell = [&] {
        for (int c = 0; c < sh::kCoeffs; ++c) out[c] = Rgb(0, 0, 0);
    };
    if (brick == kCulled) return culledCell();
    std::size_t levelOf = 0;
    for (std::size_t l = 1; brick >= 0; ++l) {
        levelOf = l;
        for (int a = 0; a < 3; ++a) {
            const double g = snap(frac[a] * K);
            cell[a] = std::min(int(g), K - 1);
            frac[a] = g - cell[a];
        }
        const Level& level = levels_[l];
        base = level.nodes.data() +
               (std::size_t(brick) * side * side * side + cell[0] + side * (cell[1] + std::size_t(side) * cell[2])) * kFloats;
        sx = kFloats, sy = std::size_t(side) * kFloats, sz = std::size_t(side) * sy;
        brick = level.child.empty() ? -1 : level.child[std::size_t(brick) * K * K * K + cell[0] + K * (cell[1] + K * cell[2])];
        if (brick == kCulled) return culledCell();
    }
    float weights[8];
    for (int corner = 0; corner < 8; ++corner) {
        double w = 1.0;
        for (int a = 0; a < 3; ++a) w *= ((corner >> a) & 1) ? frac[a] : 1.0 - frac[a];
        weights[corner] = float(w);
    }
    const bool weighted = depthWeights_ && query_detail::depthWeightsApplyAt(levelOf, levels_.size());
    if (weighted) {
        const Level& level = levels_[levelOf];
        const float* depthBase = level.depth.data() + std::size_t(base - level.nodes.data()) / kFloats * depth::kFloatsPerNode;
        const float* depth[8];
        for (int corner = 0; corner < 8; ++corner) {
            const std::size_t off = ((corner & 1) * sx + ((corner >> 1) & 1) * sy + (corner >> 2) * sz) / kFloats;
            depth[corner] = depthBase + off * depth::kFloatsPerNode;
        }
        query_detail::weightByDepth(weights, depth, float(frac[0]), float(frac[1]), float(frac[2]));
    }
    double sum[kFloats] = {};
    for (int corner = 0; corner < 8; ++corner) {
        const int d[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
        double w = weighted ? double(weights[corner]) : 1.0;
        if (!weighted)
            for (int a = 0; a < 3; ++a) w *= d[a] ? frac[a] : 1.0 - frac[a];
        if (w == 0.0) continue;
        const float* p = base + d[0] * sx + d[1] * sy + d[2] * sz;
        for (int f = 0; f < kFloats; ++f) sum[f] += w * p[f];
    }
    for (int c = 0; c < sh::kCoeffs; ++c) {
        const double a = sh::kCosineLobe[sh::bandOf(c)];  // unfold the constants copyFolded applied
        out[c] = Rgb(float(sum[3 * c] / a), float(sum[3 * c + 1] / a), float(sum[3 * c + 2] / a));
    }
}

int ShLevelsLookup::levelAt(const Vec3f& x) const {
    int level = 0;
    descend(x, [&](int l, const float*, std::size_t, std::size_t, std::size_t, float, float, float) { level = l; });
    return level;
}

Rgbd referenceLevelsLookup(const Volume& volume, const Vec3d& x, const Vec3d& n, int* levelUsed) {
    int cell[3];
    double frac[3];
    const std::size_t l = finestCellAt(volume.levels, volume.refineFactor(), x, cell, frac);
    const VolumeLevel& level = volume.levels[l];
    double y[9];
    sh::evalGeneric(2, normalize(n), y);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        const int d[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
        double w = 1.0;
        for (int a = 0; a < 3; ++a) w *= d[a] ? frac[a] : 1.0 - frac[a];
        const int64_t at = findNode(level, level.grid.index(cell[0] + d[0], cell[1] + d[1], cell[2] + d[2]));
        if (at < 0) throw FormatError("lookup would read a node of level " + std::to_string(l) + " that was not baked");
        const float* p = level.nodeData(std::size_t(at), volume.basis.channelCount());
        for (int j = 0; j < 9; ++j)
            e += Rgbd(p[3 * j], p[3 * j + 1], p[3 * j + 2]) * (w * sh::kCosineLobe[sh::bandOf(j)] * y[j]);
    }
    if (levelUsed) *levelUsed = int(l);
    return e;
}

void ShLevelsLookup::channelValues(const Vec3d& x, float* out) const {
    Rgb L[9];
    shRadiance(x, L);
    for (int j = 0; j < 9; ++j) out[3 * j] = L[j].x, out[3 * j + 1] = L[j].y, out[3 * j + 2] = L[j].z;
}

}  // namespace vdblight
