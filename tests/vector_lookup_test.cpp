// Irradiance-vector volumes: the n^2 blend, the fast lookup against the simple reference,
// exactness of trilinear and tricubic reconstruction on linear fields, C1 continuity of the
// tricubic one (finite differences), the registry, and a .vdb round trip.
#include <gtest/gtest.h>

#include <cmath>

#include "grids.h"
#include "test_util.h"
#include "vdblight/irradiance_vectors.h"
#include "vdblight/query.h"
#include "vdblight/sampling.h"
#include "vdblight/vdb_io.h"
#include "vdblight/vector_grid_lookup.h"

using namespace vdblight;

namespace {
GridSpec testGrid() { return test::makeGrid({1, 2, 3}, 0.5, 5, 4, 6); }

// Each float f of a node: a_f + b_f . position (a linear field), or random values.
Volume makeVolume(bool linear, uint64_t seed) {
    Volume v;
    v.basis = iv::basis();
    v.levels.resize(1);
    VolumeLevel& l = v.levels[0];
    l.grid = testGrid();
    l.data.resize(l.grid.nodeCount() * iv::kFloatsPerNode);
    Rng rng(seed);
    std::vector<float> a(iv::kFloatsPerNode), b(3 * iv::kFloatsPerNode);
    for (float& x : a) x = rng.uniform() * 2 - 1;
    for (float& x : b) x = rng.uniform() * 2 - 1;
    for (std::size_t n = 0; n < l.grid.nodeCount(); ++n) {
        const Vec3d p = l.grid.node(n);
        for (int f = 0; f < iv::kFloatsPerNode; ++f)
            l.data[n * iv::kFloatsPerNode + f] =
                linear ? float(a[f] + b[3 * f] * p.x + b[3 * f + 1] * p.y + b[3 * f + 2] * p.z) : rng.uniform() * 2 - 1;
    }
    return v;
}

Vec3f randomPoint(Rng& rng, const GridSpec& g) {
    const Bounds b = g.nodeBounds();
    return Vec3f(float(b.lo.x + rng.uniform() * (b.hi.x - b.lo.x)), float(b.lo.y + rng.uniform() * (b.hi.y - b.lo.y)),
                 float(b.lo.z + rng.uniform() * (b.hi.z - b.lo.z)));
}
}  // namespace

TEST(IrradianceVectors, BlendIsExactOnTheAxesAndPicksBySign) {
    float v[iv::kFloatsPerNode];
    for (int f = 0; f < iv::kFloatsPerNode; ++f) v[f] = float(f + 1);
    for (int d = 0; d < iv::kDirections; ++d) {
        Vec3f n{0, 0, 0};
        n[d / 2] = d % 2 ? -1.0f : 1.0f;
        const Rgb e = iv::irradiance(v, n);
        for (int c = 0; c < 3; ++c) {
            const float* p = v + 3 * iv::channel(d, c);
            EXPECT_FLOAT_EQ(e[c], dot(Vec3f(p[0], p[1], p[2]), n)) << "direction " << d;
        }
    }
    EXPECT_EQ(iv::basis().channelNames[iv::channel(iv::direction(2, true), 1)], "iv_zneg_g");
}

TEST(VectorGridLookup, TrilinearMatchesTheReference) {
    const Volume v = makeVolume(false, 7);
    const VectorGridLookup fast(v, OutsidePolicy::Clamp);
    Rng rng(3);
    for (int s = 0; s < 500; ++s) {
        const Vec3f x = randomPoint(rng, v.levels[0].grid);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb e = fast.irradiance(x, n);
        const Rgbd r = referenceVectorLookup(v, Vec3d(x), Vec3d(n));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], r[c], 1e-5) << s;
    }
}

TEST(VectorGridLookup, LinearFieldsAreReproducedExactly) {
    const Volume v = makeVolume(true, 11);
    for (Interpolation interp : {Interpolation::Trilinear, Interpolation::Tricubic}) {
        const VectorGridLookup lookup(v, OutsidePolicy::Clamp, interp);
        Rng rng(5);
        for (int s = 0; s < 300; ++s) {
            const Vec3f x = randomPoint(rng, v.levels[0].grid);
            const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
            // The linear field at x, rebuilt from the same random coefficients.
            Rng r(11);
            float field[iv::kFloatsPerNode];
            std::vector<float> a(iv::kFloatsPerNode), b(3 * iv::kFloatsPerNode);
            for (float& q : a) q = r.uniform() * 2 - 1;
            for (float& q : b) q = r.uniform() * 2 - 1;
            for (int f = 0; f < iv::kFloatsPerNode; ++f) field[f] = a[f] + b[3 * f] * x.x + b[3 * f + 1] * x.y + b[3 * f + 2] * x.z;
            const Rgb want = iv::irradiance(field, n), got = lookup.irradiance(x, n);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], want[c], 2e-5 * (1 + std::abs(want[c])))
                    << (interp == Interpolation::Tricubic ? "tricubic" : "trilinear") << " sample " << s;
        }
    }
}

// C1: the derivative along x just left and just right of a node plane agree for tricubic
// (and differ for trilinear, which shows the test can fail).
TEST(VectorGridLookup, TricubicIsC1AcrossCells) {
    const Volume v = makeVolume(false, 13);
    const GridSpec& g = v.levels[0].grid;
    const Vec3f n = normalize(Vec3f(0.3f, 0.8f, -0.5f));
    const float h = 1e-3f;
    double worstCubic = 0, worstLinear = 0;
    for (Interpolation interp : {Interpolation::Tricubic, Interpolation::Trilinear}) {
        const VectorGridLookup lookup(v, OutsidePolicy::Clamp, interp);
        for (int i = 1; i < g.nx - 1; ++i) {
            const Vec3f x = Vec3f(g.node(i, 1, 2)) + Vec3f(0, 0.13f, 0.21f);
            const Vec3f dx{h, 0, 0};
            const double left = (lookup.irradiance(x, n).x - lookup.irradiance(x - dx, n).x) / h;
            const double right = (lookup.irradiance(x + dx, n).x - lookup.irradiance(x, n).x) / h;
            const double jump = std::abs(left - right);
            (interp == Interpolation::Tricubic ? worstCubic : worstLinear) = std::max(
                interp == Interpolation::Tricubic ? worstCubic : worstLinear, jump);
        }
    }
    std::printf("largest derivative jump across a node plane: tricubic %.4f, trilinear %.4f\n", worstCubic, worstLinear);
    EXPECT_LT(worstCubic, 0.05);
    EXPECT_GT(worstLinear, 0.2);
}

TEST(VectorGridLookup, RegisteredAndSurvivesAVdbRoundTrip) {
    const Volume v = makeVolume(false, 17);
    test::TempDir dir;
    const std::string path = dir.file("iv.vdb");
    writeVolume(v, path);
    const Volume back = readVolume(path);
    EXPECT_EQ(back.basis.kind, "irradiance_vectors");
    EXPECT_EQ(back.basis.channelNames, v.basis.channelNames);
    EXPECT_EQ(back.levels[0].data, v.levels[0].data);
    const IrradianceQuery query(back);
    EXPECT_STREQ(query.kind(), "irradiance-vectors-uniform");
    // At a node with n = -y: <I_{-y}, -y> of that node.
    const GridSpec& g = v.levels[0].grid;
    const std::size_t node = g.index(2, 1, 3);
    const Rgb e = query.irradiance(Vec3f(g.node(2, 1, 3)), Vec3f(0, -1, 0));
    for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(e[c], -v.levels[0].nodeData(node, iv::kChannels)[3 * iv::channel(iv::direction(1, true), c) + 1]);
}
