// Filtering across nodes (issue 32): a small smoothing kernel over a uniform level's node
// values, with the lookups' own depth weights, to trade the noise of a bake with few rays per
// node for a little blur. In the volume module: the merge of tiles runs it too (tiles.h). `--quality preview` uses it (docs/time_to_accuracy.md).
//
// One pass replaces each node's values by the weighted mean over its 3x3x3 neighbourhood:
// weight = binomial kernel (1/4, 1/2, 1/4 per axis) x visibility of the node from the
// neighbour x visibility of the neighbour from the node, both from the depth moments
// (depth::visibility, the test a lookup weights corners with), so that a wall between two
// nodes keeps them apart. Without depth moments the visibility is 1 (plain smoothing).
// Neighbours outside the grid drop out and the weights are renormalised. The kernel is
// symmetric: a value that varies linearly between visible nodes is kept in the interior.
//
// Every value of a node is filtered with the same weights (the filter is linear, so any basis
// whose values are linear in the radiance: SH of any order, bins, irradiance vectors).
// Deterministic: each output depends only on the input values in a fixed order.
#pragma once

#include <vector>

#include "vdblight/volume/volume.h"

namespace vdblight {

/// Filters the values (VolumeLevel::data) of every level of `volume`, `passes` times (0:
/// nothing). Throws ValueError for negative passes, a sparse level (bilevel / adaptive
/// layouts: not supported) or a tile's window of the nodes (the kernel crosses tile borders:
/// a tiled bake leaves the filter to mergeTiles, which runs it on the merged nodes). `relativeError` (optional, one-level volumes): each node's relative standard
/// error of its mean irradiance (BakeStats::estimatedError; negative = inside a solid, left
/// out); with it a neighbour's weight also falls with the two nodes' difference in mean
/// luminance over their noise (exp(-d^2 / 2 (s_n^2 + s_m^2))): a bilateral filter that smooths
/// noise and keeps differences the noise does not explain. `threads` as core::threadCount reads
/// it (0: every core); the same bits on any.
void filterNodes(Volume& volume, int passes, const std::vector<float>* relativeError = nullptr, int threads = 0);

}  // namespace vdblight
