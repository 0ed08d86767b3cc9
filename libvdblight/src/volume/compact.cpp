// The compact form of a whole irradiance-vector volume (bake --compact): the per-node
// compaction is the basis's (irradiance_vectors_compact.h), the volume around it is ours.
#include "volume/volume_compact.h"

#include "vdblight/core/errors.h"
#include "basis/irradiance_vectors_compact.h"

namespace vdblight {
namespace iv {

Volume compact(const Volume& full) {
    if (!full.basis.isIrradianceVectors() || full.basis.channelCount() != kChannels || full.levels.size() != 1 ||
        full.levels[0].sparse())
        throw FormatError("the compact form needs a single-level irradiance-vector volume, got basis '" +
                          full.basis.kind + "'");
    Volume out;
    out.basis = compactBasis();
    out.meta = full.meta;
    out.meta["compact_form"] = std::string("Pacanowski et al. 2009 section 4.2: colour |I_R|,|I_G|,|I_B| + unit direction of I_R+I_G+I_B per delta");
    out.levels.resize(1);
    VolumeLevel& level = out.levels[0];
    level.grid = full.levels[0].grid;
    level.validity = full.levels[0].validity;
    level.depth = full.levels[0].depth;  // the lookup's depth weights do not depend on the form
    const std::size_t nodes = full.levels[0].storedNodes();
    level.data.resize(nodes * kCompactFloatsPerNode);
    for (std::size_t n = 0; n < nodes; ++n)
        compactNode(full.levels[0].data.data() + n * kFloatsPerNode, level.data.data() + n * kCompactFloatsPerNode);
    return out;
}

}  // namespace iv
}  // namespace vdblight
