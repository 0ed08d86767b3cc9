// Irradiance-vector volumes: the two blends (the quadratic one exact for SH bands 0-2 and odd
// bands, against numerical integration; the paper's n^2 blend exact on the axes and a lower
// bound), the fast lookup against the simple reference, exactness of trilinear and tricubic
// reconstruction on linear fields, C1 continuity of the tricubic one (finite differences),
// the registry, and a .vdb round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "grids.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "vdblight/volume/vdb_io.h"

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

TEST(IrradianceVectors, BothBlendsAreExactOnTheAxes) {
    float v[iv::kFloatsPerNode];
    for (int f = 0; f < iv::kFloatsPerNode; ++f) v[f] = float(f + 1);
    for (iv::Blend blend : {iv::Blend::Quadratic, iv::Blend::Paper})
        for (int d = 0; d < iv::kDirections; ++d) {
            Vec3f n{0, 0, 0};
            n[d / 2] = d % 2 ? -1.0f : 1.0f;
            const Rgb e = iv::irradiance(v, n, blend);
            for (int c = 0; c < 3; ++c) {
                const float* p = v + 3 * iv::channel(d, c);
                EXPECT_FLOAT_EQ(e[c], dot(Vec3f(p[0], p[1], p[2]), n)) << iv::blendName(blend) << " direction " << d;
            }
        }
    EXPECT_EQ(iv::basis().channelNames[iv::channel(iv::direction(2, true), 1)], "iv_zneg_g");
    EXPECT_EQ(iv::parseBlend("paper"), iv::Blend::Paper);
    EXPECT_THROW(iv::parseBlend("cubic"), ValueError);
}

TEST(IrradianceVectors, FloatBlendsMatchTheDoubleReference) {
    Rng rng(21);
    for (int s = 0; s < 300; ++s) {
        float v[iv::kFloatsPerNode];
        double vd[iv::kFloatsPerNode];
        for (int f = 0; f < iv::kFloatsPerNode; ++f) vd[f] = v[f] = rng.uniform() * 2 - 1;
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        for (iv::Blend blend : {iv::Blend::Bounded, iv::Blend::Quadratic, iv::Blend::Paper}) {
            const Rgb e = iv::irradiance(v, n, blend);
            const Rgbd r = iv::referenceIrradiance(vd, Vec3d(n), blend);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], r[c], 1e-5) << iv::blendName(blend) << " sample " << s;
        }
    }
}

namespace {
/// The six vectors of a radiance field L(w) and its exact irradiance E(n), by numerical
/// integration over the sphere (midpoint rule in (cos theta, phi): equal solid angles).
struct Integrated {
    double v[iv::kFloatsPerNode] = {};  // colour 0 only is filled, then copied to 1 and 2
    std::vector<Vec3d> dirs;
    std::vector<double> radiance;
    double weight = 0;
    double irradiance(const Vec3d& n) const {
        double e = 0;
        for (std::size_t i = 0; i < dirs.size(); ++i) e += radiance[i] * std::max(0.0, dot(dirs[i], n));
        return e * weight;
    }
};

template <typename F>
Integrated integrate(F radiance, int rows = 400) {
    Integrated r;
    const int cols = 2 * rows;
    r.weight = 4.0 * kPi / (double(rows) * cols);
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
            const double z = -1.0 + 2.0 * (i + 0.5) / rows, phi = 2.0 * kPi * (j + 0.5) / cols;
            const double s = std::sqrt(std::max(0.0, 1 - z * z));
            const Vec3d w(s * std::cos(phi), s * std::sin(phi), z);
            const double L = radiance(w);
            r.dirs.push_back(w);
            r.radiance.push_back(L);
            for (int a = 0; a < 3; ++a) {
                if (w[a] == 0.0) continue;
                const int d = iv::direction(a, w[a] < 0.0);
                for (int k = 0; k < 3; ++k) r.v[9 * d + k] += L * w[k] * r.weight;
            }
        }
    for (int d = 0; d < iv::kDirections; ++d)
        for (int c = 1; c < 3; ++c)
            for (int k = 0; k < 3; ++k) r.v[9 * d + 3 * c + k] = r.v[9 * d + k];
    return r;
}
}  // namespace

// The quadratic blend is exact for any radiance of SH bands 0, 1, 2 plus an odd band (here a
// band-3 term w_x w_y w_z, which the clamped cosine does not see); so is the bounded one, the
// radiance being non-negative (band 0 large enough); the paper's blend is not (the test can fail).
TEST(IrradianceVectors, QuadraticBlendIsExactForSecondOrderRadiance) {
    Rng rng(31);
    for (int field = 0; field < 4; ++field) {
        float c[sh::kCoeffs];
        c[0] = 12.0f;  // L >= 3.39 - 8 * 0.6 * 0.63 - 2 * 0.19 > 0
        for (int j = 1; j < sh::kCoeffs; ++j) c[j] = rng.uniform() * 1.2f - 0.6f;
        const double odd = rng.uniform() * 4 - 2;
        const Integrated in = integrate([&](const Vec3d& w) {
            float y[sh::kCoeffs];
            sh::evalUnrolled(Vec3f(w), y);
            double L = odd * w.x * w.y * w.z;
            for (int j = 0; j < sh::kCoeffs; ++j) L += c[j] * y[j];
            return L;
        });
        double worstQuadratic = 0, worstPaper = 0;
        for (int s = 0; s < 40; ++s) {
            const Vec3d n(uniformSphere(rng.uniform(), rng.uniform()));
            const double want = in.irradiance(n);
            worstQuadratic = std::max(worstQuadratic, std::abs(iv::referenceIrradiance(in.v, n, iv::Blend::Quadratic).x - want));
            worstPaper = std::max(worstPaper, std::abs(iv::referenceIrradiance(in.v, n, iv::Blend::Paper).x - want));
            float vf[iv::kFloatsPerNode];
            for (int f = 0; f < iv::kFloatsPerNode; ++f) vf[f] = float(in.v[f]);
            EXPECT_NEAR(iv::irradiance(vf, Vec3f(n), iv::Blend::Quadratic).y, want, 2e-3 * c[0]) << field << " " << s;
            EXPECT_NEAR(iv::irradiance(vf, Vec3f(n), iv::Blend::Bounded).y, want, 2e-3 * c[0]) << field << " " << s;
        }
        std::printf("SH bands 0-2 + odd band 3, field %d: worst |E - exact| quadratic %.2e, paper %.2e (E ~ %.2f)\n",
                    field, worstQuadratic, worstPaper, kPi * c[0] * 0.2821);
        EXPECT_LT(worstQuadratic, 2e-3 * c[0]);
        EXPECT_GT(worstPaper, 0.05 * c[0]);
    }
}

// The paper's blend reads, per axis, the tangent plane <I_delta, n> of the convex function E
// at delta: a lower bound of E for every non-negative radiance. Under uniform light it is
// pi L sum |n_a|^3; the quadratic blend gives pi L.
TEST(IrradianceVectors, PaperBlendIsALowerBoundQuadraticIsExactUnderUniformLight) {
    Rng rng(41);
    for (int field = 0; field < 3; ++field) {
        // A dim ambient plus three lobes of random directions and sharpness: non-negative.
        Vec3d axis[3];
        double power[3], sharp[3];
        for (int k = 0; k < 3; ++k) {
            axis[k] = Vec3d(uniformSphere(rng.uniform(), rng.uniform()));
            power[k] = 1 + 4 * rng.uniform();
            sharp[k] = 1 + 30 * rng.uniform();
        }
        const Integrated in = integrate([&](const Vec3d& w) {
            double L = 0.05;
            for (int k = 0; k < 3; ++k) L += power[k] * std::pow(std::max(0.0, dot(w, axis[k])), sharp[k]);
            return L;
        });
        for (int s = 0; s < 60; ++s) {
            const Vec3d n(uniformSphere(rng.uniform(), rng.uniform()));
            const double want = in.irradiance(n), paper = iv::referenceIrradiance(in.v, n, iv::Blend::Paper).x;
            EXPECT_LE(paper, want * (1 + 1e-3) + 1e-4) << "field " << field << " normal " << s;
            // The bounded blend is never further from E than the quadratic one (E lies within the bounds).
            const double q = iv::referenceIrradiance(in.v, n, iv::Blend::Quadratic).x;
            const double b = iv::referenceIrradiance(in.v, n, iv::Blend::Bounded).x;
            EXPECT_LE(std::abs(b - want), std::abs(q - want) + 1e-3 * want + 1e-4) << "field " << field << " normal " << s;
        }
    }
    const Integrated uniform = integrate([](const Vec3d&) { return 1.0; });
    for (int s = 0; s < 50; ++s) {
        const Vec3d n(uniformSphere(rng.uniform(), rng.uniform()));
        const double cubes = std::pow(std::abs(n.x), 3) + std::pow(std::abs(n.y), 3) + std::pow(std::abs(n.z), 3);
        EXPECT_NEAR(iv::referenceIrradiance(uniform.v, n, iv::Blend::Quadratic).x, kPi, 2e-3) << s;
        EXPECT_NEAR(iv::referenceIrradiance(uniform.v, n, iv::Blend::Bounded).x, kPi, 2e-3) << s;
        EXPECT_NEAR(iv::referenceIrradiance(uniform.v, n, iv::Blend::Paper).x, kPi * cubes, 2e-3) << s;
    }
}

// One distant light of irradiance E0 from w: I_delta = E0 w for the three delta facing it,
// E(n) = E0 max(0, w.n). The lower bound max_delta <I_delta, n> is then E itself, so the
// bounded blend never reads less than E, never further from it than the quadratic blend, and
// exactly E when w lies in n's octant (where the upper bound is E too).
TEST(IrradianceVectors, BoundedBlendAndOneDistantLight) {
    Rng rng(51);
    int sameOctant = 0;
    for (int s = 0; s < 2000; ++s) {
        const Vec3d w(uniformSphere(rng.uniform(), rng.uniform())), n(uniformSphere(rng.uniform(), rng.uniform()));
        double v[iv::kFloatsPerNode] = {};
        for (int d = 0; d < iv::kDirections; ++d) {
            if (w[d / 2] * (d % 2 ? -1.0 : 1.0) <= 0.0) continue;
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) v[9 * d + 3 * c + k] = 2.0 * w[k];
        }
        const double want = 2.0 * std::max(0.0, dot(w, n));
        const double q = iv::referenceIrradiance(v, n, iv::Blend::Quadratic).x, b = iv::referenceIrradiance(v, n, iv::Blend::Bounded).x;
        EXPECT_GE(b, want - 1e-12) << s;
        EXPECT_LE(std::abs(b - want), std::abs(q - want) + 1e-12) << s;
        if (w.x * n.x > 0 && w.y * n.y > 0 && w.z * n.z > 0) {
            ++sameOctant;
            EXPECT_NEAR(b, want, 1e-12) << s;
            // (n is a float unit vector: sum n_a^2 = 1 to float precision)
            EXPECT_NEAR(iv::referenceIrradiance(v, n, iv::Blend::Paper).x, want, 1e-6) << s;
        }
    }
    EXPECT_GT(sameOctant, 100);
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
    // At a node: the reference lookup (the default, bounded blend); with the quadratic blend and
    // n = -y, <I_{-y}, -y> of that node. (The random vectors are not those of any light, so the
    // bounded blend's clamp may move them.)
    const GridSpec& g = v.levels[0].grid;
    const std::size_t node = g.index(2, 1, 3);
    const Vec3f x(g.node(2, 1, 3)), n(0, -1, 0);
    const Rgb e = query.irradiance(x, n);
    const Rgbd r = referenceVectorLookup(back, Vec3d(x), Vec3d(n));
    const Rgb q = VectorGridLookup(back, OutsidePolicy::Clamp, Interpolation::Trilinear, iv::Blend::Quadratic).irradiance(x, n);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(e[c], r[c], 1e-6);
        EXPECT_NEAR(q[c], -v.levels[0].nodeData(node, iv::kChannels)[3 * iv::channel(iv::direction(1, true), c) + 1], 1e-6);
    }
}
