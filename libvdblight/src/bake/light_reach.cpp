// LightReach (light_reach.h).

#include "bake/light_reach.h"

#include <algorithm>
#include <cmath>

namespace vdblight::bake_detail {

namespace {
/// A loop the plane test may answer for: planar within 1e-9 of its size, strictly convex
/// counter-clockwise around `normal`.
bool convexPlanarLoop(const std::vector<Vec3d>& loop, const Vec3d& normal) {
    const std::size_t m = loop.size();
    if (m < 3) return false;
    double size = 0;
    for (const Vec3d& v : loop) size = std::max(size, length(v - loop[0]));
    if (!(size > 0) || !std::isfinite(size)) return false;
    for (std::size_t i = 0; i < m; ++i) {
        const Vec3d &a = loop[i], &b = loop[(i + 1) % m], &c = loop[(i + 2) % m];
        if (std::abs(dot(normal, a - loop[0])) > 1e-9 * size) return false;   // not planar
        if (!(dot(cross(b - a, c - b), normal) > 1e-9 * size * size)) return false;  // a reflex or straight corner
    }
    return true;
}
}  // namespace

LightReach::LightReach(const DirectLight& light) : light_(light), area_(light.area()) {
    planeTest_ = light.kind == DirectLight::Kind::Polygon && light.loops.size() == 1 &&
                 std::abs(length(light.normal) - 1.0) < 1e-9 && maxComponent(light.value) >= 1e-6f && area_ > 0 &&
                 convexPlanarLoop(light.loops[0], light.normal);
}

bool LightReach::reaches(const Vec3d& x) const {
    if (planeTest_) {
        const std::vector<Vec3d>& loop = light_.loops[0];
        // The exact path's own side test (exact_irradiance.cpp, facing): on the plane, or behind
        // a one-sided light, its sum is zero.
        const double side = dot(light_.normal, x - loop[0]);
        if (side == 0 || (side < 0 && !light_.twoSided)) return false;
        // Off the plane by h, the loop's solid angle is at least h * area / r^3 (r: its farthest
        // vertex). Above 1e-9 sr it is positive in double (each triangle's atan2 term rounds by
        // ~1e-16) and its irradiance, >= 1e-6 radiance times it, is a positive float.
        double r2 = 0;
        for (const Vec3d& v : loop) r2 = std::max(r2, dot(v - x, v - x));
        const double r = std::sqrt(r2);
        if (std::abs(side) * area_ > 1e-9 * r2 * r) return true;
    }
    return maxComponent(meanIrradiance(light_, x)) > 0.0f;
}

}  // namespace vdblight::bake_detail
