// The lookups' hot loops compiled a second time for AVX2 and picked at run time (issue 33,
// part 4): the blend of a node's floats over the eight corners and the depth weights are
// independent lanes, so eight of them per instruction instead of four halve their count.
// Only AVX2, not FMA: every multiply and add stays a separate IEEE operation in the same order
// (GCC contracts a * b + c into an FMA only where FMA is enabled), so both versions give the
// same bits, and a query answers alike on any x86-64 CPU. Not under the sanitizers (their
// instrumentation and the run-time dispatch are kept apart), nor on other architectures.
// (Internal to the query module.)
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define VDBLIGHT_WIDE_VECTORS 1
#define VDBLIGHT_AVX2 __attribute__((target("avx2")))
#else
#define VDBLIGHT_WIDE_VECTORS 0
#define VDBLIGHT_AVX2
#endif
#define VDBLIGHT_ALWAYS_INLINE inline __attribute__((always_inline))

namespace vdblight::query_detail {

/// v, kept in a general-purpose register: the eight corners' node indices and record addresses
/// are pinned with it, because the AVX2 build otherwise vectorised that index arithmetic
/// (64-bit products in vector lanes) and then extracted every lane before its load.
template <class T>
VDBLIGHT_ALWAYS_INLINE T inScalarRegister(T v) {
    asm("" : "+r"(v));
    return v;
}

/// True if the lookups may run their AVX2 versions (the CPU has AVX2, and they were compiled).
inline bool cpuHasAvx2() {
#if VDBLIGHT_WIDE_VECTORS
    static const bool yes = __builtin_cpu_supports("avx2");
    return yes;
#else
    return false;
#endif
}

}  // namespace vdblight::query_detail
