// PRT for a scene far from the world origin (scene_origin.h): the bake works in the scene's
// local frame, lights are given in world coordinates (prtLocal), and the relit volume is
// placed in the world, so that it reads at world points what the same scene near the origin
// reads at the corresponding points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "prt_fixtures.h"
#include "test_util.h"
#include "vdblight/prt/prt.h"
#include "vdblight/query/query.h"
#include "vdblight/scene/scene.h"
#include "scene/scene_origin.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight {
namespace {

PrtOptions options() {
    PrtOptions o;
    o.samples = 300;
    o.clusterSize = 150;
    o.visDirs = 64;
    o.visCoeffs = 8;
    o.trainLights = 40;
    o.bounces = 2;
    o.volumeResolution = 4;
    return o;
}

float relativeDifference(const Rgb& a, const Rgb& b) {
    const Rgb d = a - b;
    return (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) / (std::abs(b.x) + std::abs(b.y) + std::abs(b.z) + 1e-6f);
}

TEST(PrtOrigin, FarSceneRelitVolumeLandsAtWorldPositions) {
    const Scene base = loadScene(defaultScenePath());
    Scene far = base;
    const Vec3d offset(1e6, -1e6, 5e5 + 0.375);
    translateScene(far, offset);
    const Tracer baseTracer(base), farTracer(far);
    const PrtData basePrt = bakePrt(base, baseTracer, options());
    const PrtData farPrt = bakePrt(far, farTracer, options());
    EXPECT_EQ(basePrt.origin, Vec3d(0, 0, 0));
    EXPECT_EQ(farPrt.origin, offset);

    // The file keeps the origin; the samples read back in the local frame.
    test::TempDir dir;
    writePrt(farPrt, dir.file("far_prt.vdb"));
    const PrtData read = readPrt(dir.file("far_prt.vdb"));
    EXPECT_EQ(read.origin, offset);
    ASSERT_EQ(read.samples.size(), farPrt.samples.size());
    for (std::size_t i = 0; i < read.samples.size(); ++i)
        EXPECT_LT(length(read.samples.position[i] - farPrt.samples.position[i]), 1e-6f) << i;

    // The same physical light, given in world coordinates of each scene.
    const Vec3d light(0.28, 0.40, 0.28);
    const DirectLight nearLight = test::pointLight(prtLocal(basePrt, light), Rgb{1, 0.8f, 0.6f});
    const DirectLight farLight = test::pointLight(prtLocal(farPrt, light + offset), Rgb{1, 0.8f, 0.6f});
    EXPECT_LT(length(farLight.position - nearLight.position), 1e-6);
    const Volume nearV = relightVolume(basePrt, {nearLight}, &base, &baseTracer);
    const Volume farV = relightVolume(farPrt, {farLight}, &far, &farTracer);
    // Read back (16-bit storage), the far file relights to the same volume within quantisation.
    const Volume readV = relightVolume(read, {farLight}, &far, &farTracer);
    EXPECT_EQ(readV.levels[0].grid.origin, farV.levels[0].grid.origin);
    std::vector<Rgb> a(farV.levels[0].data.size() / 3), b(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const float* f = farV.levels[0].data.data() + 3 * i;
        const float* r = readV.levels[0].data.data() + 3 * i;
        a[i] = Rgb{r[0], r[1], r[2]};
        b[i] = Rgb{f[0], f[1], f[2]};
    }
    EXPECT_LT(rmsRelativeError(a, b), 0.01);
    const GridSpec& gn = nearV.levels[0].grid;
    const GridSpec& gf = farV.levels[0].grid;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(gf.origin[a], gn.origin[a] + offset[a], 1e-9) << a;
    EXPECT_EQ(gf.spacing, gn.spacing);

    // The light lands on the same local point, so the relit values and the light's visibility
    // channel are the same bits, and the listed light is in the world.
    EXPECT_EQ(farV.levels[0].data, nearV.levels[0].data);
    ASSERT_TRUE(farV.direct.hasVisibility());
    EXPECT_EQ(farV.levels[0].lightVisibility, nearV.levels[0].lightVisibility);
    EXPECT_LT(length(farV.direct.lights[0].position - (light + offset)), 1e-6);

    // Query both at the same physical points (nodes and points between them) in world
    // coordinates: the shifted lookup of the far volume must read what the near one reads.
    // Cells with a node inside a solid (all zero) are skipped: there the lookup's weights
    // leave out that node, and a point on it reads a rounding-dependent mix.
    auto cellHasDarkNode = [&](const Vec3d& x) {
        int c[3];
        for (int a = 0; a < 3; ++a) c[a] = int(std::floor((x[a] - gn.origin[a]) / gn.spacing + 1e-9));
        const int dims[3] = {gn.nx, gn.ny, gn.nz};
        for (int corner = 0; corner < 8; ++corner) {
            int ijk[3];
            for (int a = 0; a < 3; ++a) ijk[a] = std::min(dims[a] - 1, std::max(0, c[a] + ((corner >> a) & 1)));
            const std::size_t node = (std::size_t(ijk[2]) * std::size_t(gn.ny) + std::size_t(ijk[1])) * std::size_t(gn.nx) + std::size_t(ijk[0]);
            if (nearV.levels[0].data[node * 27] == 0.0f) return true;
        }
        return false;
    };
    const IrradianceQuery qn(nearV), qf(farV);
    const Vec3f normals[3] = {{0, 1, 0}, {1, 0, 0}, normalize(Vec3f{-1, -1, 1})};
    int compared = 0;
    for (std::size_t node = 0; node < gn.nodeCount(); ++node) {
        for (const Vec3d& shift : {Vec3d(0, 0, 0), Vec3d(0.37, 0.21, 0.5) * gn.spacing}) {
            const Vec3d x = gn.node(node) + shift;
            if (!qn.inside(x) || cellHasDarkNode(x)) continue;
            for (const Vec3f& n : normals) {
                const Rgb a = qn.irradianceWorld(x, n), b = qf.irradianceWorld(x + offset, n);
                EXPECT_LT(relativeDifference(b, a), 1e-4f) << "node " << node << " shift " << shift.x;
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 100);
    // Not placed, the far volume would be read at its local box (the check above would fail):
    // the world point of a node is far outside it.
    EXPECT_FALSE(qf.inside(gn.node(0)));
}

}  // namespace
}  // namespace vdblight
