// Exact photon sums (issue 17, tiles of the photon pass; photons.h, tiles.h).
//
// The photon pass adds each batch of photons into a float buffer, then every batch's buffer
// into the total. The total is kept as 128-bit fixed-point integers: each batch's float sum
// is rounded once to a multiple of one quantum q, and integers add exactly in any order and
// grouping. So the single bake (every batch) and the merge of photon tiles (each tile the
// sum of a run of batches) hold the same integers, and give the same floats, byte for byte.
// (A double total added in batch order, as before, depends on the grouping: tile partial sums
// added at the merge would round differently.)
//
// Scale: q = 2^exponent with exponent = ilogb(Phi) - 80, Phi the largest colour component of
// the scene's emitted power (PhotonEmitter::totalPower): the same for every tile of a bake,
// and in the units of the sums (a photon carries its light's share of Phi / photons).
//
// Range (nothing can overflow): a batch's sum of one value must satisfy
// |sum| <= 2^(exponent + 118) = 2^(ilogb(Phi) + 38) >= 2^37 Phi (checked; a bake beyond it
// stops with ValueError rather than wrap). A bake has at most 256 batches (photonBatchSize),
// so every total, a bake's or a merge's, is below 256 * 2^118 = 2^126 quanta < 2^127. Real
// sums are the flux through one dual face: at most a few times Phi (light crossing the face
// again after bounces; 1 / (1 - albedo) in a white furnace), times the flux estimator's
// 1 / |w_a| for grazing photons; 2^37 Phi is 11 orders of magnitude above that.
//
// Precision: q <= 2^-80 Phi; rounding each batch loses at most q / 2, so a total is within
// 128 q <= 2^-73 Phi of the exact sum of the batches' floats. Relative to the largest value a
// total may hold (2^126 q) that is 2^-126; every sum of at least 2^-49 Phi keeps float's full
// 24-bit precision (its error is at most half a float ulp of it). The stored value is
// float(double(total) * q / area), the same rounding as before for any total below 2^53 q.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/volume.h"

#if !defined(__SIZEOF_INT128__)
#error "vdblight's photon sums need a 128-bit integer type (GCC and Clang on 64-bit targets)"
#endif

namespace vdblight {

/// One fixed-point photon sum: an integer count of quanta 2^PhotonSums::exponent.
using PhotonFixed = __int128;

/// Where the photon sums of direction d at node (i, j, k) are: direction-major, and within a
/// direction the axis of that direction varies fastest, so that the crossings of one segment
/// with the planes normal to axis a are neighbours in memory (a stride of 9 values), which
/// keeps the photon walk in cache. 9 values (colour-major vectors) per (direction, node).
struct PhotonSumLayout {
    std::size_t nodes = 0;
    std::size_t stride[3][3];  ///< stride[a][b]: step in nodes of index b in the arrays of axis a

    explicit PhotonSumLayout(const GridSpec& g) : nodes(g.nodeCount()) {
        const std::size_t n[3] = {std::size_t(g.nx), std::size_t(g.ny), std::size_t(g.nz)};
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            stride[a][a] = 1;
            stride[a][b] = n[a];
            stride[a][c] = n[a] * n[b];
        }
    }
    /// First value of (direction d, node (i, j, k)); 9 values (colour-major vectors) follow.
    std::size_t offset(int d, int i, int j, int k) const {
        const int a = d / 2;
        return (std::size_t(d) * nodes + i * stride[a][0] + j * stride[a][1] + k * stride[a][2]) * 9;
    }
};

/// The photon pass's sums over some of its batches (all of them: a bake; a run: a tile).
struct PhotonSums {
    GridSpec grid;                    ///< the pass's nodes (placed as the volume is)
    int exponent = 0;                 ///< a value is integer * 2^exponent (photonSumExponent)
    std::vector<PhotonFixed> values;  ///< PhotonSumLayout order, iv::kFloatsPerNode per node
    /// The batches summed: [firstBatch, endBatch) of the bake's `batches`.
    uint64_t firstBatch = 0, endBatch = 0, batches = 0;
    bool complete() const { return firstBatch == 0 && endBatch == batches; }
};

/// The quantum's exponent for emitted power `maxPower` (the largest colour component of the
/// scene's total, > 0 and finite; ValueError otherwise): ilogb(maxPower) - 80.
int photonSumExponent(double maxPower);

/// A batch's float sum in quanta 2^exponent (rounded to nearest, ties away from zero), or
/// false if it is not finite or exceeds the per-batch range 2^118 quanta (header comment).
/// `scale` = 2^-exponent (exact: a power of two; the product is exact in double).
inline bool toPhotonFixed(float v, double scale, PhotonFixed& out) {
    const double d = double(v) * scale;
    if (!(std::abs(d) <= 0x1p118)) return false;  // NaN fails too
    if (std::abs(d) >= 0x1p62) {
        // An integer already (>= 2^53): mantissa << exponent, exact (and faster than the
        // compiler's double -> 128-bit conversion, a library call).
        uint64_t bits;
        std::memcpy(&bits, &d, sizeof bits);
        const int shift = int((bits >> 52) & 0x7ff) - 1075;  // >= 10 here
        const PhotonFixed magnitude = PhotonFixed((bits & 0xfffffffffffffull) | (1ull << 52)) << shift;
        out = (bits >> 63) ? -magnitude : magnitude;
        return true;
    }
    const int64_t t = int64_t(d);       // truncated; d - t is exact (the fraction of d)
    const double frac = d - double(t);
    out = PhotonFixed(t + (frac >= 0.5 ? 1 : 0) - (frac <= -0.5 ? 1 : 0));
    return true;
}

/// The batches of tile `index` of `count` of a photon bake with `batches` batches: the
/// contiguous run [first, end) = [index * batches / count, (index + 1) * batches / count).
/// ValueError unless 1 <= count <= batches and 0 <= index < count.
void photonTileBatches(uint64_t batches, int count, int index, uint64_t& first, uint64_t& end);

/// The irradiance-vector volume of complete sums (every batch; ValueError otherwise): each sum divided by its node's
/// dual-face area (h^2, halved on the node box's boundary) into node-major order, basis
/// iv::basis(), metadata `meta`. The single bake and the merge of photon tiles both call it.
Volume photonVolume(const PhotonSums& sums, Metadata meta);

}  // namespace vdblight
