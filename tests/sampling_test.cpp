// Sampling: maps are area-preserving and invertible, sequences are stratified and
// deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "vdblight/sampling/sampling.h"

using namespace vdblight;

TEST(Sampling, ConcentricMapRoundTrips) {
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            const float u = (i + 0.37f) / 64, v = (j + 0.61f) / 64;
            float dx, dy, u2, v2;
            concentricSquareToDisk(u, v, dx, dy);
            ASSERT_LE(dx * dx + dy * dy, 1.0f + 1e-6f);
            concentricDiskToSquare(dx, dy, u2, v2);
            EXPECT_NEAR(u, u2, 2e-5f) << "u=" << u << " v=" << v;
            EXPECT_NEAR(v, v2, 2e-5f) << "u=" << u << " v=" << v;
        }
}

TEST(Sampling, ConcentricMapPreservesArea) {
    // Equal-area strata of the square land in equal-area regions of the disk: the
    // fraction of points inside radius r is r^2.
    const int n = 256;
    int inside = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            float dx, dy;
            concentricSquareToDisk((i + 0.5f) / n, (j + 0.5f) / n, dx, dy);
            inside += (dx * dx + dy * dy < 0.25f) ? 1 : 0;
        }
    EXPECT_NEAR(double(inside) / (n * n), 0.25, 2e-3);
}

TEST(Sampling, UniformSphereIntegratesPolynomialsExactly) {
    // E[z^2] = 1/3 and E[x y] = 0 on the sphere; a (0,2)-sequence gets close fast.
    const uint32_t n = 4096;
    double z2 = 0, xy = 0, len = 0;
    for (uint32_t i = 0; i < n; ++i) {
        float u, v;
        sobol02(i, 42, u, v);
        const Vec3f d = uniformSphere(u, v);
        z2 += d.z * d.z;
        xy += d.x * d.y;
        len = std::max(len, std::abs(double(length(d)) - 1.0));
    }
    EXPECT_NEAR(z2 / n, 1.0 / 3.0, 1e-3);
    EXPECT_NEAR(xy / n, 0.0, 1e-3);
    EXPECT_LT(len, 1e-6);
}

TEST(Sampling, SobolIsStratifiedInElementaryIntervals) {
    // For 2^m points, every 2^a x 2^(m-a) box of the unit square holds exactly one point.
    const int m = 8, n = 1 << m;
    for (int a = 0; a <= m; ++a) {
        std::vector<int> count(n, 0);
        for (int i = 0; i < n; ++i) {
            float u, v;
            sobol02(uint32_t(i), 7, u, v);
            const int cx = int(u * (1 << a)), cy = int(v * (1 << (m - a)));
            ++count[cx * (1 << (m - a)) + cy];
        }
        for (int c : count) ASSERT_EQ(c, 1) << "a=" << a;
    }
}

TEST(Sampling, CosineHemisphereHasCosineDensity) {
    // E[cos] under pdf cos/pi is 2/3.
    const uint32_t n = 1 << 14;
    double sum = 0;
    for (uint32_t i = 0; i < n; ++i) {
        float u, v;
        sobol02(i, 3, u, v);
        const Vec3f d = cosineHemisphere(u, v);
        ASSERT_GE(d.z, 0.0f);
        sum += d.z;
    }
    EXPECT_NEAR(sum / n, 2.0 / 3.0, 1e-3);
}

TEST(Sampling, RadicalInverseAndRngAreDeterministic) {
    EXPECT_DOUBLE_EQ(radicalInverse(2, 1), 0.5);
    EXPECT_DOUBLE_EQ(radicalInverse(3, 1), 1.0 / 3.0);
    EXPECT_DOUBLE_EQ(radicalInverse(3, 4), 1.0 / 3.0 + 1.0 / 9.0);
    Rng a(5, 9), b(5, 9), c(5, 10);
    bool differs = false;
    for (int i = 0; i < 100; ++i) {
        const uint32_t x = a.next();
        EXPECT_EQ(x, b.next());
        differs |= x != c.next();
    }
    EXPECT_TRUE(differs);
}

TEST(Sampling, UniformTriangleCoversTheTriangleEvenly) {
    // Mean of barycentrics is (1/3, 1/3).
    const uint32_t n = 1 << 12;
    double s1 = 0, s2 = 0;
    for (uint32_t i = 0; i < n; ++i) {
        float u, v, b1, b2;
        sobol02(i, 11, u, v);
        uniformTriangle(u, v, b1, b2);
        ASSERT_GE(b1, 0.0f);
        ASSERT_GE(b2, 0.0f);
        ASSERT_LE(b1 + b2, 1.0f + 1e-6f);
        s1 += b1;
        s2 += b2;
    }
    EXPECT_NEAR(s1 / n, 1.0 / 3.0, 2e-3);
    EXPECT_NEAR(s2 / n, 1.0 / 3.0, 2e-3);
}
