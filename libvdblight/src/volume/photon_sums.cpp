// Exact photon sums (photon_sums.h): the scale, the tiles' runs of batches, and the one
// normalisation the single bake and the merge of photon tiles share.
#include "vdblight/volume/tiles.h"

#include <tbb/parallel_for.h>

#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"

namespace vdblight {

int photonSumExponent(double maxPower) {
    if (!(maxPower > 0) || !std::isfinite(maxPower))
        throw ValueError("the photon sums need a positive, finite emitted power, got " + std::to_string(maxPower));
    return std::ilogb(maxPower) - 80;
}

void photonTileBatches(uint64_t batches, int count, int index, uint64_t& first, uint64_t& end) {
    if (count < 1 || uint64_t(count) > batches)
        throw ValueError("--tiles must be between 1 and " + std::to_string(batches) +
                         " (the photon batches of this bake: more photons give more), got " + std::to_string(count));
    if (index < 0 || index >= count)
        throw ValueError("--tile must be between 0 and " + std::to_string(count - 1) + ", got " + std::to_string(index));
    // batches <= 256 (photonBatchSize) and count <= batches: no overflow.
    first = uint64_t(index) * batches / uint64_t(count);
    end = uint64_t(index + 1) * batches / uint64_t(count);
}

Volume photonVolume(const PhotonSums& sums, Metadata meta) {
    const GridSpec& g = sums.grid;
    if (sums.values.size() != g.nodeCount() * iv::kFloatsPerNode)
        throw ValueError("the photon sums do not match their grid");
    if (!sums.complete())
        throw ValueError("the photon sums hold batches " + std::to_string(sums.firstBatch) + ".." +
                         std::to_string(sums.endBatch) + " of " + std::to_string(sums.batches) + ", not every batch");
    Volume volume;
    volume.basis = iv::basis();
    volume.levels.resize(1);
    volume.levels[0].grid = g;
    volume.meta = std::move(meta);
    std::vector<float>& out = volume.levels[0].data;
    out.resize(sums.values.size());
    const double quantum = std::ldexp(1.0, sums.exponent);
    const int dims[3] = {g.nx, g.ny, g.nz};
    const PhotonSumLayout layout(g);
    tbb::parallel_for(0, g.nz, [&](int k) {
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const int idx[3] = {i, j, k};
                const std::size_t base = g.index(i, j, k) * iv::kFloatsPerNode;
                for (int d = 0; d < iv::kDirections; ++d) {
                    const int a = d / 2;
                    double area = g.spacing * g.spacing;
                    for (int b = 0; b < 3; ++b)
                        if (b != a && (idx[b] == 0 || idx[b] == dims[b] - 1)) area *= 0.5;
                    const PhotonFixed* src = sums.values.data() + layout.offset(d, i, j, k);
                    // double(n) rounds to nearest (exact below 2^53 quanta); * quantum is exact.
                    for (int f = 0; f < 9; ++f) out[base + 9 * d + f] = float(double(src[f]) * quantum / area);
                }
            }
    });
    return volume;
}

}  // namespace vdblight
