// Error-targeted point gather: each node samples in rounds until its estimated relative
// standard error of irradiance falls below a target or a maximum ray count is reached, so
// that easy regions stop early.
//
// Rounds: samples [0, minRays), then doubling the total (minRays, 2 minRays, 4 minRays, ...,
// maxRays) of the node's stratified sequence, so every round ends on a power-of-two multiple
// of the first and keeps the (0,2)-sequence stratification. A node that stops after N samples
// holds exactly the bits of the fixed-budget bake (bake.h) with N rays per node.
//
// The error estimate is of the node's mean irradiance over all normal directions,
// Ebar = (1/4) * integral of L over the sphere (luminance) = pi * Y00 * L00: the irradiance
// the SH DC term carries, which has no SH truncation error. Its standard error is taken from
// the sample variance of the per-sample estimates of Ebar (conservative for the stratified
// direction part); relative error = standard error / Ebar, where Ebar includes exactly
// evaluated punctual lights (which add no variance). A node stops when this estimate times
// a margin for the uncertainty of a variance estimated from n samples (the 10 % chi-square
// quantile: 1.33 at n = 16, 1.13 at n = 64, 1.03 at n = 1024) is at most the target at the
// end of two consecutive rounds (path-traced samples are heavy-tailed: a small round that
// happens to miss its rare large samples looks converged), so a node takes at least two
// rounds unless its variance is exactly zero. A node
// whose Ebar is zero with zero variance (dark, or a constant sky) stops at the first round.
// The reported achieved error is the plain estimate (without the margin).
//
// Determinism: a node's decisions depend only on its own samples, so the volume has the same
// bits for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/bake.h"

namespace vdblight {

struct AdaptiveOptions {
    double targetError = 0.05;  ///< relative standard error of Ebar at which a node stops
    uint32_t minRays = 64;      ///< first round (>= 2); small rounds have unreliable variances
    uint32_t maxRays = 4096;    ///< a node never takes more
    uint64_t seed = 1;
    int threads = 0;
    TransportOptions transport;
    /// Probe-to-probe bounces as GatherOptions::probePasses (bake.h); every pass samples to
    /// the target. The per-node error then excludes the earlier passes' noise.
    int probePasses = 0;
    /// As GatherOptions (bake.h): one tile's nodes, and one stage of a staged bake (tiles.h).
    const NodeMask* only = nullptr;
    int stage = -1;
    const Volume* stageInput = nullptr;
};

struct AdaptiveStats : BakeStats {
    std::vector<uint32_t> raysPerNode;    ///< gathered rays (samples) per node (a tile: per node of its window)
    uint64_t samples = 0;                 ///< sum of raysPerNode
    uint64_t nodesAtMax = 0;              ///< nodes that stopped at maxRays without meeting the rule
    // estimatedError (BakeStats): the achieved relative standard error per node.
};

/// Bakes an SH order-2 radiance volume on `grid`, node by node to the target error.
/// Throws ValueError for a target that is not in (0, 1], minRays < 2 or maxRays < minRays.
Volume bakeShGatherAdaptive(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                            const AdaptiveOptions& options, Interrupter* interrupter = nullptr,
                            AdaptiveStats* stats = nullptr);

}  // namespace vdblight
