// The in-memory volume: levels of nodes, each node holding one RGB value per basis
// channel, plus the metadata that travels with it into the .vdb.
//
// Storage in memory is plain arrays (fast to fill in parallel, no OpenVDB types in the
// public API); vdb_io.h turns a Volume into OpenVDB grids and back (docs/format.md).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/math.h"

namespace vdblight {

/// Format version written as vdblight:format_version. Bumped on incompatible changes.
constexpr int kFormatVersion = 1;

using MetaValue = std::variant<std::string, int64_t, double>;
/// Metadata keys without the "vdblight:" prefix that the file adds.
using Metadata = std::map<std::string, MetaValue>;

/// The directional basis stored at each node.
struct BasisDesc {
    std::string kind = "sh2";                ///< "sh2": real SH order 2, radiance coefficients
    std::vector<std::string> channelNames;   ///< grid name of each channel, in channel order

    int channelCount() const { return int(channelNames.size()); }
    /// SH order 2 radiance: nine channels named as sh::gridName(j).
    static BasisDesc sh2();
};

struct VolumeLevel {
    GridSpec grid;
    /// Node-major: data[(node * channels + c) * 3 + rgb], node = grid.index(i, j, k).
    std::vector<float> data;
    /// Optional, empty or one value per node in [0, 1]: the fraction of the node's
    /// trilinear basis-function weight that lay in the domain of interest when it was baked
    /// (bake_antialiased.h); written as the FloatGrid `validity` (docs/format.md).
    std::vector<float> validity;

    const float* nodeData(std::size_t node, int channels) const { return data.data() + node * channels * 3; }
};

struct Volume {
    BasisDesc basis;
    std::vector<VolumeLevel> levels;  ///< level 0 is the coarsest (a uniform volume has one)
    Metadata meta;

    /// Throws FormatError if levels, grids and data sizes are inconsistent.
    void validate() const;
};

/// Reads a metadata value (with conversion between int and double), or `fallback`.
double metaNumber(const Metadata& meta, const std::string& key, double fallback);
std::string metaString(const Metadata& meta, const std::string& key, const std::string& fallback = {});

}  // namespace vdblight
