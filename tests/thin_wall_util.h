// The thin-wall room of the visibility-aware interpolation tests (depth_weights_test.cpp,
// depth_weights_photons_test.cpp): its scene, its node grid and the measure of how much light
// a lookup lets through the wall.
#pragma once

#include <algorithm>
#include <cmath>

#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"

#include "random_volumes.h"
#include "support/scene_generators.h"

namespace vdblight::test {

// A closed room [0,4]x[0,2]x[0,2] cut in two at x = 2 by a solid wall 0.08 thick with no
// door, a point light in the x < 2 half. The x > 2 half gets exactly no light. Nodes every
// 0.4 from 0.2: the wall lies between the nodes at x = 1.8 and 2.2 (0.2 of a cell thick).
inline constexpr double kWallLo = 1.96, kWallHi = 2.04;

inline Scene thinWallScene() {
    Scene s;
    s.name = "thin_wall_no_door";
    s.materials.resize(1);
    s.materials[0].albedo = Rgb(0.7f, 0.7f, 0.7f);
    appendBox(s, Vec3f(0, 0, 0), Vec3f(4, 2, 2), /*inward=*/true, 0);
    appendBox(s, Vec3f(float(kWallLo), -0.01f, -0.01f), Vec3f(float(kWallHi), 2.01f, 2.01f), /*inward=*/false, 0);
    s.pointLights.push_back({Vec3f(1.0f, 1.3f, 0.9f), Rgb(10, 10, 10)});
    return s;
}

inline GridSpec thinWallGrid(double originX = 0.2) {
    GridSpec g;
    g.origin = Vec3d(originX, 0.2, 0.2);
    g.spacing = 0.4;
    g.nx = 10;
    g.ny = g.nz = 5;
    return g;
}

struct SideMeans {
    double litMean = 0, darkMean = 0, darkMax = 0;
};

// Irradiance at random points with random normals in the cells that straddle the wall:
// the lit side x in [litLo, 1.96), the dark side x in (2.04, darkHi].
inline SideMeans measureSides(const IrradianceQuery& q, double litLo = 1.8, double darkHi = 2.2) {
    Rng rng(7, 3);
    SideMeans m;
    const int n = 400;
    for (int i = 0; i < n; ++i) {
        const float y = 0.2f + 1.6f * rng.uniform(), z = 0.2f + 1.6f * rng.uniform();
        const Vec3f normal = uniformSphere(rng.uniform(), rng.uniform());
        const float xl = float(litLo + (kWallLo - litLo) * rng.uniform());
        const float xd = float(kWallHi + 1e-3 + (darkHi - kWallHi - 1e-3) * rng.uniform());
        const Rgb lit = q.irradiance(Vec3f(xl, y, z), normal), dark = q.irradiance(Vec3f(xd, y, z), normal);
        m.litMean += std::fabs(luminance(lit)) / n;
        m.darkMean += std::fabs(luminance(dark)) / n;
        m.darkMax = std::max(m.darkMax, double(std::fabs(luminance(dark))));
    }
    return m;
}

// An adaptive SH volume (3 levels, refine 2) on the room's node grid and geometry, with
// random coefficients and random depth moments (random_volumes.h).
inline Volume randomAdaptiveVolume(const Scene& scene, uint64_t dataSeed, uint64_t depthSeed) {
    LevelsPlacement placement;
    placement.kind = LayoutKind::Adaptive;
    placement.refine = 2;
    placement.levels = 3;
    const LevelLayout layout = placeLevels(thinWallGrid(), scene.positions, scene.indices, placement, 256);
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels = volumeLevels(layout.levels);
    for (VolumeLevel& l : v.levels) l.data.resize(l.storedNodes() * 27);
    randomData(v, dataSeed);
    randomDepth(v, depthSeed);
    return v;
}

}  // namespace vdblight::test
