// Large coordinates: the frame arithmetic shared by scenes (scene_origin.h), volumes and
// lookups of volumes far from the origin (query/shifted_lookup.cpp). Header-only, in `core`:
// the anchor is a property of a box, not of a scene, so a lookup need not know scenes.
#pragma once

#include <algorithm>
#include <cmath>

#include "vdblight/core/math.h"

namespace vdblight {

/// The anchor a box far from the origin is recentred on: its centre rounded to a multiple of
/// the power of two at or above its largest extent (so the subtraction is cheap to reason
/// about and small moves of the box keep the same anchor). (0, 0, 0) when the centre lies
/// within 16 extents of the origin, where float coordinates already resolve the box to
/// better than 1e-6 of its size: nothing near the origin is moved.
inline Vec3d recenteringAnchor(const Bounds& box) {
    if (box.empty()) return {0, 0, 0};
    const Vec3d c = box.center(), size = box.size();
    const double extent = std::max(size.x, std::max(size.y, size.z));
    const double distance = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z)));
    if (!std::isfinite(distance) || !(distance > 16.0 * extent)) return {0, 0, 0};
    // Granularity: the power of two at or above the extent (at least 2^-20 for a point).
    const double g = std::exp2(std::ceil(std::log2(std::max(extent, std::ldexp(1.0, -20)))));
    return {std::round(c.x / g) * g, std::round(c.y / g) * g, std::round(c.z / g) * g};
}

/// A world box in a frame whose origin lies at `origin` (world - origin, in double).
inline Bounds toLocalBounds(Bounds box, const Vec3d& origin) {
    if (!box.empty()) { box.lo -= origin; box.hi -= origin; }
    return box;
}

}  // namespace vdblight
