// Triangle / box overlap by the separating-axis theorem (Akenine-Moeller 2001, "Fast 3D
// triangle-box overlap testing"): 13 axes, the 3 box normals, the triangle normal and the
// 9 cross products of box axes with triangle edges. Computed in double; touching overlaps.
#include <algorithm>

#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {

/// True if the projections of the triangle (v0, v1, v2) and the box (half sizes h, centred
/// at the origin) onto `axis` are disjoint.
bool separated(const Vec3d& axis, const Vec3d& v0, const Vec3d& v1, const Vec3d& v2, const Vec3d& h) {
    const double p0 = dot(axis, v0), p1 = dot(axis, v1), p2 = dot(axis, v2);
    const double r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

}  // namespace

bool triangleOverlapsBox(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Bounds& box) {
    const Vec3d centre = box.center();
    const Vec3d h = box.size() * 0.5;
    const Vec3d v0 = a - centre, v1 = b - centre, v2 = c - centre;

    // Box normals: the triangle's bounding box against the box.
    for (int ax = 0; ax < 3; ++ax) {
        if (std::min({v0[ax], v1[ax], v2[ax]}) > h[ax] || std::max({v0[ax], v1[ax], v2[ax]}) < -h[ax]) return false;
    }
    // Edge x box-axis cross products (a zero axis never separates: both sides give 0 <= r).
    const Vec3d edges[3] = {v1 - v0, v2 - v1, v0 - v2};
    const Vec3d units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3d& e : edges)
        for (const Vec3d& u : units)
            if (separated(cross(u, e), v0, v1, v2, h)) return false;
    // Triangle plane.
    return !separated(cross(edges[0], edges[1]), v0, v1, v2, h);
}

}  // namespace vdblight
