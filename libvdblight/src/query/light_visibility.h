// Lookups that interpolate per-light visibility (bake --direct occlusion, query_direct.h):
// OcclusionLookup on a volume in memory, and its streamed twin (query/query.h). Export
// samples the visibility textures through this interface, whichever of the two it is given.
#pragma once

#include "vdblight/core/math.h"

namespace vdblight {

class LightVisibility {
public:
    virtual ~LightVisibility() = default;
    /// Visibility (0..1) of every listed light at x (one float per light, in list order),
    /// interpolated between level 0's nodes, x clamped into the node box.
    virtual void visibility(const Vec3d& x, float* out) const = 0;
};

}  // namespace vdblight
