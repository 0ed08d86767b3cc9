// Pass 0's values blended into the probe pass's (volume/first_pass_blend.h, issue 32, the preview):
// by inverse variance, pass 0's counted kFirstPassVarianceFactor times, each pass's variance
// pooled over the node's neighbours. Pure data on a small grid: no bake.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "volume/first_pass_blend.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

using vdblight::blendWithFirstPass;
using vdblight::kFirstPassVarianceFactor;

constexpr int kN = 4;
constexpr std::size_t kFloats = 2;

GridSpec grid() {
    GridSpec g;
    g.nx = g.ny = g.nz = kN;
    return g;
}

struct Passes {
    std::vector<float> first, firstError, probe, probeError;
    Passes(float firstValue, float e0, float probeValue, float e1)
        : first(std::size_t(kN * kN * kN) * kFloats, firstValue), firstError(std::size_t(kN * kN * kN), e0),
          probe(std::size_t(kN * kN * kN) * kFloats, probeValue), probeError(std::size_t(kN * kN * kN), e1) {}
    void blend() { blendWithFirstPass(grid(), kFloats, first, firstError, probe, probeError); }
};

TEST(PassBlend, WeighsEachPassByItsInverseVariance) {
    // Relative errors 0.1 (pass 0) and 0.2 (probe): w = k 0.01 / (k 0.01 + 0.04).
    Passes p(1.0f, 0.1f, 2.0f, 0.2f);
    p.blend();
    const double w = kFirstPassVarianceFactor * 0.01 / (kFirstPassVarianceFactor * 0.01 + 0.04);
    for (float x : p.probe) EXPECT_NEAR(x, w * 2.0 + (1 - w) * 1.0, 1e-6);
    // The blend's error: sqrt(w^2 e1^2 + (1 - w)^2 e0^2), below either pass's.
    const double e = std::sqrt(w * w * 0.04 + (1 - w) * (1 - w) * 0.01);
    for (float x : p.probeError) EXPECT_NEAR(x, e, 1e-6);
    EXPECT_LT(e, 0.1);
}

TEST(PassBlend, AMuchNoisierFirstPassWeighsLittle) {
    Passes p(10.0f, 1.0f, 1.0f, 0.01f);  // pass 0 100 x the probe pass's error (a room behind a door)
    p.blend();
    for (float x : p.probe) EXPECT_NEAR(x, 1.0, 1e-3);
}

TEST(PassBlend, WeightsComeFromTheNeighbourhoodNotTheNodeAlone) {
    // One node's pass 0 happened to draw a tiny error; its neighbours' say pass 0 is as noisy
    // as the probe pass. Its weight follows the pool (27 nodes, one of them ~0), not its own.
    Passes p(1.0f, 0.2f, 2.0f, 0.2f);
    const std::size_t n = grid().index(1, 1, 1);
    p.firstError[n] = 1e-6f;
    p.blend();
    const double v0 = 0.04 * 26.0 / 27.0;
    const double w = kFirstPassVarianceFactor * v0 / (kFirstPassVarianceFactor * v0 + 0.04);
    EXPECT_NEAR(p.probe[n * kFloats], w * 2.0 + (1 - w) * 1.0, 1e-5);
}

TEST(PassBlend, NodesInsideSolidsAndWithoutEstimatesKeepTheProbePass) {
    Passes p(1.0f, 0.1f, 2.0f, 0.1f);
    const std::size_t inside = grid().index(2, 2, 2), unknown = grid().index(0, 0, 0);
    p.probeError[inside] = kNodeInsideSolid;
    p.firstError[unknown] = -1.0f;  // no estimate
    p.blend();
    EXPECT_EQ(p.probe[inside * kFloats], 2.0f);
    EXPECT_EQ(p.probeError[inside], kNodeInsideSolid);
    EXPECT_EQ(p.probe[unknown * kFloats], 2.0f);
}

}  // namespace
}  // namespace vdblight
