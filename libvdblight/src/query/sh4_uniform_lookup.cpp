#include "sh4_uniform_lookup.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
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

typedef float Float8 __attribute__((vector_size(32)));

/// The irradiance of the corners' records p[c] blended with weights w[c], for the terms'
/// weights bw[t] (A_l Y(n) of lit coefficient t), V's width of floats at a time (4 or 8: the
/// same operations on the same lanes, so both give the same bits), in ChannelLookup's order
/// (the same bits as it, and as the streamed lookups):
///  - each float f of the record summed over the corners in order c = 0..7, then times bw of
///    its term (the lanes of bw repeated per colour);
///  - each colour's products summed over the terms in order, from 0.
/// The blend and the products stay in registers until one store: through a float array of
/// blended values, the AVX2 build's loads of each term's three colours straddled its 32-byte
/// stores and waited for them (its lookup took 1.4x the SSE one's time, points in cache); and GCC, left
/// to vectorise the corner loop, kept the loads apart from the products (three SSE
/// instructions per four floats and corner).
template <class V>
VDBLIGHT_ALWAYS_INLINE Rgb blendTerms(const float* const p[8], const float w[8], const float bw[ShFourUniformLookup::kLitCoeffs]) {
    constexpr int kLanes = int(sizeof(V) / sizeof(float));
    constexpr int kStride = ShFourUniformLookup::kLitStride, kLit = 3 * ShFourUniformLookup::kLitCoeffs;
    static_assert(kStride % kLanes == 0, "whole vectors per record");
    // Records start 16-byte aligned (record(), every stride a multiple of 4 floats), so the SSE
    // build folds the loads into its products.
    const auto lanes = [](V& v, const float* q) { std::memcpy(&v, __builtin_assume_aligned(q, 16), sizeof v); };
    float products[kStride];
#pragma GCC unroll 14
    for (int f = 0; f < kStride; f += kLanes) {
        V s, t;
        lanes(s, p[0] + f);
        s *= w[0];
#pragma GCC unroll 7
        for (int c = 1; c < 8; ++c) {
            lanes(t, p[c] + f);
            s += t * w[c];
        }
        V termWeight;
        for (int l = 0; l < kLanes; ++l) termWeight[l] = f + l < kLit ? bw[(f + l) / 3] : 0.0f;
        s *= termWeight;
        std::memcpy(products + f, &s, sizeof s);
    }
    float sum[3] = {0.0f, 0.0f, 0.0f};
#pragma GCC unroll 18
    for (int t = 0; t < ShFourUniformLookup::kLitCoeffs; ++t)
        for (int c = 0; c < 3; ++c) sum[c] += products[3 * t + c];
    return Rgb(sum[0], sum[1], sum[2]);
}
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
    // Four floats more, and the first record where the storage is 16-byte aligned (record()):
    // operator new promises that alignment on x86-64, but not every allocator keeps it.
    records_.assign(nodes * std::size_t(stride_) + 4, 0.0f);
    recordOffset_ = (16 - reinterpret_cast<std::uintptr_t>(records_.data()) % 16) % 16 / sizeof(float);
    dark_.resize(nodes * kDarkFloats);
    for (std::size_t n = 0; n < nodes; ++n) {
        const float* in = level.data.data() + n * kCoeffs * 3;
        float* record = records_.data() + recordOffset_ + n * std::size_t(stride_);
        for (int t = 0; t < kLitCoeffs; ++t)
            for (int c = 0; c < 3; ++c) record[3 * t + c] = in[3 * storedIndex(t) + c];
        if (hasDepth_) query_detail::prepareDepth(level.depth.data() + n * depth::kFloatsPerNode, record + kLitStride);
        std::copy(in + 3 * 9, in + 3 * 16, dark_.data() + n * kDarkFloats);
    }
    depthWeights_ = hasDepth_;
    // The AVX2 build where the CPU has it (the same bits): vdblight_bench --only query's "blend's
    // builds" rows, two runs under the lock on a shared 2-core AMD EPYC, AVX2 against portable:
    // plain 1.09x, 1.16x, with depth weights 1.23x, 1.20x.
    avx2_ = query_detail::cpuHasAvx2();
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
    for (int c = 0; c < 8; ++c)
        corner[c] = query_detail::inScalarRegister(base + (c & 1) * sx + ((c >> 1) & 1) * sy + (c >> 2) * sz);
    if constexpr (std::is_same_v<T, float>) {
        query_detail::trilinearWeights(f[0], f[1], f[2], weight);  // the same products, four at a time
    } else {
        const T wx[2] = {1 - f[0], f[0]}, wy[2] = {1 - f[1], f[1]}, wz[2] = {1 - f[2], f[2]};
        for (int c = 0; c < 8; ++c) weight[c] = float(wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2]);
    }
    if (depthWeights_) {  // visibility-aware interpolation (depth_weights.h)
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = query_detail::inScalarRegister(record(corner[c]) + kLitStride);
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

template <class V>
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

    const float* p[8];
    for (int c = 0; c < 8; ++c) p[c] = query_detail::inScalarRegister(record(corner[c]));
    return blendTerms<V>(p, w, bw);
}

VDBLIGHT_AVX2 Rgb ShFourUniformLookup::blendIrradianceAvx2(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
    return blendIrradianceBody<Float8>(x, n, cell);
}

Rgb ShFourUniformLookup::blendIrradiance(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
    return blendIrradianceBody<query_detail::Float4>(x, n, cell);
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
        const float* lit = record(corner[c]);
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
