// Whether a light can add anything at a point, asked many times per light (issue 32: the
// preview's shadow-edge search asks it at every step of its march, ~200 times per node and
// light, and each answer was a polygon's exact solid angle in double: 4 % of the office's
// preview). (Internal to the bake module.)
//
// The exact answer is maxComponent(meanIrradiance(light, x)) > 0 (bake_direct.h: a point the
// light cannot reach counts as unshadowed). For one convex planar loop, the usual panel, it
// is decided by the plane's side wherever the solid angle is far above double rounding; the
// exact formula answers the rest (near the plane, other kinds), so the answer never differs
// from it (light_reach_test checks that at points chosen to be hard).
#pragma once

#include <vector>

#include "vdblight/core/math.h"
#include "vdblight/light/direct_light.h"

namespace vdblight::bake_detail {

class LightReach {
public:
    /// `light` must outlive this.
    explicit LightReach(const DirectLight& light);

    /// maxComponent(meanIrradiance(light, x)) > 0, the same answer at every x.
    bool reaches(const Vec3d& x) const;

private:
    const DirectLight& light_;
    double area_;             ///< DirectLight::area()
    bool planeTest_ = false;  ///< one convex planar loop, positive area and radiance
};

}  // namespace vdblight::bake_detail
