// Every volume kind answers a point outside its node box the same way (issue 15, item 5):
// with OutsidePolicy::Clamp (the default) exactly the value at the nearest point of the box,
// with OutsidePolicy::Throw a ValueError. Baked volumes of every kind on the bundled Cornell
// box: SH point gather, SH bilevel levels, Greger bins, photon irradiance vectors (full and
// compact; trilinear and tricubic lookups).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "vdblight/bake.h"
#include "vdblight/bake_bins.h"
#include "vdblight/bake_levels.h"
#include "vdblight/errors.h"
#include "vdblight/irradiance_vectors_compact.h"
#include "vdblight/layout_levels.h"
#include "vdblight/photons.h"
#include "vdblight/query.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"
#include "vdblight/vector_grid_lookup.h"
#include "vdblight/volume_compact.h"

using namespace vdblight;

namespace {
struct Kind {
    std::string name;
    Volume volume;
};

std::vector<Kind> bakeEveryKind(const Scene& s, const Tracer& tracer, const GridSpec& grid) {
    std::vector<Kind> kinds;
    GatherOptions g;
    g.raysPerNode = 16;
    g.threads = 1;
    kinds.push_back({"sh2 uniform", bakeShGather(s, tracer, grid, g)});
    LevelsPlacement lp;
    lp.kind = LayoutKind::Bilevel;
    lp.refine = 2;
    kinds.push_back({"sh2 bilevel", bakeShGatherLevels(s, tracer, placeLevels(grid, s.positions, s.indices, lp, 1), g)});
    BinsBakeOptions bo;
    bo.basis.kind = bins::BasisSpec::Kind::Bins;
    bo.basis.resolution = 2;
    bo.threads = 1;
    kinds.push_back({"bins", bakeBins(s, tracer, uniformLayout(grid), bo)});
    PhotonOptions p;
    p.photons = 20000;
    p.threads = 1;
    Volume photons = bakePhotons(s, tracer, grid, p);
    kinds.push_back({"irradiance vectors compact", iv::compact(photons)});
    kinds.push_back({"irradiance vectors", std::move(photons)});
    return kinds;
}

/// Points outside the box beyond each face, edge and corner, and their nearest box points.
void outsidePoints(const Bounds& box, std::vector<Vec3f>& outside, std::vector<Vec3f>& nearest) {
    const Vec3d c = box.center(), half = box.size() * 0.5;
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                if (!dx && !dy && !dz) continue;
                // Inside: a point in the Cornell box's open space (between the blocks); outside:
                // 0.4 box sizes beyond the face(s).
                const Vec3d inward(c.x - 0.5 * half.x, c.y - 0.2 * half.y, c.z + 0.45 * half.z);
                Vec3d p = inward, q = inward;
                const int d[3] = {dx, dy, dz};
                for (int a = 0; a < 3; ++a) {
                    if (!d[a]) continue;
                    p[a] = c[a] + d[a] * (half[a] + 0.4 * box.size()[a]);
                    q[a] = d[a] > 0 ? box.hi[a] : box.lo[a];
                }
                outside.push_back(Vec3f(p));
                nearest.push_back(Vec3f(q));
            }
}
}  // namespace

TEST(OutsidePolicy, EveryKindClampsToTheNearestPointOfItsBox) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement gp;
    gp.resolution = 5;
    const GridSpec grid = placeUniformGrid(s.bounds(), gp, 1);
    const Vec3f normals[3] = {{0, 1, 0}, normalize(Vec3f(0.3f, -0.5f, 0.8f)), {-1, 0, 0}};
    for (const Kind& k : bakeEveryKind(s, tracer, grid)) {
        const IrradianceQuery q(k.volume);  // the default policy
        std::vector<Vec3f> outside, nearest;
        outsidePoints(q.bounds(), outside, nearest);
        for (std::size_t i = 0; i < outside.size(); ++i) {
            ASSERT_FALSE(q.inside(outside[i])) << k.name;
            for (const Vec3f& n : normals) {
                const Rgb far = q.irradiance(outside[i], n), edge = q.irradiance(nearest[i], n);
                // The same value (up to the float rounding of a lattice coordinate on the box face).
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(far[c], edge[c], 1e-5f * (1.0f + std::abs(edge[c]))) << k.name << " point " << i;
            }
            // Lit from above: a point beyond the box is not dark (a lookup returning 0 there fails).
            EXPECT_GT(luminance(q.irradiance(outside[i], {0, -1, 0})), 0.0f) << k.name << " point " << i;
        }
    }
}

TEST(OutsidePolicy, EveryKindRefusesOutsidePointsWhenAskedTo) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement gp;
    gp.resolution = 5;
    const GridSpec grid = placeUniformGrid(s.bounds(), gp, 1);
    for (const Kind& k : bakeEveryKind(s, tracer, grid)) {
        const IrradianceQuery q(k.volume, OutsidePolicy::Throw);
        std::vector<Vec3f> outside, nearest;
        outsidePoints(q.bounds(), outside, nearest);
        for (std::size_t i = 0; i < outside.size(); ++i)
            EXPECT_THROW(q.irradiance(outside[i], {0, 1, 0}), ValueError) << k.name << " point " << i;
        EXPECT_NO_THROW(q.irradiance(Vec3f(q.bounds().center()), {0, 1, 0})) << k.name;
    }
}

TEST(OutsidePolicy, TricubicPhotonLookupClampsLikeTrilinear) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement gp;
    gp.resolution = 5;
    const GridSpec grid = placeUniformGrid(s.bounds(), gp, 1);
    PhotonOptions p;
    p.photons = 20000;
    p.threads = 1;
    const Volume v = bakePhotons(s, tracer, grid, p);
    const VectorGridLookup cubic(v, OutsidePolicy::Clamp, Interpolation::Tricubic);
    std::vector<Vec3f> outside, nearest;
    outsidePoints(grid.nodeBounds(), outside, nearest);
    for (std::size_t i = 0; i < outside.size(); ++i) {
        const Rgb far = cubic.irradiance(outside[i], {0, 1, 0}), edge = cubic.irradiance(nearest[i], {0, 1, 0});
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(far[c], edge[c], 1e-5f * (1.0f + std::abs(edge[c]))) << "point " << i;
    }
}
