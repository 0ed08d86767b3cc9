// Generated scenes shared by the benchmarks.
#pragma once

#include <string>

#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"

#include "support/scene_generators.h"

namespace vdblight::bench {

/// The default scene (Cornell box) plus two geodesic spheres standing on the floor, of
/// 20 * 4^subdivisions triangles each, in a copy of the white material without emission.
inline Scene cornellWithSpheres(int subdivisionsLarge, int subdivisionsSmall) {
    Scene s = loadScene(defaultScenePath());
    s.name = "cornell_box+spheres";
    Material white = s.materials[0];
    for (const Material& m : s.materials)
        if (m.name.find("white") != std::string::npos) white = m;
    white.emission = {0, 0, 0};
    s.materials.push_back(white);
    const uint32_t id = uint32_t(s.materials.size() - 1);
    appendIcosphere(s, {0.15f, 0.08f, 0.12f}, 0.07f, subdivisionsLarge, id);
    appendIcosphere(s, {0.42f, 0.42f, 0.15f}, 0.06f, subdivisionsSmall, id);
    return s;
}

/// A 64 x 64 floor with 16 closed blocks and `lights` point lights 0.5 to 4 units above it
/// (total intensity independent of the count).
inline Scene manyLightsScene(int lights) {
    Scene s;
    s.name = "many_lights_" + std::to_string(lights);
    s.materials.push_back(Material{});
    s.materials[0].albedo = Rgb(0.6f, 0.6f, 0.6f);
    addTriangle(s, Vec3f(0, 0, 0), Vec3f(0, 0, 64), Vec3f(64, 0, 64), 0);
    addTriangle(s, Vec3f(0, 0, 0), Vec3f(64, 0, 64), Vec3f(64, 0, 0), 0);
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 4; ++k) {
            const Vec3f lo(8.0f + 16 * i, 0, 8.0f + 16 * k);
            appendBox(s, lo, lo + Vec3f(3, 3, 3), false, 0);
        }
    Rng rng(99);
    const float intensity = 2000.0f / float(lights);
    for (int l = 0; l < lights; ++l) {
        const Vec3f pos(64 * rng.uniform(), 0.5f + 3.5f * rng.uniform(), 64 * rng.uniform());
        const float r = 0.5f + rng.uniform();
        s.pointLights.push_back({pos, Rgb(r, 1, 2 - r) * intensity});
    }
    return s;
}

/// An office-like room 8 x 3 x 6 with an emissive ceiling panel, desks (boxes) and
/// `spheres` geodesic "chairs" of 20 * 4^subdivisions triangles each.
inline Scene officeScene(int spheres, int subdivisions) {
    Scene s;
    s.name = "office_" + std::to_string(spheres) + "x" + std::to_string(subdivisions);
    s.materials.resize(3);
    s.materials[0].albedo = Rgb(0.7f, 0.7f, 0.7f);
    s.materials[1].albedo = Rgb(0.6f, 0.4f, 0.3f);
    s.materials[2].emission = Rgb(8, 8, 8);
    appendBox(s, Vec3f(0, 0, 0), Vec3f(8, 3, 6), true, 0);
    addTriangle(s, Vec3f(3, 2.99f, 2), Vec3f(5, 2.99f, 2), Vec3f(5, 2.99f, 4), 2);
    addTriangle(s, Vec3f(3, 2.99f, 2), Vec3f(5, 2.99f, 4), Vec3f(3, 2.99f, 4), 2);
    for (int d = 0; d < 4; ++d) appendBox(s, Vec3f(1.0f + 1.8f * d, 0, 1), Vec3f(2.2f + 1.8f * d, 0.75f, 1.8f), false, 1);
    for (int c = 0; c < spheres; ++c)
        appendIcosphere(s, Vec3f(1.0f + 6.0f * (c + 0.5f) / spheres, 0.4f, 4.5f), 0.35f, subdivisions, 1);
    return s;
}

}  // namespace vdblight::bench
