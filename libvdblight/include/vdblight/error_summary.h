// The metadata summaries of per-node statistics that the point gathers write (bake.h,
// bake_adaptive.h) and that a merge of tiles (tiles.h) recomputes from the tiles' per-node
// values: one function for both, so that the merged file has the single bake's bytes.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/volume.h"

namespace vdblight {

/// The per-node error value of a node that no lookup in free space reads: a node inside a
/// solid (most of its first hits are back faces, insideSolidByBackFaces) of a volume whose
/// depth weights (depth_moments.h) keep it out of every lookup from open space. Its noise
/// is large (almost no light reaches it) and says nothing about what a user sees, so the
/// summaries leave it out and count it instead (issue 29). Negative: no real error is.
constexpr float kNodeInsideSolid = -1.0f;

/// True if more than half of a node's `rays` first hits were back faces: the node lies inside
/// closed geometry (the test of prt.h's insideSolid and of the domain of interest, applied to
/// the gather's own first hits).
inline bool insideSolidByBackFaces(uint32_t backFaceHits, uint32_t rays) {
    return 2 * uint64_t(backFaceHits) > uint64_t(rays);
}

/// q-quantile (0..1, nearest rank) of the values that are not kNodeInsideSolid (any negative);
/// 0 if there are none.
double errorQuantile(const std::vector<float>& values, double q);

/// The per-node error summary (one value per node of `grid`, node order) over the nodes that
/// free-space lookups read: error_estimate (what it is), estimated_error_p50 / _p95 / _max
/// and estimated_error_worst_nodes ("i,j,k:error;..." for the five worst nodes, ties by node
/// index); nodes_inside_solids counts the kNodeInsideSolid nodes left out (written only if
/// there are any).
void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid);

/// How many of `values` are kNodeInsideSolid (negative).
std::size_t nodesInsideSolids(const std::vector<float>& values);

/// The sample summary of an error-targeted bake from its metadata samples_total, nodes and
/// max_rays: rays_per_node_mean and samples_saved_vs_max.
void addSampleSummary(Metadata& m);

}  // namespace vdblight
