// The radical inverse of sampling.h for a base known at compile time, several digits at a
// time: for hot loops that draw Halton points (the photon pass draws five per photon).
//
// The index's base-B digits are reversed in integer arithmetic, a chunk of K digits (B^K
// at most 2048) per step from a table, and the reversed integer is divided once by B^n. For
// i < 2^42 both are exact in double, so the result is the correctly rounded radical inverse,
// where the digit-by-digit radicalInverse() accumulates rounding; the two agree to a few ulps.
//
// Internal to the library (the bake's passes include it as "sampling/radical_inverse_fast.h";
// tests as "../libvdblight/src/sampling/radical_inverse_fast.h").
#pragma once

#include <array>
#include <cstdint>

namespace vdblight {

namespace detail {
template <uint32_t Base>
struct RadicalChunks {
    static constexpr int digits() {
        int k = 1;
        uint32_t p = Base;
        while (p * Base <= 2048) p *= Base, ++k;
        return k;
    }
    static constexpr uint32_t span() {
        uint32_t p = 1;
        for (int k = 0; k < digits(); ++k) p *= Base;
        return p;
    }
    /// reversed[c] = the digits() base-B digits of c in reverse order.
    static constexpr std::array<uint16_t, span()> table() {
        std::array<uint16_t, span()> t{};
        for (uint32_t c = 0; c < span(); ++c) {
            uint32_t v = c, r = 0;
            for (int k = 0; k < digits(); ++k) r = r * Base + v % Base, v /= Base;
            t[c] = uint16_t(r);
        }
        return t;
    }
    static constexpr std::array<uint16_t, span()> reversed = table();
};
}  // namespace detail

/// Radical inverse of `i` in base `Base` (2 <= Base <= 2048), in [0, 1), for i < 2^53
/// (correctly rounded for i < 2^42).
template <uint32_t Base>
double radicalInverseFast(uint64_t i) {
    static_assert(Base >= 2 && Base <= 2048, "base out of range");
    using C = detail::RadicalChunks<Base>;
    constexpr uint64_t span = C::span();
    uint64_t reversed = 0, scale = 1;
    while (i > 0) {
        const uint64_t next = i / span;
        reversed = reversed * span + C::reversed[i - next * span];
        scale *= span;
        i = next;
    }
    const double r = double(reversed) / double(scale);
    return r < 1.0 ? r : 0x1.fffffffffffffp-1;
}

}  // namespace vdblight
