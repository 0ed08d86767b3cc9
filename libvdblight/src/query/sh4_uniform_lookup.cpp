#include "sh4_uniform_lookup.h"

#include <algorithm>
#include <string>
#include <type_traits>

#include "../basis/sh_polynomials.h"
#include "depth_weights.h"
#include "float4.h"
#include "lattice_locate.h"
#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "wide_vectors.h"

namespace vdblight {

namespace {
using query_detail::splitCell;

/// The stored coefficient (j = l (l + 1) + m) of lit coefficient t: bands 0..2, then band 4.
constexpr int storedIndex(int t) { return t < 9 ? t : t + 7; }
/// The band l of lit coefficient t.
constexpr int bandOfLit(int t) { return t == 0 ? 0 : (t < 4 ? 1 : (t < 9 ? 2 : 4)); }
}  // namespace

bool ShFourUniformLookup::accepts(const Volume& volume) {
    return !volume.basis.isSh2() && volume.basis.shOrder() == 4 && volume.levels.size() == 1 && !volume.levels[0].sparse() &&
           basisOf(volume.basis) != nullptr;
}

ShFourUniformLookup::ShFourUniformLookup(const Volume& volume, OutsidePolicy outside) : outside_(outside) {
    if (!accepts(volume)) throw FormatError("sh4-uniform lookup: the volume is not one dense level of basis sh:4");
    const VolumeLevel& level = volume.levels[0];
    grid_ = level.grid;
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    const std::size_t nodes = grid_.nodeCount();
    if (level.data.size() != nodes * kCoeffs * 3)
        throw FormatError("sh4-uniform lookup: " + std::to_string(level.data.size()) + " values for " +
                          std::to_string(nodes) + " nodes of 25 RGB coefficients");
    for (int t = 0; t < kLitCoeffs; ++t) lobe_[t] = float(sh::cosineLobe(bandOfLit(t)));
    hasDepth_ = !level.depth.empty();
    if (hasDepth_ && level.depth.size() != nodes * depth::kFloatsPerNode)
        throw FormatError("sh4-uniform lookup: the depth moments do not match the grid");
    stride_ = kLitStride + (hasDepth_ ? query_detail::kPreparedDepthFloats : 0);
    records_.assign(nodes * std::size_t(stride_), 0.0f);
    dark_.resize(nodes * kDarkFloats);
    for (std::size_t n = 0; n < nodes; ++n) {
        const float* in = level.data.data() + n * kCoeffs * 3;
        float* record = records_.data() + n * std::size_t(stride_);
        for (int t = 0; t < kLitCoeffs; ++t)
            for (int c = 0; c < 3; ++c) record[3 * t + c] = in[3 * storedIndex(t) + c];
        if (hasDepth_) query_detail::prepareDepth(level.depth.data() + n * depth::kFloatsPerNode, record + kLitStride);
        std::copy(in + 3 * 9, in + 3 * 16, dark_.data() + n * kDarkFloats);
    }
    depthWeights_ = hasDepth_;
    // The portable build by default: vdblight_bench --only query, the AVX2 build against it
    // alternately in the same runs (2-core AMD EPYC with AVX-512, shared), was slower: on the
    // 54-float layout plain 1.00x, 0.92x, 0.97x, 0.94x, 0.95x, with depth weights 0.91x, 0.89x,
    // 0.97x, 0.93x, 0.92x; on the node records of 56 floats (seven whole 8-lane vectors) plain
    // 0.82x, 0.79x, with depth weights 0.97x, 0.92x. setWideVectors(true) picks it.
}

template <class T>
VDBLIGHT_ALWAYS_INLINE void ShFourUniformLookup::locate(const T g[3], std::size_t corner[8], float weight[8], query_detail::SharedCell* cell) const {
    int idx[3] = {0, 0, 0};
    T f[3] = {0, 0, 0};
    const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    for (int a = 0; a < 3; ++a)
        if (dims[a] >= 2) splitCell(g[a], dims[a], idx[a], f[a]);  // a flat axis: one node, f = 0
    // Node strides along x, y, z (0 along a flat axis: both corners are its one node).
    const std::size_t sx = dims[0] > 1, sy = dims[1] > 1 ? std::size_t(dims[0]) : 0,
                      sz = dims[2] > 1 ? std::size_t(dims[0]) * dims[1] : 0;
    const std::size_t base = grid_.index(idx[0], idx[1], idx[2]);
    for (int c = 0; c < 8; ++c) corner[c] = base + (c & 1) * sx + ((c >> 1) & 1) * sy + (c >> 2) * sz;
    if constexpr (std::is_same_v<T, float>) {
        query_detail::trilinearWeights(f[0], f[1], f[2], weight);  // the same products, four at a time
    } else {
        const T wx[2] = {1 - f[0], f[0]}, wy[2] = {1 - f[1], f[1]}, wz[2] = {1 - f[2], f[2]};
        for (int c = 0; c < 8; ++c) weight[c] = float(wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2]);
    }
    if (depthWeights_) {  // visibility-aware interpolation (depth_weights.h)
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = records_.data() + corner[c] * stride_ + kLitStride;
        query_detail::weightByPreparedDepth(weight, depth, float(f[0]), float(f[1]), float(f[2]));
    }
    if (cell) {
        for (int a = 0; a < 3; ++a) {
            cell->lower[a] = idx[a];
            cell->step[a] = dims[a] > 1;
        }
        for (int c = 0; c < 8; ++c) cell->weight[c] = weight[c];
    }
}

void ShFourUniformLookup::setWideVectors(bool on) { avx2_ = on && query_detail::cpuHasAvx2(); }

VDBLIGHT_AVX2 Rgb ShFourUniformLookup::blendIrradianceAvx2(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
    return blendIrradianceBody(x, n, cell);
}

Rgb ShFourUniformLookup::blendIrradiance(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
    return blendIrradianceBody(x, n, cell);
}

VDBLIGHT_ALWAYS_INLINE Rgb ShFourUniformLookup::blendIrradianceBody(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
    const Vec3f gv = (x - origin_) * invSpacing_;
    query_detail::checkInside(gv, grid_, x, outside_);
    const float g[3] = {gv.x, gv.y, gv.z};
    std::size_t corner[8];
    float w[8];
    locate(g, corner, w, cell);

    float y[kCoeffs];
    sh::evalPolynomials(4, n, y, false);  // band 3 (A_3 = 0) is not read
    float bw[kLitCoeffs];  // A_l Y_j(n), rounded as ShBasis::terms rounds it
    for (int t = 0; t < kLitCoeffs; ++t) bw[t] = lobe_[t] * y[storedIndex(t)];

    // The corners blended first, each float summed over the corners in order (as ChannelLookup
    // sums a term's channel), then the terms in order, one sum per colour. One pass over the
    // record's 56 floats with the eight corners inside: GCC vectorises it (with the corner loop
    // outside, it kept a scalar loop storing blend[f] after every corner: 4.5 against 12 M
    // lookups/s). The three colours of a term sit side by side, so the sums over the terms run
    // in the lanes of one vector (lane 3 picks up the next term's red, and is not read).
    const float* p[8];
    for (int c = 0; c < 8; ++c) p[c] = records_.data() + corner[c] * stride_;
    float blend[kLitStride];
    for (int f = 0; f < kLitStride; ++f) {
        float s = p[0][f] * w[0];
        s += p[1][f] * w[1];
        s += p[2][f] * w[2];
        s += p[3][f] * w[3];
        s += p[4][f] * w[4];
        s += p[5][f] * w[5];
        s += p[6][f] * w[6];
        s += p[7][f] * w[7];
        blend[f] = s;
    }
    query_detail::Float4 sum = {0, 0, 0, 0};
#pragma GCC unroll 18
    for (int t = 0; t < kLitCoeffs; ++t) sum += query_detail::load4(blend + 3 * t) * bw[t];
    return Rgb(sum[0], sum[1], sum[2]);
}

void ShFourUniformLookup::channelValues(const Vec3d& x, float* out) const {
    // In double, so that at a node position the weights are exactly 0 and 1 (the node's values).
    const double g[3] = {(x.x - grid_.origin.x) / grid_.spacing, (x.y - grid_.origin.y) / grid_.spacing,
                         (x.z - grid_.origin.z) / grid_.spacing};
    std::size_t corner[8];
    float w[8];
    locate(g, corner, w);
    std::fill(out, out + kCoeffs * 3, 0.0f);
    for (int c = 0; c < 8; ++c) {
        const float* lit = records_.data() + corner[c] * stride_;
        const float* dark = dark_.data() + corner[c] * kDarkFloats;
        for (int t = 0; t < kLitCoeffs; ++t)
            for (int col = 0; col < 3; ++col) out[3 * storedIndex(t) + col] += w[c] * lit[3 * t + col];
        for (int f = 0; f < kDarkFloats; ++f) out[3 * 9 + f] += w[c] * dark[f];
    }
}

void ShFourUniformLookup::shRadiance(const Vec3d& x, Rgb out[9]) const {
    float values[kCoeffs * 3];
    channelValues(x, values);
    for (int j = 0; j < 9; ++j) out[j] = Rgb(values[3 * j], values[3 * j + 1], values[3 * j + 2]);
}

}  // namespace vdblight
