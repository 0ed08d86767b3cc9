// The probe pass's values blended with pass 0's (issue 32, the preview): pass 0 traces full
// paths from every node and its values are an unbiased estimate of the same light, which the
// probe pass then replaces. Where both are about as noisy (a lit room, the office) their mean
// halves the variance for no rays; where pass 0 is much noisier (a room lit through a door)
// it weighs little. In the volume module: a tiled bake's merge blends too (tiles.h), since the
// pooled variances cross tile borders. (Internal to the library.)
//
// Weights by inverse variance: each pass's relative variance (the square of its nodes'
// relative standard error, node_sampler.h) averaged over the node's 3 x 3 x 3 neighbours, so
// that a node's weight does not follow its own noisy sample (which would bias the blend toward
// the darker estimate). Deterministic: per node, in a fixed order.
#pragma once

#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"

namespace vdblight {

/// Pass 0's pooled variance counts this many times: its paths' heavy tails (a path that finds
/// the door) make its sample variance an underestimate where it matters. Measured on the
/// preview, RMS over the mean of seeds 1, 3 and 5 (docs/time_to_accuracy.md): without the blend
/// office 5.5 %, two rooms 8.7 %; factor 1: 5.0 % and 8.9 %; factor 2: 5.2 % and 8.7 %.
constexpr double kFirstPassVarianceFactor = 2.0;

/// `values` (the probe pass's, `floatsPerNode` per node of `grid`, node order) becomes
/// w * values + (1 - w) * firstValues per node, w = k v0 / (k v0 + v1) from the pooled relative
/// variances of `firstError` (v0) and `error` (v1), k = kFirstPassVarianceFactor; `error`
/// becomes the blend's. Nodes with a
/// negative error (inside a solid) or without a finite estimate keep the probe pass's values.
void blendWithFirstPass(const GridSpec& grid, std::size_t floatsPerNode, const std::vector<float>& firstValues,
                        const std::vector<float>& firstError, std::vector<float>& values, std::vector<float>& error);

}  // namespace vdblight
