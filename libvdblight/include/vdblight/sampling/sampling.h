// Deterministic sampling: counter-based hashing, low-discrepancy sequences, and the
// maps from the unit square to spheres, hemispheres and triangles.
//
// Every sample of a bake is a pure function of (seed, stream index, sample number), so a
// bake gives the same bits for any thread count and any scheduling.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vdblight/core/math.h"

namespace vdblight {

/// 64-bit finaliser of SplitMix64: a good bijective mix of its input.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
constexpr uint64_t hashCombine(uint64_t a, uint64_t b) { return mix64(a ^ (mix64(b) + 0x9e3779b97f4a7c15ull)); }

/// Float in [0, 1) from the top 24 bits of a 64-bit value.
inline float toUnitFloat(uint64_t bits) { return float(bits >> 40) * (1.0f / 16777216.0f); }
inline double toUnitDouble(uint64_t bits) { return double(bits >> 11) * (1.0 / 9007199254740992.0); }

/// Small, fast, counter-seeded generator (PCG32) for the random parts of a path.
class Rng {
public:
    explicit Rng(uint64_t seed, uint64_t stream = 0)
        : state_(0), inc_((mix64(stream) << 1u) | 1u) {
        next();
        state_ += mix64(seed);
        next();
    }
    uint32_t next() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    }
    /// Uniform float in [0, 1).
    float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }

private:
    uint64_t state_, inc_;
};

/// Radical inverse in base 2 with a scramble (Owen-free XOR scramble): sample i of a
/// (0,1) sequence. Used with sobol2 below for 2-D (0,2)-sequence points.
inline float vanDerCorput(uint32_t i, uint32_t scramble) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return float((i ^ scramble) >> 8) * (1.0f / 16777216.0f);
}
/// Second dimension of the Sobol (0,2)-sequence.
inline float sobol2(uint32_t i, uint32_t scramble) {
    uint32_t r = scramble;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1) r ^= v & (0u - (i & 1u));  // no data-dependent branch
    return float(r >> 8) * (1.0f / 16777216.0f);
}

/// Point i of a randomly scrambled 2-D Sobol (0,2)-sequence: stratified in every
/// elementary interval for power-of-two counts, so sphere estimates converge ~ N^-3/4.
inline void sobol02(uint32_t i, uint64_t scrambleSeed, float& u, float& v) {
    const uint64_t s = mix64(scrambleSeed);
    u = vanDerCorput(i, uint32_t(s));
    v = sobol2(i, uint32_t(s >> 32));
}
/// sobol02 with the scramble already mixed (mix64(scrambleSeed)), for loops over i.
inline void sobol02Mixed(uint32_t i, uint64_t mixedScramble, float& u, float& v) {
    u = vanDerCorput(i, uint32_t(mixedScramble));
    v = sobol2(i, uint32_t(mixedScramble >> 32));
}

/// std::upper_bound(cdf, cdf + n, w) - cdf for n >= 1 (the same index, also for a NaN w),
/// without a data-dependent branch: a random w mispredicts half of upper_bound's branches.
inline std::size_t upperBoundIndex(const float* cdf, std::size_t n, float w) {
    const float* first = cdf;
    while (n > 1) {
        const std::size_t half = n / 2;
        first = !(w < first[half - 1]) ? first + half : first;
        n -= half;
    }
    return std::size_t(first - cdf) + (!(w < first[0]) ? 1 : 0);
}

/// Radical inverse of i in a prime base (Halton), for higher dimensions.
double radicalInverse(uint32_t base, uint64_t i);
/// radicalInverse(Base, i) with the base known at compile time: the same arithmetic (so the
/// same bits), without a 64-bit division by a variable per digit.
template <uint32_t Base>
inline double radicalInverseOf(uint64_t i) {
    constexpr double invBase = 1.0 / Base;
    double invBi = 1.0, result = 0.0;
    while (i > 0) {
        const uint64_t next = i / Base;
        const uint64_t digit = i - next * Base;
        invBi *= invBase;
        result += double(digit) * invBi;
        i = next;
    }
    return result < 1.0 ? result : 0x1.fffffffffffffp-1;
}

/// Uniform direction on the unit sphere from (u, v) in [0,1)^2 (area-preserving).
Vec3f uniformSphere(float u, float v);
/// Cosine-weighted direction around +Z (Malley's method over the concentric disk).
Vec3f cosineHemisphere(float u, float v);
/// Shirley-Chiu concentric map from [0,1)^2 to the unit disk, and its inverse.
void concentricSquareToDisk(float u, float v, float& dx, float& dy);
void concentricDiskToSquare(float dx, float dy, float& u, float& v);
/// Uniform barycentrics (b1, b2) on a triangle (b0 = 1 - b1 - b2).
void uniformTriangle(float u, float v, float& b1, float& b2);

}  // namespace vdblight
