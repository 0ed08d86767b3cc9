// The raw ray-throughput probe of the benchmarks (bench_foundation, bench_photons: the bake's
// rays/s against Embree's on the same scene). Internal to the trace module; benchmarks and
// tests include it as "../libvdblight/src/trace/random_rays.h".
#pragma once

#include <cstddef>
#include <cstdint>

#include "vdblight/core/math.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

/// Traces `count` random rays whose origins lie uniformly in `box` with uniformly random
/// directions, with plain single-ray rtcIntersect1 (or rtcOccluded1 if `occlusion`) on the
/// calling thread. Returns the number of hits (so the work cannot be optimised out).
/// Defined in tracer.cpp, beside the calls it measures.
std::size_t traceRandomRays(const Tracer& tracer, const Bounds& box, std::size_t count, uint64_t seed,
                            bool occlusion = false);

}  // namespace vdblight
