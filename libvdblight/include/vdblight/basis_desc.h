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
};

}  // namespace vdblight
