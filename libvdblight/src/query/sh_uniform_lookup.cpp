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
    // Fold the convolution constants A_l into the coefficients once, so that a lookup is
    // a plain dot product with Y_j(n).
    coeffs_.resize(level.data.size());
    for (std::size_t i = 0; i < level.data.size(); ++i) {
        const int j = int((i % kFloatsPerNode) / 3);
        coeffs_[i] = level.data[i] * float(sh::kCosineLobe[sh::bandOf(j)]);
    }
    depth_ = level.depth;
    depthWeights_ = !depth_.empty();
    setWideVectors(true);
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
        if (depthWeights_) depth[corner] = depth_.data() + nodes[corner] * depth::kFloatsPerNode;
    }
    if (depthWeights_) query_detail::weightByDepth(weights, depth, fx, fy, fz);
    for (int corner = 0; corner < 8; ++corner) {
        const float w = weights[corner];
        const float* p = coeffs_.data() + nodes[corner] * kFloatsPerNode;
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
        for (int c = 0; c < 8; ++c) depth[c] = depth_.data() + corners.node[c] * depth::kFloatsPerNode;
        query_detail::weightCornersByDepth(corners, depth, grid_, x, outside_);
    }
    double sum[kFloatsPerNode] = {};
    for (int c = 0; c < 8; ++c) {
        const double w = corners.weight[c];
        if (w == 0.0) continue;
        const float* p = coeffs_.data() + corners.node[c] * kFloatsPerNode;
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

    const std::size_t sx = grid_.nx > 1 ? kFloatsPerNode : 0;
    const std::size_t sy = grid_.ny > 1 ? std::size_t(grid_.nx) * kFloatsPerNode : 0;
    const std::size_t sz = grid_.nz > 1 ? std::size_t(grid_.nx) * grid_.ny * kFloatsPerNode : 0;
    const std::size_t node = grid_.index(i, j, k);
    return query_detail::interpolateSh(coeffs_.data() + node * kFloatsPerNode, sx, sy, sz, fx, fy, fz, y,
                                       depthWeights_ ? depth_.data() + node * depth::kFloatsPerNode : nullptr);
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
