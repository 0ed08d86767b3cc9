// The point gather's projection at one point (gather.cpp), which the uniform, levels and
// back-face-invalidated gathers call per node, and tests and benchmarks call as the reference
// SH of a point. Internal to the bake module (tests and benchmarks include it as
// "../libvdblight/src/bake/project_incident.h").
#pragma once

#include <cstdint>

#include "vdblight/light/light.h"
#include "vdblight/core/math.h"

namespace vdblight {

class Tracer;

/// Projects the incident radiance at one point into nine RGB SH coefficients (double),
/// with the sampling of bakeShGather for stream `streamIndex`.
/// If `tracer` and `backFaceHits` are given, the first hit of every gathered ray is traced
/// here (same hits, same result) and the rays whose first hit is a back-face are counted.
/// If `depthOut` is given, it receives the node's depth::kFloatsPerNode depth moments from
/// the same first hits, in units of `spacing` (the node's level spacing).
void projectIncidentRadiance(const RadianceEstimator& estimator, const Vec3f& x, uint32_t rays,
                             uint64_t seed, uint64_t streamIndex, Rgbd out[9], RayCount& count,
                             const Tracer* tracer = nullptr, uint32_t* backFaceHits = nullptr,
                             float* depthOut = nullptr, double spacing = 1.0);

}  // namespace vdblight
