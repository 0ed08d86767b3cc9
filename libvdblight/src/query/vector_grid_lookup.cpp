#include "vdblight/query/query.h"

#include "core/grid_index.h"
#include "depth_weights.h"
#include "lattice_locate.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "basis/irradiance_vectors_compact.h"

namespace vdblight {

bool VectorGridLookup::accepts(const Volume& volume) {
    if (volume.levels.size() != 1) return false;
    return (volume.basis.isIrradianceVectors() && volume.basis.channelCount() == iv::kChannels) ||
           (volume.basis.isCompactIrradianceVectors() && volume.basis.channelCount() == iv::kCompactChannels);
}

VectorGridLookup::VectorGridLookup(const Volume& volume, OutsidePolicy outside, Interpolation interp, iv::Blend blend)
    : outside_(outside), interp_(interp), blend_(blend) {
    if (!accepts(volume)) throw FormatError("not a single-level irradiance-vector volume");
    compact_ = volume.basis.isCompactIrradianceVectors();
    stride_ = compact_ ? iv::kCompactFloatsPerNode : iv::kFloatsPerNode;
    perDirection_ = stride_ / iv::kDirections;
    grid_ = volume.levels[0].grid;
    origin_ = Vec3f(grid_.origin);
    invSpacing_ = float(1.0 / grid_.spacing);
    data_ = volume.levels[0].data;
    depth_ = volume.levels[0].depth;
    if (!depth_.empty() && depth_.size() != grid_.nodeCount() * depth::kFloatsPerNode)
        throw FormatError("irradiance-vector lookup: the depth moments do not match the grid");
    setDepthWeights(true);
}

void VectorGridLookup::locate(const Vec3f& x, int idx[3], float frac[3]) const {
    const Vec3f g = (x - origin_) * invSpacing_;
    const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    if (outside_ == OutsidePolicy::Throw) {
        const float tol = 1e-4f;
        for (int a = 0; a < 3; ++a)
            if (!(g[a] >= -tol && g[a] <= dims[a] - 1 + tol)) {
                std::ostringstream s;
                s << "point (" << x.x << ", " << x.y << ", " << x.z << ") is outside the volume";
                throw ValueError(s.str());
            }
    }
    for (int a = 0; a < 3; ++a) {
        float c = g[a];
        if (!(c >= 0.0f)) c = 0.0f;  // also NaN
        if (c > float(dims[a] - 1)) c = float(dims[a] - 1);
        idx[a] = std::min(int(c), std::max(dims[a] - 2, 0));
        frac[a] = c - float(idx[a]);
    }
}

// Taps along one axis: node indices and weights; returns the number of taps (2 or 4).
int VectorGridLookup::weightsAndNodes(int axis, int i, float t, int nodes[4], float w[4]) const {
    const int n = axis == 0 ? grid_.nx : (axis == 1 ? grid_.ny : grid_.nz);
    auto clampNode = [n](int k) { return std::min(std::max(k, 0), n - 1); };
    if (interp_ == Interpolation::Trilinear) {
        nodes[0] = clampNode(i), nodes[1] = clampNode(i + 1);
        w[0] = 1 - t, w[1] = t;
        return 2;
    }
    // Catmull-Rom through nodes i-1 .. i+2.
    const float t2 = t * t, t3 = t2 * t;
    w[0] = 0.5f * (-t3 + 2 * t2 - t);
    w[1] = 0.5f * (3 * t3 - 5 * t2 + 2);
    w[2] = 0.5f * (-3 * t3 + 4 * t2 + t);
    w[3] = 0.5f * (t3 - t2);
    // Missing end nodes are linear extrapolations: v(-1) = 2 v(0) - v(1), v(n) = 2 v(n-1) - v(n-2).
    if (i - 1 < 0) {
        w[1] += 2 * w[0], w[2] -= w[0], w[0] = 0;
    }
    if (i + 2 > n - 1) {
        w[2] += 2 * w[3], w[1] -= w[3], w[3] = 0;
    }
    for (int k = 0; k < 4; ++k) nodes[k] = clampNode(i - 1 + k);
    return 4;
}

Rgb VectorGridLookup::irradiance(const Vec3f& x, const Vec3f& n) const {
    int idx[3];
    float frac[3];
    locate(x, idx, frac);
    int nodes[3][4];
    float w[3][4];
    int taps = 0;
    for (int a = 0; a < 3; ++a) taps = weightsAndNodes(a, idx[a], frac[a], nodes[a], w[a]);
    // The directions this normal reads: the three of its signs (Paper) or all six.
    int offset[iv::kDirections];
    int directions = 0;
    for (int d = 0; d < iv::kDirections; ++d)
        if (blend_ != iv::Blend::Paper || d == iv::direction(d / 2, n[d / 2] < 0.0f))
            offset[directions++] = perDirection_ * d;

    float interp[iv::kFloatsPerNode] = {};
    if (depthWeights_) {  // trilinear, each corner weighted by its visibility (depth_weights.h)
        float weight[8];
        const float* depth[8];
        std::size_t node[8];
        for (int c = 0; c < 8; ++c) {
            node[c] = grid_.index(nodes[0][c & 1], nodes[1][(c >> 1) & 1], nodes[2][c >> 2]);
            weight[c] = w[0][c & 1] * w[1][(c >> 1) & 1] * w[2][c >> 2];
            depth[c] = depth_.data() + node[c] * depth::kFloatsPerNode;
        }
        query_detail::weightByDepth(weight, depth, frac[0], frac[1], frac[2]);
        for (int c = 0; c < 8; ++c) {
            const float* p = data_.data() + node[c] * stride_;
            for (int d = 0; d < directions; ++d)
                for (int f = 0; f < perDirection_; ++f) interp[offset[d] + f] += weight[c] * p[offset[d] + f];
        }
        return compact_ ? iv::compactIrradiance(interp, n, blend_) : iv::irradiance(interp, n, blend_);
    }
    for (int c = 0; c < taps; ++c)
        for (int b = 0; b < taps; ++b) {
            const float wbc = w[1][b] * w[2][c];
            if (wbc == 0.0f) continue;
            for (int a = 0; a < taps; ++a) {
                const float wt = w[0][a] * wbc;
                if (wt == 0.0f) continue;
                const float* p = data_.data() + grid_.index(nodes[0][a], nodes[1][b], nodes[2][c]) * stride_;
                for (int d = 0; d < directions; ++d)
                    for (int f = 0; f < perDirection_; ++f) interp[offset[d] + f] += wt * p[offset[d] + f];
            }
        }
    return compact_ ? iv::compactIrradiance(interp, n, blend_) : iv::irradiance(interp, n, blend_);
}

Rgbd referenceVectorLookup(const Volume& volume, const Vec3d& x, const Vec3d& nIn, iv::Blend blend, bool depthWeights) {
    const VolumeLevel& level = volume.levels.at(0);
    query_detail::TrilinearCorners t = query_detail::referenceCorners(level.grid, x);
    if (depthWeights && level.hasDepth()) {
        // The point's offset from each corner in cells, from the corners' own positions.
        const Vec3d lattice = (x - level.grid.origin) / level.grid.spacing;
        const int dims[3] = {level.grid.nx, level.grid.ny, level.grid.nz};
        double sum = 0.0;
        for (int corner = 0; corner < 8; ++corner) {
            const std::size_t node = t.node[corner];
            const core::Index3 at = core::unflatten(node, uint64_t(dims[0]), uint64_t(dims[1]));
            const int idx[3] = {at.i, at.j, at.k};
            double o[3];
            for (int a = 0; a < 3; ++a) o[a] = std::min(std::max(lattice[a], 0.0), double(dims[a] - 1)) - idx[a];
            t.weight[corner] *= referenceNodeVisibility(level.depth.data() + node * depth::kFloatsPerNode, o) +
                                double(depth::kDepthFloor);
            sum += t.weight[corner];
        }
        for (double& w : t.weight) w /= sum;
    }
    double v[iv::kFloatsPerNode] = {};
    for (int corner = 0; corner < 8; ++corner) {
        const float* p = level.nodeData(t.node[corner], iv::kChannels);
        for (int f = 0; f < iv::kFloatsPerNode; ++f) v[f] += t.weight[corner] * p[f];
    }
    return iv::referenceIrradiance(v, normalize(nIn), blend);
}

}  // namespace vdblight

namespace vdblight {

void VectorGridLookup::irradianceVectors(const Vec3d& x, float out[54]) const {
    static_assert(iv::kFloatsPerNode == 54, "54 floats per node");
    query_detail::TrilinearCorners corners = query_detail::trilinearCorners(grid_, x, outside_);
    if (depthWeights_) {
        const float* depth[8];
        for (int c = 0; c < 8; ++c) depth[c] = depth_.data() + corners.node[c] * depth::kFloatsPerNode;
        query_detail::weightCornersByDepth(corners, depth, grid_, x, outside_);
    }
    double sum[iv::kFloatsPerNode] = {};
    for (int c = 0; c < 8; ++c) {
        const double w = corners.weight[c];
        if (w == 0.0) continue;
        const float* p = data_.data() + corners.node[c] * stride_;
        float expanded[iv::kFloatsPerNode];
        if (compact_) {  // vectors of a compact volume: decompress each node, then interpolate
            iv::expandNode(p, expanded);
            p = expanded;
        }
        for (int f = 0; f < iv::kFloatsPerNode; ++f) sum[f] += w * p[f];
    }
    for (int f = 0; f < iv::kFloatsPerNode; ++f) out[f] = float(sum[f]);
}

}  // namespace vdblight
