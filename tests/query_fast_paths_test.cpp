// The query paths rearranged for speed (issue 33, part 4) give the bits of the plain forms
// they replace: the depth weights of every SH lookup (query/depth_weights.h) against
// depth::visibility applied corner by corner, as depth_moments.h writes the formula.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "vdblight/basis/depth_moments.h"
#include "vdblight/sampling/sampling.h"
#include "../libvdblight/src/query/depth_weights.h"  // internal: query_detail::weightByDepth

namespace vdblight {
namespace {

/// The weights as the formula reads: each corner's visibility from depth::visibility at the
/// point's offset from it, plus the floor, times its trilinear weight, renormalised.
void weightCornerByCorner(float w[8], const float* const depth[8], float fx, float fy, float fz) {
    float sum = 0.0f;
    for (int c = 0; c < 8; ++c) {
        const float v = depth::visibility(depth[c], fx - float(c & 1), fy - float((c >> 1) & 1), fz - float(c >> 2));
        w[c] *= v + depth::kDepthFloor;
        sum += w[c];
    }
    const float inv = 1.0f / sum;
    for (int c = 0; c < 8; ++c) w[c] *= inv;
}

/// A fraction in [0, 1]: often exactly 0, 1 or 1/2 (a node, a cell face), else uniform.
float randomFraction(Rng& rng) {
    const double u = rng.uniform();
    if (u < 0.1) return 0.0f;
    if (u < 0.2) return 1.0f;
    if (u < 0.25) return 0.5f;
    return float(rng.uniform());
}

TEST(QueryFastPaths, DepthWeightsHaveTheBitsOfTheCornerByCornerFormula) {
    Rng rng(3301);
    float depth[8][depth::kFloatsPerNode];
    const float* corners[8];
    for (int c = 0; c < 8; ++c) corners[c] = depth[c];
    int weighted = 0;  // lookups where some corner was (half) hidden, so the weights moved
    for (int t = 0; t < 200000; ++t) {
        // Stored depth: k / 255; means anywhere in a cell (a wall at any distance, or free: 1),
        // deviations small or large.
        for (int c = 0; c < 8; ++c)
            for (int i = 0; i < depth::kFloatsPerNode; ++i) {
                const bool sigma = i >= 6;
                const double u = rng.uniform();
                depth[c][i] = depth::quantize(sigma ? (t % 2 ? 0.1 : 1.0) * u : (u < 0.3 ? 1.0 : u));
            }
        const float f[3] = {randomFraction(rng), randomFraction(rng), randomFraction(rng)};
        float fast[8], plain[8];
        for (int c = 0; c < 8; ++c)
            fast[c] = plain[c] = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
        query_detail::weightByDepth(fast, corners, f[0], f[1], f[2]);
        weightCornerByCorner(plain, corners, f[0], f[1], f[2]);
        for (int c = 0; c < 8; ++c)
            ASSERT_EQ(std::memcmp(&fast[c], &plain[c], sizeof(float)), 0)
                << "t " << t << " f " << f[0] << " " << f[1] << " " << f[2] << ": corner " << c << " " << fast[c] << " vs "
                << plain[c];
        bool hidden = false;
        for (int c = 0; c < 8; ++c)
            hidden = hidden || depth::visibility(depth[c], f[0] - float(c & 1), f[1] - float((c >> 1) & 1),
                                                 f[2] - float(c >> 2)) < 0.5f;
        weighted += hidden;
    }
    EXPECT_GT(weighted, 50000);  // the inputs did exercise the hidden case
    std::printf("[ info ] %d of 200000 lookups had a corner with visibility < 0.5\n", weighted);
}

}  // namespace
}  // namespace vdblight
