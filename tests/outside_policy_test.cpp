// Every volume kind answers a point outside its node box the same way (issue 15, item 5):
// with OutsidePolicy::Clamp (the default) exactly the value at the nearest point of the box,
// with OutsidePolicy::Throw a ValueError beyond 1e-4 of a cell. Baked volumes of every kind on
// the bundled Cornell box: SH point gather (plain and depth-weighted), SH bilevel levels, a
// registry basis (sh:3), Greger bins, a moment basis, photon irradiance vectors (full and
// compact; trilinear and tricubic lookups; both blends), queried far outside and just outside
// (1e-3 and 0.5 of a cell) every face, edge and corner. `bake --direct occlusion` volumes clamp
// their stored light and light visibility the same way and evaluate the lights' exact direct
// light at the point itself (docs/format.md, "Outside the node box").
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "bake/bake_basis.h"
#include "bake/bake_bins.h"
#include "vdblight/core/errors.h"
#include "basis/irradiance_vectors_compact.h"
#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "query/query_direct.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "volume/volume_compact.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup

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
    GatherOptions gd = g;
    gd.depthMoments = true;
    kinds.push_back({"sh2 depth-weighted", bakeShGather(s, tracer, grid, gd)});
    BasisBakeOptions bb;
    bb.raysPerNode = 18;
    bb.threads = 1;
    kinds.push_back({"sh:3 basis", bakeBasis(s, tracer, uniformLayout(grid), *makeBasis("sh:3"), bb)});
    LevelsPlacement lp;
    lp.kind = LayoutKind::Bilevel;
    lp.refine = 2;
    kinds.push_back({"sh2 bilevel", bakeShGatherLevels(s, tracer, placeLevels(grid, s.positions, s.indices, lp, 1), g)});
    BinsBakeOptions bo;
    bo.basis.kind = bins::BasisSpec::Kind::Bins;
    bo.basis.resolution = 2;
    bo.threads = 1;
    kinds.push_back({"bins", bakeBins(s, tracer, uniformLayout(grid), bo)});
    BinsBakeOptions mo = bo;
    mo.basis.kind = bins::BasisSpec::Kind::Moment;
    mo.basis.order = 4;
    kinds.push_back({"moment:4", bakeBins(s, tracer, uniformLayout(grid), mo)});
    PhotonOptions p;
    p.photons = 20000;
    p.threads = 1;
    Volume photons = bakePhotons(s, tracer, grid, p);
    kinds.push_back({"irradiance vectors compact", iv::compact(photons)});
    kinds.push_back({"irradiance vectors", std::move(photons)});
    return kinds;
}

/// Points outside the box beyond each face, edge and corner, and their nearest box points:
/// 0.4 box sizes beyond, and just beyond (1e-3 and 0.5 of a cell `spacing`).
void outsidePoints(const Bounds& box, std::vector<Vec3f>& outside, std::vector<Vec3f>& nearest, double spacing = 0) {
    const Vec3d c = box.center(), half = box.size() * 0.5;
    std::vector<Vec3d> beyond = {box.size() * 0.4};
    if (spacing > 0) beyond.push_back(Vec3d(1, 1, 1) * (1e-3 * spacing)), beyond.push_back(Vec3d(1, 1, 1) * (0.5 * spacing));
    for (const Vec3d& by : beyond)
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    if (!dx && !dy && !dz) continue;
                    // Inside: a point in the Cornell box's open space (between the blocks); outside:
                    // `by` beyond the face(s).
                    const Vec3d inward(c.x - 0.5 * half.x, c.y - 0.2 * half.y, c.z + 0.45 * half.z);
                    Vec3d p = inward, q = inward;
                    const int d[3] = {dx, dy, dz};
                    for (int a = 0; a < 3; ++a) {
                        if (!d[a]) continue;
                        p[a] = c[a] + d[a] * (half[a] + by[a]);
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
        outsidePoints(q.bounds(), outside, nearest, grid.spacing);
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
        outsidePoints(q.bounds(), outside, nearest, grid.spacing);
        for (std::size_t i = 0; i < outside.size(); ++i) {
            EXPECT_THROW(q.irradiance(outside[i], {0, 1, 0}), ValueError) << k.name << " point " << i;
            EXPECT_NO_THROW(q.irradiance(nearest[i], {0, 1, 0})) << k.name << " point " << i;  // on the box
        }
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
    std::vector<Vec3f> outside, nearest;
    outsidePoints(grid.nodeBounds(), outside, nearest, grid.spacing);
    for (iv::Blend blend : {iv::Blend::Quadratic, iv::Blend::Paper}) {
        const VectorGridLookup cubic(v, OutsidePolicy::Clamp, Interpolation::Tricubic, blend);
        const VectorGridLookup refusing(v, OutsidePolicy::Throw, Interpolation::Tricubic, blend);
        for (std::size_t i = 0; i < outside.size(); ++i) {
            const Vec3f n = normalize(Vec3f(0.3f, 1.0f, -0.4f));
            const Rgb far = cubic.irradiance(outside[i], n), edge = cubic.irradiance(nearest[i], n);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(far[c], edge[c], 1e-5f * (1.0f + std::abs(edge[c]))) << iv::blendName(blend) << " point " << i;
            EXPECT_THROW(refusing.irradiance(outside[i], n), ValueError) << iv::blendName(blend) << " point " << i;
        }
    }
}

// bake --direct occlusion: the stored (indirect) light and the lights' visibility clamp to the
// nearest box point like every kind; the exact direct light of each listed light is evaluated
// at the point itself (it needs no stored data), times that clamped visibility.
TEST(OutsidePolicy, OcclusionVolumesClampStoredLightAndVisibility) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    GridPlacement gp;
    gp.resolution = 5;
    const GridSpec grid = placeUniformGrid(s.bounds(), gp, 1);
    DirectOptions d;
    d.mode = DirectMode::Occlusion;
    d.threads = 1;
    const DirectPlan plan = planDirectLight(s, tracer, grid, d);
    ASSERT_FALSE(plan.lights.empty());
    GatherOptions g;
    g.raysPerNode = 16;
    g.threads = 1;
    g.transport.skipAtReceiver = plan.filter;
    Volume v = bakeShGather(s, tracer, grid, g);
    bakeLightVisibility(s, tracer, plan, d, v);
    const IrradianceQuery q(v);
    const OcclusionLookup occ(std::make_unique<ShUniformLookup>(v, OutsidePolicy::Clamp), v);
    std::vector<Vec3f> outside, nearest;
    outsidePoints(grid.nodeBounds(), outside, nearest, grid.spacing);
    const std::size_t m = occ.lights().size();
    std::vector<float> visFar(m), visNear(m);
    for (std::size_t i = 0; i < outside.size(); ++i) {
        const Vec3f n = normalize(Vec3f(0.2f, -1.0f, 0.3f));
        occ.visibility(Vec3d(outside[i]), visFar.data());
        occ.visibility(Vec3d(nearest[i]), visNear.data());
        for (std::size_t l = 0; l < m; ++l) EXPECT_NEAR(visFar[l], visNear[l], 1e-5f) << "point " << i;
        Rgb direct{0, 0, 0};
        for (std::size_t l = 0; l < m; ++l)
            direct += exactIrradiance(occ.lights()[l], Vec3d(outside[i]), Vec3d(n)) * visNear[l];
        const Rgb stored = occ.irradiance(nearest[i], n) - occ.direct(Vec3d(nearest[i]), n);
        const Rgb far = q.irradiance(outside[i], n), want = stored + direct;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(far[c], want[c], 1e-4f * (1.0f + std::abs(want[c]))) << "point " << i;
    }
    const IrradianceQuery refusing(v, OutsidePolicy::Throw);
    for (const Vec3f& x : outside) EXPECT_THROW(refusing.irradiance(x, {0, 1, 0}), ValueError);
}
