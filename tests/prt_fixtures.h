// Fixtures of the PRT tests: small bake options, and the white furnace (a closed unit box
// whose faces look inwards with albedo 0.5: with uniform direct irradiance E0 on the walls,
// bounce b brings 0.5^b E0 everywhere inside).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "vdblight/prt/prt.h"
#include "vdblight/scene/scene.h"

#include "support/scene_generators.h"

namespace vdblight::test {

/// A small PRT bake for tests (400 samples in clusters of 100, 256 visibility directions
/// compressed to 24 coefficients, 60 training lights), without closure normalisation (as the
/// disk references). The caller sets transferCoeffs and bounces.
inline PrtOptions smallPrtOptions() {
    PrtOptions o;
    o.samples = 400;
    o.clusterSize = 100;
    o.visDirs = 256;
    o.visCoeffs = 24;
    o.trainLights = 60;
    o.closureNormalise = false;
    return o;
}

/// A point light (DirectLight) at p of intensity `intensity` W/sr, for relighting.
inline DirectLight pointLight(const Vec3f& p, const Rgb& intensity = Rgb{1, 1, 1}) {
    DirectLight l;
    l.kind = DirectLight::Kind::Point;
    l.position = Vec3d(p);
    l.value = intensity;
    return l;
}

/// The box [0, 1]^3, faces inward, one material "grey" of albedo 0.5.
inline Scene greyUnitBox() {
    Scene scene;
    const uint32_t m = addMaterial(scene, Material{"grey", Rgb{0.5f, 0.5f, 0.5f}});
    appendBox(scene, {0, 0, 0}, {1, 1, 1}, true, m);
    return scene;
}

/// Distance from surface sample i of greyUnitBox() to the nearest edge of its face (point-to-
/// disk form factors miss the near field there).
inline float distanceToUnitBoxEdge(const SurfaceSamples& s, std::size_t i) {
    float edge = 1.0f;
    for (int a = 0; a < 3; ++a) {
        const float c = s.position[i][a];
        if (std::abs(s.normal[i][a]) < 0.5f) edge = std::min(edge, std::min(c, 1.0f - c));
    }
    return edge;
}

}  // namespace vdblight::test
