// truncateSh (sh_truncate.h): keeps the first (order + 1)^2 channels of every node. The
// channel order of sh2 and sh:N is the same (j = l (l + 1) + m, basis.h), so bands 0..order
// are a prefix of each node's values.
#include "volume/sh_truncate.h"

#include <memory>
#include <string>

#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"

namespace vdblight {

int storedShOrder(const Volume& volume) {
    // Basis::shCoefficients: (N + 1)^2 for sh2 and sh:N, 0 for every other basis.
    const std::unique_ptr<Basis> basis = basisOf(volume.basis);
    const int coeffs = basis ? basis->shCoefficients() : 0;
    if (coeffs == 0) return -1;
    int order = 0;
    while ((order + 1) * (order + 1) < coeffs) ++order;
    return order;
}

Volume truncateSh(Volume volume, int order) {
    const int stored = storedShOrder(volume);
    if (stored < 0)
        throw ValueError("--sh-order applies to volumes of real SH (sh2, sh:N); this one stores '" + volume.basis.kind + "'");
    if (order < 1 || order > stored)
        throw ValueError("--sh-order must be between 1 and the volume's order " + std::to_string(stored) + ", got " +
                         std::to_string(order));
    if (order == stored) return volume;
    const std::size_t keep = std::size_t((order + 1) * (order + 1)) * 3;
    const std::size_t from = std::size_t(volume.basis.channelCount()) * 3;
    for (VolumeLevel& level : volume.levels) {
        const std::size_t nodes = level.data.size() / from;
        std::vector<float> cut(nodes * keep);
        for (std::size_t n = 0; n < nodes; ++n)
            std::copy(level.data.begin() + std::ptrdiff_t(n * from), level.data.begin() + std::ptrdiff_t(n * from + keep),
                      cut.begin() + std::ptrdiff_t(n * keep));
        level.data = std::move(cut);
    }
    volume.basis = order == 2 ? BasisDesc::sh2() : makeBasis("sh:" + std::to_string(order))->desc();
    return volume;
}

}  // namespace vdblight
