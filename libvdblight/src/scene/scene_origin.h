// Large coordinates: a scene keeps a double-precision world origin and its geometry in float
// relative to it, as large-world engines do (docs/scene.md, "Large coordinates").
//
// Everything that traces rays works in the scene's local frame (Scene::positions); only the
// placement of a volume in the world (its grids' origins, hence the .vdb transform) and the
// points given to `query` / `reference` are world coordinates, in double. The frame
// arithmetic (recenteringAnchor, toLocalBounds) is in world_frame.h, placing a volume in
// the world (placeVolumeInWorld) in volume/volume.h.
#pragma once

#include "vdblight/core/math.h"
#include "core/world_frame.h"

namespace vdblight {

struct Scene;

/// Moves the scene's local frame by recenteringAnchor(scene.bounds()): vertices and
/// point / spot light positions are rewritten relative to the new origin (in double, then
/// rounded to float once). A no-op for scenes near the origin. Returns the shift applied.
Vec3d recenterScene(Scene& scene);

/// Moves the whole scene by `offset` in world space without touching its float geometry:
/// only Scene::origin changes, so lighting in the local frame is bit-identical.
void translateScene(Scene& scene, const Vec3d& offset);

}  // namespace vdblight
