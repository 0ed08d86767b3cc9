// Pass 0's rays per node from its own error estimate (issue 32 item 1, "rays per node from the
// error estimate", here for any stored basis, sh:4 included; the error-targeted bake,
// bake_adaptive.h, stores SH order 2 only). In the preview, a room lit only through a door is
// noise: the few pass-0 paths that find the door carry all of its light, and they also feed
// the surface cache's bins (surface_bins.h) that the probe pass reads. So pass 0 runs in two
// rounds at the same total rays: every node takes kPilotShare of its budget first, then the
// rest goes to the nodes by their pooled relative error to the power kErrorPower (more to the
// dark room, less to the lit rooms, whose error the first round already shows to be low).
// Each node's samples stay one stratified sequence (node_sampler.h: the second round continues
// the first's sample numbers), so the node's values, its error estimate, its depth moments and
// the bins all take every ray. The probe pass can run the same way (GatherOptions::
// probePassByError, `--quality fast`): its own first round's errors share the rest of its rays,
// its guided directions continued. (Internal to the bake module.)
//
// Deterministic: the split is a function of the first round's errors in node order.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/layout/layout.h"

namespace vdblight::bake_detail {

/// The first round's share of pass 0's rays per node (a quarter: 16 of the preview's 64).
constexpr uint32_t kPilotShare = 4;
/// Rays go by (pooled error)^kErrorPower. Measured on the preview over seeds 1, 3, 5
/// (docs/time_to_accuracy.md, "Pass 0's rays by its error"): the power 1 (the variance-optimal
/// split for a known error) went by the first round's noisy estimates too far, 0.5 did not.
constexpr double kErrorPower = 0.5;
/// No node takes more than this many times the rays per node.
constexpr uint32_t kMostRaysFactor = 8;

/// The first round's rays per node for `raysPerNode` (at least 2, for an error estimate).
uint32_t pilotRays(uint32_t raysPerNode);

/// A pass's rays per node of `grid` (node order), `pilotRays` or more each: the rest of
/// raysPerNode x nodes shared by the root mean square of `pilotError` (the first round's relative
/// standard errors, node order) over each node's 3 x 3 x 3 neighbours, to the power
/// kErrorPower, at most kMostRaysFactor x raysPerNode per node (rounded: the total is the budget
/// within one ray per node). Nodes in `insideSolid` (empty, or a flag per node) or without a
/// finite estimate keep `pilotRays`. Even errors give every node raysPerNode.
std::vector<uint32_t> raysPerNodeByError(const GridSpec& grid, const std::vector<float>& pilotError,
                                         const std::vector<uint8_t>& insideSolid, uint32_t pilotRays,
                                         uint32_t raysPerNode);

}  // namespace vdblight::bake_detail
