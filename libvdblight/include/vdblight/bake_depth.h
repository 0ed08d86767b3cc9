// The depth-moment pass: per node of any volume (every layout, basis and bake method), the
// depth moments of depth_moments.h from first-hit rays cast from the node itself.
//
// The rays are the first rays of the point gather: node n of level l uses the stream
// (l << 56) | linear index and the same scrambled Sobol directions, so for a point gather with
// as many rays (and the same seed) these are exactly the gather's first hits. They are traced
// again here (first hits only, in 16-ray packets), which keeps the pass one small function
// that every pass, including the anti-aliased and photon ones whose rays do not start at the
// nodes, can call after baking.
//
// Deterministic: node values depend only on (seed, stream, ray count) and are summed in ray
// order, so the result has the same bits for any thread count.
#pragma once

#include <cstdint>

#include "vdblight/light.h"
#include "vdblight/tiles.h"
#include "vdblight/volume.h"

namespace vdblight {

class Tracer;
class Interrupter;

struct DepthOptions {
    uint32_t raysPerNode = 256;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    /// Bake only these nodes (one tile of a bake, tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
};

struct DepthStats {
    uint64_t rays = 0;
    double seconds = 0;
};

/// One node's depth moments (out: depth::kFloatsPerNode floats) from `rays` first-hit rays
/// at x with the gather's directions for (seed, stream); `spacing` is the node's level spacing.
void nodeDepthMoments(const Tracer& tracer, const Vec3f& x, double spacing, uint64_t seed, uint64_t stream,
                      uint32_t rays, float* out, RayCount& count);

/// Fills VolumeLevel::depth of every level of `volume` and records the pass in its metadata
/// (depth_moments, depth_rays_per_node). Throws ValueError for 0 rays, Cancelled if asked.
void bakeDepthMoments(const Tracer& tracer, Volume& volume, const DepthOptions& options,
                      Interrupter* interrupter = nullptr, DepthStats* stats = nullptr);

}  // namespace vdblight
