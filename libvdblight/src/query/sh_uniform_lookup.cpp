#include "depth_weights.h"
#include "lattice_locate.h"
#include "vdblight/query.h"

#include <cmath>
#include <sstream>

#include "vdblight/errors.h"
#include "vdblight/sh.h"

namespace vdblight {

namespace {
constexpr int kFloatsPerNode = sh::kCoeffs * 3;

// Lattice coordinate of x along one axis, clamped into [0, n - 1], split into the lower
// node index and the fraction towards the next node.
inline void split(float g, int n, int& i, float& f) {
    if (!(g >= 0.0f)) g = 0.0f;  // also maps NaN to the boundary instead of an index
    if (g > float(n - 1)) g = float(n - 1);
    i = std::min(int(g), std::max(n - 2, 0));
    f = g - float(i);
}
}  // namespace

bool ShUniformLookup::accepts(const Volume& volume) {
    return volume.basis.kind == "sh2" && volume.levels.size() == 1;
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
}

void ShUniformLookup::locate(const Vec3f& x, int& i, int& j, int& k, float& fx, float& fy, float& fz) const {
    const Vec3f g = (x - origin_) * invSpacing_;
    if (outside_ == OutsidePolicy::Throw) {
        const float tol = 1e-4f;
        if (!(g.x >= -tol && g.y >= -tol && g.z >= -tol && g.x <= grid_.nx - 1 + tol && g.y <= grid_.ny - 1 + tol &&
              g.z <= grid_.nz - 1 + tol)) {
            std::ostringstream s;
            s << "point (" << x.x << ", " << x.y << ", " << x.z << ") is outside the volume";
            throw ValueError(s.str());
        }
    }
    split(g.x, grid_.nx, i, fx);
    split(g.y, grid_.ny, j, fy);
    split(g.z, grid_.nz, k, fz);
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
        int lo[3];
        double frac[3];
        query_detail::locateExact(grid_, x, outside_, lo, frac);
        float w[8];
        const float* depth[8];
        for (int c = 0; c < 8; ++c) {
            w[c] = float(corners.weight[c]);
            depth[c] = depth_.data() + corners.node[c] * depth::kFloatsPerNode;
        }
        query_detail::weightByDepth(w, depth, float(frac[0]), float(frac[1]), float(frac[2]));
        for (int c = 0; c < 8; ++c) corners.weight[c] = w[c];
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

Rgb ShUniformLookup::irradiance(const Vec3f& x, const Vec3f& n) const {
    int i, j, k;
    float fx, fy, fz;
    locate(x, i, j, k, fx, fy, fz);
    float y[sh::kCoeffs];
    sh::evalUnrolled(n, y);

    const std::size_t sx = grid_.nx > 1 ? kFloatsPerNode : 0;
    const std::size_t sy = grid_.ny > 1 ? std::size_t(grid_.nx) * kFloatsPerNode : 0;
    const std::size_t sz = grid_.nz > 1 ? std::size_t(grid_.nx) * grid_.ny * kFloatsPerNode : 0;
    const float* base = coeffs_.data() + grid_.index(i, j, k) * kFloatsPerNode;
    const float* corners[8] = {base, base + sx, base + sy, base + sx + sy,
                               base + sz, base + sx + sz, base + sy + sz, base + sx + sy + sz};
    const float wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy}, wz[2] = {1 - fz, fz};
    float weights[8];
    for (int c = 0; c < 8; ++c) weights[c] = wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2];
    if (depthWeights_) {
        // The same corners in the depth array (depth::kFloatsPerNode floats per node).
        const float* depth[8];
        for (int c = 0; c < 8; ++c)
            depth[c] = depth_.data() + std::size_t(corners[c] - coeffs_.data()) / kFloatsPerNode * depth::kFloatsPerNode;
        query_detail::weightByDepth(weights, depth, fx, fy, fz);
    }

    // Interpolate the 27 coefficients first, then one 9-term dot product per channel.
    float interp[kFloatsPerNode] = {};
    for (int c = 0; c < 8; ++c) {
        const float w = weights[c];
        const float* p = corners[c];
        for (int f = 0; f < kFloatsPerNode; ++f) interp[f] += w * p[f];
    }
    Rgb e{0, 0, 0};
    for (int c = 0; c < sh::kCoeffs; ++c) e += Rgb(interp[3 * c], interp[3 * c + 1], interp[3 * c + 2]) * y[c];
    return e;
}

Rgbd referenceLookup(const Volume& volume, const Vec3d& x, const Vec3d& n) {
    const VolumeLevel& level = volume.levels.at(0);
    const GridSpec& g = level.grid;
    const int channels = volume.basis.channelCount();
    const Vec3d lattice = (x - g.origin) / g.spacing;
    const int dims[3] = {g.nx, g.ny, g.nz};
    int lo[3];
    double frac[3];
    for (int a = 0; a < 3; ++a) {
        const double c = std::min(std::max(lattice[a], 0.0), double(dims[a] - 1));
        lo[a] = std::min(int(std::floor(c)), std::max(dims[a] - 2, 0));
        frac[a] = c - lo[a];
    }
    double y[9];
    sh::evalGeneric(2, normalize(n), y);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        int idx[3];
        double w = 1.0;
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            idx[a] = std::min(lo[a] + bit, dims[a] - 1);
            w *= bit ? frac[a] : 1.0 - frac[a];
        }
        const float* p = level.nodeData(g.index(idx[0], idx[1], idx[2]), channels);
        for (int j = 0; j < 9; ++j) {
            const double s = w * sh::kCosineLobe[sh::bandOf(j)] * y[j];
            e += Rgbd(p[3 * j], p[3 * j + 1], p[3 * j + 2]) * s;
        }
    }
    return e;
}

}  // namespace vdblight
