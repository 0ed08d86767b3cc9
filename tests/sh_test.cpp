// Spherical harmonics: the basis is orthonormal, projections of known functions match
// their closed forms, the irradiance convolution is exact for constant light, and the
// unrolled code matches the generic recurrence.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"

using namespace vdblight;

namespace {
// Deterministic quadrature over the sphere: midpoint rule in (z, phi), which is an equal
// area grid, so it integrates the band-limited products below to ~1e-6.
void integrate(int n, const std::function<void(const Vec3d&, double)>& f) {
    const double w = 4.0 * kPi / (double(n) * n);
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double z = 1.0 - 2.0 * (a + 0.5) / n, phi = 2.0 * kPi * (b + 0.5) / n;
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            f({r * std::cos(phi), r * std::sin(phi), z}, w);
        }
}
}  // namespace

TEST(SH, BasisIsOrthonormal) {
    double gram[9][9] = {};
    integrate(400, [&](const Vec3d& d, double w) {
        float y[9];
        sh::evalUnrolled(Vec3f(d), y);
        for (int i = 0; i < 9; ++i)
            for (int j = 0; j < 9; ++j) gram[i][j] += w * y[i] * y[j];
    });
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) EXPECT_NEAR(gram[i][j], i == j ? 1.0 : 0.0, 2e-4) << i << "," << j;
}

TEST(SH, UnrolledMatchesGenericRecurrence) {
    Rng rng(1);
    for (int t = 0; t < 1000; ++t) {
        const Vec3f d = uniformSphere(rng.uniform(), rng.uniform());
        float fast[9];
        double slow[9];
        sh::evalUnrolled(d, fast);
        sh::evalGeneric(2, Vec3d(d), slow);
        for (int j = 0; j < 9; ++j) ASSERT_NEAR(fast[j], slow[j], 2e-6) << "j=" << j << " d=" << d.x << "," << d.y << "," << d.z;
    }
}

TEST(SH, GenericHigherOrdersAreOrthonormalToo) {
    // The reference path is a general recurrence: check it up to order 4 (25 functions).
    const int n = 25;
    std::vector<double> gram(n * n, 0.0);
    integrate(300, [&](const Vec3d& d, double w) {
        double y[25];
        sh::evalGeneric(4, d, y);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) gram[i * n + j] += w * y[i] * y[j];
    });
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) EXPECT_NEAR(gram[i * n + j], i == j ? 1.0 : 0.0, 5e-4) << i << "," << j;
}

TEST(SH, TableMatchesDocumentedConstants) {
    // docs/format.md and sh.h list these values for the axis directions.
    float y[9];
    sh::evalUnrolled({0, 0, 1}, y);
    EXPECT_NEAR(y[0], 0.282095f, 1e-6f);
    EXPECT_NEAR(y[2], 0.488603f, 1e-6f);
    EXPECT_NEAR(y[6], 0.315392f * 2, 1e-6f);
    sh::evalUnrolled({1, 0, 0}, y);
    EXPECT_NEAR(y[3], 0.488603f, 1e-6f);
    EXPECT_NEAR(y[8], 0.546274f, 1e-6f);
    EXPECT_NEAR(y[6], -0.315392f, 1e-6f);
    sh::evalUnrolled({0, 1, 0}, y);
    EXPECT_NEAR(y[1], 0.488603f, 1e-6f);
    EXPECT_NEAR(y[8], -0.546274f, 1e-6f);
    const float s = float(1.0 / std::sqrt(2.0));
    sh::evalUnrolled({s, s, 0}, y);
    EXPECT_NEAR(y[4], 1.092548f * 0.5f, 1e-6f);
    sh::evalUnrolled({0, s, s}, y);
    EXPECT_NEAR(y[5], 1.092548f * 0.5f, 1e-6f);
    sh::evalUnrolled({s, 0, s}, y);
    EXPECT_NEAR(y[7], 1.092548f * 0.5f, 1e-6f);
    EXPECT_STREQ(sh::gridName(0), "sh_l0m0");
    EXPECT_STREQ(sh::gridName(1), "sh_l1m_neg1");
    EXPECT_STREQ(sh::gridName(4), "sh_l2m_neg2");
    EXPECT_STREQ(sh::gridName(8), "sh_l2m2");
}

TEST(SH, ConstantProjectsToDcOnly) {
    // L(w) = c  =>  L_0 = c * sqrt(4 pi), all other coefficients 0.
    double c[9] = {};
    integrate(1000, [&](const Vec3d& d, double w) {
        float y[9];
        sh::evalUnrolled(Vec3f(d), y);
        for (int j = 0; j < 9; ++j) c[j] += w * 2.5 * y[j];
    });
    EXPECT_NEAR(c[0], 2.5 * std::sqrt(4 * kPi), 1e-4);
    for (int j = 1; j < 9; ++j) EXPECT_NEAR(c[j], 0.0, 1e-4);
}

TEST(SH, ConstantEnvironmentGivesPiLForEveryNormal) {
    const float L = 1.7f;
    Rgb coeffs[9] = {};
    coeffs[0] = Rgb(L, 2 * L, 0.5f * L) * float(std::sqrt(4 * kPi));
    Rng rng(3);
    for (int t = 0; t < 200; ++t) {
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb e = sh::irradiance(coeffs, n);
        EXPECT_NEAR(e.x, kPi * L, 1e-5);
        EXPECT_NEAR(e.y, 2 * kPi * L, 1e-5);
        EXPECT_NEAR(e.z, 0.5 * kPi * L, 1e-5);
    }
}

TEST(SH, ClampedCosineLobeProjectsToClosedForm) {
    // f(w) = max(0, w.z): coefficients sqrt(pi)/2, sqrt(pi/3), sqrt(5 pi)/8 on (0,0),(1,0),(2,0)
    // (Ramamoorthi & Hanrahan 2001), zero elsewhere; and A_l = coefficient ratio * sqrt(4pi/(2l+1)).
    double c[9] = {};
    integrate(600, [&](const Vec3d& d, double w) {
        float y[9];
        sh::evalUnrolled(Vec3f(d), y);
        for (int j = 0; j < 9; ++j) c[j] += w * std::max(0.0, d.z) * y[j];
    });
    EXPECT_NEAR(c[0], std::sqrt(kPi) / 2, 1e-4);
    EXPECT_NEAR(c[2], std::sqrt(kPi / 3), 1e-4);
    EXPECT_NEAR(c[6], std::sqrt(5 * kPi) / 8, 1e-4);
    for (int j : {1, 3, 4, 5, 7, 8}) EXPECT_NEAR(c[j], 0.0, 1e-4) << j;
    // The convolution constants follow: A_l = sqrt(4 pi / (2l + 1)) * c_l0.
    EXPECT_NEAR(sh::kCosineLobe[0], std::sqrt(4 * kPi) * c[0], 1e-3);
    EXPECT_NEAR(sh::kCosineLobe[1], std::sqrt(4 * kPi / 3) * c[2], 1e-3);
    EXPECT_NEAR(sh::kCosineLobe[2], std::sqrt(4 * kPi / 5) * c[6], 1e-3);
}

TEST(SH, IrradianceOfALinearRadianceFieldIsExact) {
    // L(w) = a + b.w (band-limited to l <= 1): E(n) = pi a + (2 pi / 3) b.n exactly.
    const double a = 2.0;
    const Vec3d b{0.3, -0.5, 0.9};
    Rgb coeffs[9] = {};
    integrate(300, [&](const Vec3d& d, double w) {
        float y[9];
        sh::evalUnrolled(Vec3f(d), y);
        const float l = float(a + dot(b, d));
        for (int j = 0; j < 9; ++j) coeffs[j] += Rgb(l, l, l) * float(w * y[j]);
    });
    Rng rng(9);
    for (int t = 0; t < 50; ++t) {
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const double expected = kPi * a + 2 * kPi / 3 * dot(b, Vec3d(n));
        EXPECT_NEAR(sh::irradiance(coeffs, n).x, expected, 2e-3);
    }
}
