// The directional basis a volume stores at each node, by name: its kind and the grid name of
// each channel. Each basis builds its own (BasisDesc::sh2 here, bins::basis, iv::basis,
// iv::compactBasis); volume.h stores one per volume.
#pragma once

#include <string>
#include <vector>

namespace vdblight {

/// The directional basis stored at each node.
struct BasisDesc {
    std::string kind = "sh2";                ///< "sh2": real SH order 2, radiance coefficients
    std::vector<std::string> channelNames;   ///< grid name of each channel, in channel order

    int channelCount() const { return int(channelNames.size()); }
    /// SH order 2 radiance: nine channels named as sh::gridName(j).
    static BasisDesc sh2();

    // Questions about the kind, answered here so that no code outside src/basis/ compares
    // kind strings (issue 30).
    /// "sh2": SH order 2 in its own fixed layout (the lookups and passes written for it).
    bool isSh2() const;
    /// Real SH radiance coefficients: sh2 or sh:N.
    bool isRealSh() const;
    /// The SH order: 2 for sh2, N for sh:N, -1 for bases that are not real SH.
    int shOrder() const;
    /// The irradiance vectors of the photon pass (iv::basis), full or compact (iv::compactBasis).
    bool isIrradianceVectors() const;
    bool isCompactIrradianceVectors() const;
    /// The same kind as `other` (channels not compared): e.g. a probe stage volume
    /// (probeStageBasis) or the full irradiance vectors a compaction needs.
    bool sameKind(const BasisDesc& other) const;
};

}  // namespace vdblight
