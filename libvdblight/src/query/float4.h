// Four floats in the lanes of one SIMD register, through GCC's and Clang's vector extensions:
// the lookups' sums that the auto-vectoriser scatters into shuffles and scalar adds (three
// colours summed over the SH terms side by side) are written with it directly. Each lane is
// its own IEEE float, operated on as the scalar code would be, so the bits are the scalar
// sums'; on a target without SIMD the compiler lowers it to four scalar operations.
// (Internal to the query module.)
#pragma once

#include <cmath>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace vdblight::query_detail {

typedef float Float4 __attribute__((vector_size(16)));
typedef int Int4 __attribute__((vector_size(16)));

/// p[0..3], from any alignment.
inline Float4 load4(const float* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// |v| in each lane, as std::fabs (the sign bit cleared).
inline Float4 abs4(Float4 v) { return Float4(Int4(v) & 0x7fffffff); }

/// The square root of each lane, correctly rounded as std::sqrt (one instruction where the
/// target has SSE: the polygon lights' four edge lengths were four scalar roots).
inline Float4 sqrt4(Float4 v) {
#if defined(__SSE__)
    return Float4(_mm_sqrt_ps(__m128(v)));
#else
    return Float4{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]), std::sqrt(v[3])};
#endif
}

}  // namespace vdblight::query_detail
