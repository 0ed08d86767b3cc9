// The hot-loop forms of the sampling functions (sampling.h) give exactly the bits of the
// plain ones: radicalInverseOf<B> == radicalInverse(B, .), sobol02Mixed == sobol02, the
// branch-free sobol2 == the branching original, upperBoundIndex == std::upper_bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "vdblight/sampling/sampling.h"

using namespace vdblight;

namespace {
template <typename T>
bool sameBits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}
float sobol2Branching(uint32_t i, uint32_t scramble) {  // the original form
    uint32_t r = scramble;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
        if (i & 1u) r ^= v;
    return float(r >> 8) * (1.0f / 16777216.0f);
}
}  // namespace

TEST(SamplingFast, RadicalInverseOfEqualsRadicalInverse) {
    Rng rng(11);
    for (uint64_t k = 0; k < 200000; ++k) {
        const uint64_t i = k < 100000 ? k : (uint64_t(rng.next()) << 20) ^ rng.next();
        ASSERT_TRUE(sameBits(radicalInverseOf<2>(i), radicalInverse(2, i))) << i;
        ASSERT_TRUE(sameBits(radicalInverseOf<3>(i), radicalInverse(3, i))) << i;
        ASSERT_TRUE(sameBits(radicalInverseOf<5>(i), radicalInverse(5, i))) << i;
    }
}

TEST(SamplingFast, Sobol02MixedAndBranchFreeSobol2EqualTheOriginals) {
    for (uint64_t seed : {0ull, 1ull, 0x123456789abcdefull}) {
        const uint64_t mixed = mix64(seed);
        for (uint32_t i = 0; i < 70000; ++i) {
            float u, v, u2, v2;
            sobol02(i, seed, u, v);
            sobol02Mixed(i, mixed, u2, v2);
            ASSERT_TRUE(sameBits(u, u2) && sameBits(v, v2)) << i;
            ASSERT_TRUE(sameBits(v, sobol2Branching(i, uint32_t(mixed >> 32)))) << i;
        }
    }
    EXPECT_TRUE(sameBits(sobol2(0xffffffffu, 77u), sobol2Branching(0xffffffffu, 77u)));
}

TEST(SamplingFast, UpperBoundIndexEqualsStdUpperBound) {
    Rng rng(5);
    for (std::size_t n : {1, 2, 3, 4, 5, 7, 8, 16, 17, 100, 1000}) {
        std::vector<float> cdf(n);
        for (int trial = 0; trial < 20; ++trial) {
            float run = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (trial % 3 != 0 || rng.uniform() < 0.7f) run += rng.uniform();  // repeats too
                cdf[i] = run;
            }
            std::vector<float> ws = {0.0f, -1.0f, run, run * 2, std::numeric_limits<float>::quiet_NaN()};
            for (std::size_t i = 0; i < n; ++i) ws.push_back(cdf[i]);  // ties
            for (int k = 0; k < 200; ++k) ws.push_back(run * rng.uniform());
            for (float w : ws) {
                const std::size_t expected = std::size_t(std::upper_bound(cdf.begin(), cdf.end(), w) - cdf.begin());
                ASSERT_EQ(upperBoundIndex(cdf.data(), n, w), expected) << "n " << n << " w " << w;
            }
        }
    }
}
