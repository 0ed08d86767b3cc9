#include "bake/sh_window.h"

#include "pass_metadata.h"
#include "vdblight/core/errors.h"
#include "basis/sh.h"

namespace vdblight {

void applyShWindow(Volume& volume) {
    if (!volume.basis.isSh2()) throw ValueError("--sh-window applies to SH order-2 volumes only");
    if (volume.meta.count("sh_window")) throw ValueError("the volume is already windowed");
    for (VolumeLevel& level : volume.levels) {
        const std::size_t nodes = level.data.size() / (sh::kCoeffs * 3);
        for (std::size_t n = 0; n < nodes; ++n)
            for (int j = 1; j < sh::kCoeffs; ++j)
                for (int c = 0; c < 3; ++c)
                    level.data[(n * sh::kCoeffs + j) * 3 + c] *= float(sh::kNonNegativeWindow[sh::bandOf(j)]);
    }
    bake_detail::PassMetadata(volume.meta)
        .text("sh_window", "non-negative spline window w_l = 1/(1 + 0.177732 l^2 (l+1)^2): 1, 0.584478, 0.135165");
}

}  // namespace vdblight
