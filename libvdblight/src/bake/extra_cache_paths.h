// More paths for the surface probe cache where pass 0 is noisiest (issue 32, the preview). In a
// room lit only through a door, the probe pass reads the room's walls from the surface bins
// (surface_bins.h), whose samples are pass 0's paths from the room's own nodes: the few that find
// the door carry all of its light, so the bins are noisy, and the probe pass passes that noise
// on (moving the probe pass's own rays there did not lower it; docs/time_to_accuracy.md, "Nodes
// rather than rays"). So after pass 0, the nodes whose pooled relative error is above
// kNoisyFactor x the median trace kExtraCachePaths more full paths each, with a seed of their
// own, whose first-vertex samples go to the bins only (the nodes' values stay pass 0's): the
// bins stay unbiased, and a scene without such a region (the office, the Cornell box) traces
// almost none. (Internal to the bake module.)
//
// Deterministic: the choice is a function of pass 0's errors in node order, and the bins' sums
// are integers.
#pragma once

#include <cstdint>
#include <vector>

#include "parallel_nodes.h"
#include "surface_bins.h"
#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"

namespace vdblight::bake_detail {

/// Paths per noisy node unless a bake asks otherwise (GatherOptions::extraCachePathsPerNode).
/// Measured on the preview (~8 192 nodes, 64 rays; docs/time_to_accuracy.md), two rooms over
/// seeds 1, 3, 5: 7.0 % without, 5.6 % with 128 paths, 5.2 % with 256.
constexpr uint32_t kExtraCachePaths = 256;
/// `--quality fast`'s (twice the preview's nodes, so about the preview's paths in all): two
/// rooms 3.09 / 3.50 / 3.32 % without, 3.10 / 3.21 / 3.19 % with them at seeds 1, 3, 5, for 7 %
/// more of its time (64: 3.40 / 3.16 % at seeds 3, 5; 256: 26 % of the default's time).
constexpr uint32_t kFastExtraCachePaths = 128;
/// A node is noisy when its pooled error is above this many times the median: 2 chose 41 % of
/// the two rooms' nodes (the unlit room's) and 0-1 % of the other scenes'.
constexpr double kNoisyFactor = 2.0;

/// The extra paths per node of `grid` (node order): `perNode` where the root mean square
/// of `firstError` (pass 0's relative standard errors, node order) over the node's 3 x 3 x 3
/// neighbours is above kNoisyFactor x the median of that over the nodes, 0 elsewhere and at
/// nodes in `insideSolid` (empty, or a flag per node) or without a finite estimate.
std::vector<uint32_t> extraCachePaths(const GridSpec& grid, const std::vector<float>& firstError,
                                      const std::vector<uint8_t>& insideSolid, uint32_t perNode = kExtraCachePaths);

/// Traces paths[n] full paths from each node n of `grid` (pass 0's sampling, the seed
/// hashCombine(seed, kExtraCachePathsStream)) into `bins` only; `estimator` must have no surface
/// cache. Returns the rays and time.
ParallelRun traceExtraCachePaths(const RadianceEstimator& estimator, const GridSpec& grid, uint64_t seed,
                                 const std::vector<uint32_t>& paths, SurfaceBins& bins, int threads,
                                 Interrupter* interrupter);

/// The extra paths' stream: not a probe pass's (those hash the pass index, 1..).
constexpr uint64_t kExtraCachePathsStream = 0xcac4e;

}  // namespace vdblight::bake_detail
