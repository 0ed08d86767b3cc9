// The metadata summaries of per-node statistics that the point gathers write (bake.h,
// bake_adaptive.h) and that a merge of tiles (tiles.h) recomputes from the tiles' per-node
// values: one function for both, so that the merged file has the single bake's bytes.
#pragma once

#include <vector>

#include "vdblight/layout.h"
#include "vdblight/volume.h"

namespace vdblight {

/// q-quantile (0..1, nearest rank) of `values`; 0 if there are none.
double errorQuantile(const std::vector<float>& values, double q);

/// The per-node error summary (one value per node of `grid`, node order): error_estimate
/// (what it is), estimated_error_p50 / _p95 / _max and estimated_error_worst_nodes
/// ("i,j,k:error;..." for the five worst nodes, ties by node index).
void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid);

/// The sample summary of an error-targeted bake from its metadata samples_total, nodes and
/// max_rays: rays_per_node_mean and samples_saved_vs_max.
void addSampleSummary(Metadata& m);

}  // namespace vdblight
