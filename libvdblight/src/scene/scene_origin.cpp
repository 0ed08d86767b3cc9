// Scene origin and recentring (scene_origin.h).
#include "scene/scene_origin.h"

#include <cmath>

#include "vdblight/scene/scene.h"

namespace vdblight {

Vec3d recenterScene(Scene& scene) {
    const Vec3d anchor = recenteringAnchor(scene.bounds());
    if (anchor == Vec3d(0, 0, 0)) return anchor;
    for (Vec3f& p : scene.positions) p = Vec3f(Vec3d(p) - anchor);
    for (PointLight& l : scene.pointLights) l.position = Vec3f(Vec3d(l.position) - anchor);
    for (SpotLight& l : scene.spotLights) l.position = Vec3f(Vec3d(l.position) - anchor);
    scene.origin += anchor;
    return anchor;
}

void translateScene(Scene& scene, const Vec3d& offset) { scene.origin += offset; }

}  // namespace vdblight
