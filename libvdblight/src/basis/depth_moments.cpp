// Names of the depth-moment channels (depth_moments.h; docs/format.md "Depth moments").
#include "vdblight/basis/depth_moments.h"

#include <stdexcept>

namespace vdblight::depth {

const std::string& channelName(int channel) {
    static const std::string names[kChannels] = {"depth_mean_pos", "depth_mean_neg", "depth_sigma_pos",
                                                 "depth_sigma_neg"};
    if (channel < 0 || channel >= kChannels) throw std::out_of_range("depth channel out of range");
    return names[channel];
}

}  // namespace vdblight::depth
