// The simple depth-weighted lookup (query.h, referenceDepthWeightedLookup): everything from
// the volume's own arrays, in double, with the visibility formula of depth_moments.h written
// out again rather than called, so that a mistake in either shows as a difference.
#include <cmath>

#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "basis/sh.h"

namespace vdblight {

double referenceNodeVisibility(const float* d, const double o[3]) {
    double product = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
        const int meanAt = (o[axis] < 0.0 ? 3 : 0) + axis;  // depth_mean_pos / _neg component
        const double mean = d[meanAt], sigma = d[6 + meanAt];
        const double excess = std::fabs(o[axis]) - mean - double(depth::kDepthBias);
        if (excess > 0.0) {
            const double var = sigma * sigma + double(depth::kDepthMinSigma) * double(depth::kDepthMinSigma);
            product *= var / (var + excess * excess);
        }
    }
    return product * product * product;
}

Rgbd referenceDepthWeightedLookup(const Volume& volume, const Vec3d& x, const Vec3d& n) {
    if (!volume.basis.isSh2()) throw FormatError("referenceDepthWeightedLookup reads SH order-2 volumes");
    int cell[3];
    double frac[3];
    const std::size_t l = finestCellAt(volume.levels, volume.refineFactor(), x, cell, frac);
    const VolumeLevel& level = volume.levels[l];
    double weight[8], sum = 0.0;
    const float* data[8];
    for (int corner = 0; corner < 8; ++corner) {
        const int d[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
        const int dims[3] = {level.grid.nx, level.grid.ny, level.grid.nz};
        int idx[3];
        double w = 1.0, offset[3];
        for (int a = 0; a < 3; ++a) {
            idx[a] = std::min(cell[a] + d[a], dims[a] - 1);
            w *= d[a] ? frac[a] : 1.0 - frac[a];
            offset[a] = frac[a] - d[a];
        }
        const int64_t at = findNode(level, level.grid.index(idx[0], idx[1], idx[2]));
        if (at < 0) throw FormatError("lookup would read a node of level " + std::to_string(l) + " that was not baked");
        data[corner] = level.nodeData(std::size_t(at), volume.basis.channelCount());
        // Cells of the finest level only (the fast lookups' depthWeightsApplyAt, written out again):
        // a coarser leaf cell was not refined, so it holds no geometry.
        const bool weighted = level.hasDepth() && l + 1 == volume.levels.size();
        const double vis = weighted ? referenceNodeVisibility(level.nodeDepth(std::size_t(at)), offset) : 1.0;
        weight[corner] = w * (vis + double(depth::kDepthFloor));
        sum += weight[corner];
    }
    double y[9];
    sh::evalGeneric(2, normalize(n), y);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner)
        for (int j = 0; j < 9; ++j)
            e += Rgbd(data[corner][3 * j], data[corner][3 * j + 1], data[corner][3 * j + 2]) *
                 (weight[corner] / sum * sh::kCosineLobe[sh::bandOf(j)] * y[j]);
    return e;
}

}  // namespace vdblight
