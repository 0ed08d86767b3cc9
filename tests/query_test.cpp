// The run-time lookup: agrees with the simple reference lookup, reproduces node values
// and linear fields exactly, and handles points outside the volume as documented.
#include <gtest/gtest.h>

#include "random_volumes.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup

using namespace vdblight;

namespace {
Vec3f randomPointIn(const GridSpec& g, Rng& rng) {
    const Bounds b = g.nodeBounds();
    return Vec3f(b.lo + b.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
}
}  // namespace

TEST(Query, MatchesTheReferenceLookup) {
    const Volume v = test::randomShVolume(7, 5, 6, 0.3, 1);
    const IrradianceQuery q(v);
    Rng rng(2);
    for (int t = 0; t < 5000; ++t) {
        const Vec3f x = randomPointIn(v.levels[0].grid, rng);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb fast = q.irradiance(x, n);
        const Rgbd slow = referenceLookup(v, Vec3d(x), Vec3d(n));
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(fast[c], slow[c], 2e-5 * (1 + std::abs(slow[c]))) << "t=" << t;
    }
}

TEST(Query, ReproducesNodeValuesExactly) {
    const Volume v = test::randomShVolume(4, 3, 5, 0.5, 3);
    const IrradianceQuery q(v);
    const GridSpec& g = v.levels[0].grid;
    const Vec3f n = normalize(Vec3f(0.3f, -0.4f, 0.8f));
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                Rgb coeffs[9];
                const float* p = v.levels[0].nodeData(g.index(i, j, k), 9);
                for (int c = 0; c < 9; ++c) coeffs[c] = Rgb(p[3 * c], p[3 * c + 1], p[3 * c + 2]);
                const Rgb expected = sh::irradiance(coeffs, n);
                const Rgb got = q.irradiance(Vec3f(g.node(i, j, k)), n);
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(got[c], expected[c], 1e-5 * (1 + std::abs(expected[c])));
            }
}

TEST(Query, TrilinearReproducesLinearFields) {
    // DC coefficient = a + b.x at every node: the query must return pi/(2 sqrt(pi)) (a + b.x).
    Volume v = test::randomShVolume(5, 6, 4, 0.25, 4);
    const GridSpec& g = v.levels[0].grid;
    const Vec3d b{0.7, -1.1, 0.4};
    for (std::size_t node = 0; node < g.nodeCount(); ++node) {
        float* p = v.levels[0].data.data() + node * 27;
        std::fill(p, p + 27, 0.0f);
        const float value = float(2.0 + dot(b, g.node(node)));
        p[0] = p[1] = p[2] = value;
    }
    const IrradianceQuery q(v);
    Rng rng(5);
    for (int t = 0; t < 1000; ++t) {
        const Vec3f x = randomPointIn(g, rng);
        const double expected = kPi * 0.28209479177387814 * (2.0 + dot(b, Vec3d(x)));
        ASSERT_NEAR(q.irradiance(x, {0, 0, 1}).x, expected, 1e-5 * expected);
    }
}

TEST(Query, ClampsOrRefusesPointsOutside) {
    const Volume v = test::randomShVolume(3, 3, 3, 1.0, 6);
    const GridSpec& g = v.levels[0].grid;
    const IrradianceQuery clamp(v, OutsidePolicy::Clamp);
    const IrradianceQuery strict(v, OutsidePolicy::Throw);
    const Vec3f corner = Vec3f(g.nodeBounds().hi);
    const Vec3f outside = corner + Vec3f(5, 0.5f, 2);
    EXPECT_FALSE(clamp.inside(outside));
    EXPECT_TRUE(clamp.inside(corner));
    const Vec3f n{0, 1, 0};
    EXPECT_EQ(clamp.irradiance(outside, n), clamp.irradiance(corner, n));
    EXPECT_THROW(strict.irradiance(outside, n), ValueError);
    EXPECT_NO_THROW(strict.irradiance(corner, n));
    // Non-finite input is outside too, never garbage.
    EXPECT_THROW(strict.irradiance({std::nanf(""), 0, 0}, n), ValueError);
    const Rgb nanClamped = clamp.irradiance({std::nanf(""), std::nanf(""), std::nanf("")}, n);
    EXPECT_EQ(nanClamped, clamp.irradiance(Vec3f(g.origin), n));
}

TEST(Query, WorksOnFlatGrids) {
    // A single node along an axis (a planar or line grid) is a valid volume.
    const Volume v = test::randomShVolume(1, 4, 1, 0.5, 7);
    const IrradianceQuery q(v);
    Rng rng(8);
    for (int t = 0; t < 200; ++t) {
        const Vec3f x = randomPointIn(v.levels[0].grid, rng);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgbd slow = referenceLookup(v, Vec3d(x), Vec3d(n));
        ASSERT_NEAR(q.irradiance(x, n).y, slow.y, 2e-5 * (1 + std::abs(slow.y)));
    }
}

TEST(Query, RefusesUnknownBases) {
    Volume v = test::randomShVolume(2, 2, 2, 1.0, 9);
    v.basis.kind = "nonsense";
    EXPECT_THROW(IrradianceQuery{v}, FormatError);
}

TEST(Query, PicksTheShUniformLookupThroughTheRegistry) {
    const Volume v = test::randomShVolume(3, 3, 3, 1.0, 10);
    const IrradianceQuery q(v);
    EXPECT_STREQ(q.kind(), "sh2-uniform");
    const ShUniformLookup direct(v, OutsidePolicy::Clamp);
    const Vec3f x{0.1f, 0.9f, 1.7f}, n = normalize(Vec3f(1, 2, 3));
    EXPECT_EQ(q.irradiance(x, n), direct.irradiance(x, n));
}
