#include "sh_uniform_lookup.h"
#include "depth_weights.h"
#include "lattice_locate.h"
#include "sh_trilinear.h"
#include "wide_vectors.h"
#include "vdblight/query/query.h"

#include <cmath>
#include <sstream>

#include "vdblight/core/errors.h"
#include "basis/sh.h"

namespace vdblight {

namespace {
constexpr int kFloatsPerNode = query_detail::kShFloats;
using query_detail::splitCell;
}  // namespace

bool ShUniformLookup::accepts(const Volume& volume) {
    return volume.basis.isSh2() && volume.levels.size() == 1;
}

ShUniformLookup::ShUniformLookup(const Volume& volume, OutsidePolicy outside) : outside_(outside) {
    const VolumeLevel& level = volume.levels[0];
    grid_ = level.grid;
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    const std::size_t nodes = grid_.nodeCount();
    if (level.data.size() != nodes * kFloatsPerNode)
        throw FormatError("sh2-uniform lookup: " + std::to_string(level.data.size()) + " values for " +
                          std::to_string(nodes) + " nodes of 9 RGB coefficients");
    hasDepth_ = !level.depth.empty();
    if (hasDepth_ && level.depth.size() != nodes * depth::kFloatsPerNode)
        throw FormatError("sh2-uniform lookup: the depth moments do not match the grid");
    stride_ = kRecordFloats + (hasDepth_ ? query_detail::kPreparedDepthFloats : 0);
    records_.assign(nodes * std::size_t(stride_), 0.0f);
    for (std::size_t n = 0; n < nodes; ++n) {
        float* record = records_.data() + n * std::size_t(stride_);
        // Fold the convolution constants A_l into the coefficients once, so that a lookup is
        // a plain dot product with Y_j(n).
        for (int i = 0; i < kFloatsPerNode; ++i)
            record[i] = level.data[n * kFloatsPerNode + i] * float(sh::kCosineLobe[sh::bandOf(i / 3)]);
        if (hasDepth_) query_detail::prepareDepth(level.depth.data() + n * depth::kFloatsPerNode, record + kRecordFloats);
    }
    depthWeights_ = hasDepth_;
}

VDBLIGHT_ALWAYS_INLINE void ShUniformLookup::locate(const Vec3f& x, int& i, int& j, int& k, float& fx, float& fy, float& fz) const {
    const Vec3f g = (x - origin_) * invSpacing_;
    query_detail::checkInside(g, grid_, x, outside_);
    splitCell(g.x, grid_.nx, i, fx);
    splitCell(g.y, grid_.ny, j, fy);
    splitCell(g.z, grid_.nz, k, fz);
}

void ShUniformLookup::radianceCoefficients(const Vec3f& x, Rgb out[9]) const {
    int i, j, k;
    float fx, fy, fz;
    locate(x, i, j, k, fx, fy, fz);
    for (int c = 0; c < sh::kCoeffs; ++c) out[c] = Rgb(0, 0, 0);
    const int di = grid_.nx > 1 ? 1 : 0, dj = grid_.ny > 1 ? 1 : 0, dk = grid_.nz > 1 ? 1 : 0;
    float weights[8];
    std::size_t nodes[8];
    const float* depth[8];
    for (int corner = 0; corner < 8; ++corner) {
        const int ci = corner & 1, cj = (corner >> 1) & 1, ck = corner >> 2;
        weights[corner] = (ci ? fx : 1 - fx) * (cj ? fy : 1 - fy) * (ck ? fz : 1 - fz);
        nodes[corner] = grid_.index(i + ci * di, j + cj * dj, k + ck * dk);
        if (depthWeights_) depth[corner] = records_.data() + nodes[corner] * stride_ + kRecordFloats;
    }
    if (depthWeights_) query_detail::weightByPreparedDepth(weights, depth, fx, fy, fz);
    for (int corner = 0; corner < 8; ++corner) {
        const float w = weights[corner];
        const float* p = records_.data() + nodes[corner] * stride_;
        for (int c = 0; c < sh::kCoeffs; ++c) {
            const float a = float(sh::kCosineLobe[sh::bandOf(c)]);
            out[c] += Rgb(p[3 * c], p[3 * c + 1], p[3 * c + 2]) * (w / a);
        }
    }
}

void ShUniformLookup::shRadiance(const Vec3d& x, Rgb out[9]) const {
    // Located in double and snapped onto a node within 1e-9 of a cell, so that sampling at a
    // node's position returns exactly that node (export relies on it); accumulated in double.
    query_detail::TrilinearCorners corners = query_detail::trilinearCorners(grid_, x, outside_);
    if (depthWeights_) {
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = records_.data() + corners.node[c] * stride_ + kRecordFloats;
        query_detail::weightCornersByDepth(corners, depth, grid_, x, outside_, true);
    }
    double sum[kFloatsPerNode] = {};
    for (int c = 0; c < 8; ++c) {
        const double w = corners.weight[c];
        if (w == 0.0) continue;
        const float* p = records_.data() + corners.node[c] * stride_;
        for (int f = 0; f < kFloatsPerNode; ++f) sum[f] += w * p[f];
    }
    for (int c = 0; c < sh::kCoeffs; ++c) {
        const double a = sh::kCosineLobe[sh::bandOf(c)];
        out[c] = Rgb(float(sum[3 * c] / a), float(sum[3 * c + 1] / a), float(sum[3 * c + 2] / a));
    }
}

void ShUniformLookup::setWideVectors(bool on) { avx2_ = on && query_detail::cpuHasAvx2(); }

Rgb ShUniformLookup::irradiancePortable(const Vec3f& x, const Vec3f& n) const { return irradianceBody(x, n); }

VDBLIGHT_AVX2 Rgb ShUniformLookup::irradianceAvx2(const Vec3f& x, const Vec3f& n) const { return irradianceBody(x, n); }

VDBLIGHT_ALWAYS_INLINE Rgb ShUniformLookup::irradianceBody(const Vec3f& x, const Vec3f& n) const {
    int i, j, k;
    float fx, fy, fz;
    locate(x, i, j, k, fx, fy, fz);
    float y[sh::kCoeffs];
    sh::evalUnrolled(n, y);

    // The corners' records (along an axis with one node both corners are that node).
    const std::size_t stride = std::size_t(stride_);
    const std::size_t sx = grid_.nx > 1 ? stride : 0;
    const std::size_t sy = grid_.ny > 1 ? std::size_t(grid_.nx) * stride : 0;
    const std::size_t sz = grid_.nz > 1 ? std::size_t(grid_.nx) * grid_.ny * stride : 0;
    const float* base = records_.data() + grid_.index(i, j, k) * stride;
    const float* corners[8] = {base, base + sx, base + sy, base + sx + sy,
                               base + sz, base + sx + sz, base + sy + sz, base + sx + sy + sz};
    float weights[8];
    query_detail::trilinearWeights(fx, fy, fz, weights);
    if (depthWeights_) {
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = corners[c] + kRecordFloats;
        query_detail::weightByPreparedDepth(weights, depth, fx, fy, fz);
    }
    return query_detail::blendShCorners<kRecordFloats>(corners, weights, y);
}

Rgbd referenceLookup(const Volume& volume, const Vec3d& x, const Vec3d& n) {
    const VolumeLevel& level = volume.levels.at(0);
    const int channels = volume.basis.channelCount();
    const query_detail::TrilinearCorners t = query_detail::referenceCorners(level.grid, x);
    double y[9];
    sh::evalGeneric(2, normalize(n), y);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        const double w = t.weight[corner];
        const float* p = level.nodeData(t.node[corner], channels);
        for (int j = 0; j < 9; ++j) {
            const double s = w * sh::kCosineLobe[sh::bandOf(j)] * y[j];
            e += Rgbd(p[3 * j], p[3 * j + 1], p[3 * j + 2]) * s;
        }
    }
    return e;
}

void ShUniformLookup::channelValues(const Vec3d& x, float* out) const {
    Rgb L[9];
    shRadiance(x, L);
    for (int j = 0; j < 9; ++j) out[3 * j] = L[j].x, out[3 * j + 1] = L[j].y, out[3 * j + 2] = L[j].z;
}

}  // namespace vdblight
