// Seam constraints: every seam node of a multi-level volume takes the coarser level's
// trilinear interpolation at its position (C0 across level boundaries; layout_levels.h).
// Which nodes are seams and their stencils are topology (level_topology.h); this writes the
// values, which is why it lives with the volume and not with the layout.
#include <cmath>
#include <string>
#include <vector>

#include "vdblight/core/errors.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

void applySeamConstraints(Volume& volume) {
    const int floats = volume.basis.channelCount() * 3;
    for (std::size_t l = 1; l < volume.levels.size(); ++l) {
        const VolumeLevel& coarse = volume.levels[l - 1];
        VolumeLevel& fine = volume.levels[l];
        const int K = int(std::lround(coarse.grid.spacing / fine.grid.spacing));
        for (const SeamStencil& s : seamStencils(coarse, fine, K, int(l))) {
            std::vector<double> acc(std::size_t(floats), 0.0);
            for (int corner = 0; corner < 8; ++corner) {
                const int d[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
                double w = 1.0;
                for (int a = 0; a < 3; ++a) w *= d[a] ? s.t[a] : 1.0 - s.t[a];
                if (w == 0.0) continue;
                const int64_t at = findNode(coarse, coarse.grid.index(s.cell[0] + d[0], s.cell[1] + d[1], s.cell[2] + d[2]));
                if (at < 0) throw FormatError("level " + std::to_string(l - 1) + " misses a corner of a refined cell");
                const float* src = coarse.data.data() + std::size_t(at) * std::size_t(floats);
                for (int f = 0; f < floats; ++f) acc[std::size_t(f)] += w * double(src[f]);
            }
            float* dst = fine.data.data() + s.node * std::size_t(floats);
            for (int f = 0; f < floats; ++f) dst[f] = float(acc[std::size_t(f)]);
        }
    }
}

}  // namespace vdblight
