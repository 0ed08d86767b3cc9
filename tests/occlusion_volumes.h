// A small `bake --direct occlusion` volume for export tests: random SH order-2 nodes (the
// indirect light), two listed point lights and visibility channels that are linear in
// position (so trilinear interpolation reproduces them exactly), plus the test's own
// formulas for what the lights add, written out independently of the library.
#pragma once

#include <cmath>

#include "random_volumes.h"
#include "vdblight/light/direct_light.h"

namespace vdblight::test {

/// 5 x 4 x 6 nodes 0.25 apart from (-0.5, 0.25, 1.0) (randomShVolume), lights
///   0: point at (0.3, 3.0, 1.4), 8, 6, 4 W/sr, visibility 0.2 + 0.8 x' (x' = 0..1 across the box)
///   1: point at (-2.5, 0.6, 2.0), 2, 3, 5 W/sr, visibility 1 - 0.6 z'
/// `visible` false: both visibilities 0 everywhere.
inline Volume occlusionVolume(uint64_t seed, bool visible = true) {
    Volume v = randomShVolume(5, 4, 6, 0.25, seed);
    v.direct.mode = DirectMode::Occlusion;
    DirectLight a, b;
    a.position = Vec3d(0.3, 3.0, 1.4);
    a.value = Rgb(8, 6, 4);
    b.position = Vec3d(-2.5, 0.6, 2.0);
    b.value = Rgb(2, 3, 5);
    v.direct.lights = {a, b};
    const GridSpec& g = v.levels[0].grid;
    v.levels[0].lightVisibility.resize(g.nodeCount() * 2);
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                float* vis = &v.levels[0].lightVisibility[g.index(i, j, k) * 2];
                vis[0] = visible ? float(0.2 + 0.8 * i / (g.nx - 1)) : 0.0f;
                vis[1] = visible ? float(1.0 - 0.6 * k / (g.nz - 1)) : 0.0f;
            }
    return v;
}

/// Light l's unshadowed peak irradiance I / d^2 at x times its visibility there (the
/// formulas of occlusionVolume), per channel.
inline Vec3d peakDirect(const Volume& v, const Vec3d& x) {
    const GridSpec& g = v.levels[0].grid;
    const double xr = (x.x - g.origin.x) / (g.spacing * (g.nx - 1)), zr = (x.z - g.origin.z) / (g.spacing * (g.nz - 1));
    const double vis[2] = {0.2 + 0.8 * xr, 1.0 - 0.6 * zr};
    Vec3d sum(0, 0, 0);
    for (int l = 0; l < 2; ++l) {
        const DirectLight& light = v.direct.lights[std::size_t(l)];
        const Vec3d d = light.position - x;
        const double d2 = d.x * d.x + d.y * d.y + d.z * d.z;
        sum = sum + Vec3d(light.value) * (vis[l] / d2);
    }
    return sum;
}

/// The worst pointwise error of SH order-2 irradiance for one point light (Ramamoorthi &
/// Hanrahan's clamped cosine cut after band 2): E_2(c) = E0 (1/4 + c/2 + 5/32 (3c^2 - 1)) for
/// c = n . w against E0 max(c, 0); |E_2 - E| peaks at c = 0 with 3/32 E0 (worked by hand; the
/// tests also measure it). Several lights: the sum of their bounds.
constexpr double kL2PointLightWorstError = 3.0 / 32.0;

}  // namespace vdblight::test
