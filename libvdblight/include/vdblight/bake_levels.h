// The point-gather pass on a multi-level layout (layout_levels.h).
//
// Every node that is not a seam node is baked exactly like a uniform node
// (projectIncidentRadiance); the sample stream of node n of level l is (l << 56) | n, so
// level 0 of a bilevel volume has the same bits as the uniform volume on the same grid.
// Seam nodes are then set from the coarser level (applySeamConstraints), coarse to fine.
#pragma once

#include "vdblight/bake.h"
#include "vdblight/layout_levels.h"

namespace vdblight {

struct LevelsBakeStats : BakeStats {
    uint64_t seamNodes = 0;  ///< nodes set from the coarser level instead of baked
};

/// Bakes an SH order-2 radiance volume on `layout`. Same determinism, cancelling and
/// metadata as bakeShGather, plus layout, refine, per-level node counts and seam nodes.
Volume bakeShGatherLevels(const Scene& scene, const Tracer& tracer, const LevelLayout& layout,
                          const GatherOptions& options, Interrupter* interrupter = nullptr,
                          LevelsBakeStats* stats = nullptr);

}  // namespace vdblight
