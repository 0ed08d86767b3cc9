// Large coordinates: a scene keeps a double-precision world origin and its geometry in float
// relative to it, as large-world engines do (docs/scene.md, "Large coordinates").
//
// Everything that traces rays works in the scene's local frame (Scene::positions); only the
// placement of a volume in the world (its grids' origins, hence the .vdb transform) and the
// points given to `query` / `reference` are world coordinates, in double.
#pragma once

#include <algorithm>
#include <cmath>

#include "vdblight/math.h"
#include "vdblight/volume.h"

namespace vdblight {

struct Scene;

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

/// Moves the scene's local frame by recenteringAnchor(scene.bounds()): vertices and
/// point / spot light positions are rewritten relative to the new origin (in double, then
/// rounded to float once). A no-op for scenes near the origin. Returns the shift applied.
Vec3d recenterScene(Scene& scene);

/// Moves the whole scene by `offset` in world space without touching its float geometry:
/// only Scene::origin changes, so lighting in the local frame is bit-identical.
void translateScene(Scene& scene, const Vec3d& offset);

/// A world box in a frame whose origin lies at `origin` (world - origin, in double).
inline Bounds toLocalBounds(Bounds box, const Vec3d& origin) {
    if (!box.empty()) { box.lo -= origin; box.hi -= origin; }
    return box;
}

/// Places a volume baked in a scene's local frame into the world: adds `origin` to every
/// level's grid origin (double). The .vdb written from it maps index space to world space.
inline void placeVolumeInWorld(Volume& volume, const Vec3d& origin) {
    for (VolumeLevel& level : volume.levels) level.grid.origin += origin;
    for (DirectLight& light : volume.direct.lights) light.translate(origin);  // bake --direct
}

}  // namespace vdblight
