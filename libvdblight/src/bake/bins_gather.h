// The bins gather at one point (bins_gather.cpp), which bakeBins calls per node and tests
// and benchmarks call as the reference of a point. Internal to the bake module (tests and
// benchmarks include it as "../libvdblight/src/bake/bins_gather.h").
#pragma once

#include <cstdint>

#include "vdblight/light/light.h"
#include "vdblight/core/math.h"

namespace vdblight {

/// Per-bin integrated radiance I_b = integral over bin b of L (RGB, 2 R^2 values) at x,
/// with the sampling of bakeBins for stream `streamIndex`.
void gatherBinRadiance(const RadianceEstimator& estimator, const Vec3f& x, int resolution, uint32_t samplesPerBin,
                       uint64_t seed, uint64_t streamIndex, Rgbd* out, RayCount& count);

}  // namespace vdblight
