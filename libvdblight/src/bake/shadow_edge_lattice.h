// The shadow edges (basis/shadow_edges.h) of a uniform lattice's nodes, searched only where a
// lookup can tell the search's answer apart from "no edge in range" (internal to the bake).
//
// findShadowEdge traces up to 12 x 12 + 4 rays per node and light; most nodes are far from
// any edge, and there its answer (distance +-kRange, width 0) changes nothing a lookup returns:
//  - A hard light (point, spot, directional: width 0) has ramp(d, 0) = 0 or 1 at every node
//    (|d| >= kMinWidth / 2 by construction), so a corner's residual depends only on its sign,
//    and the blended ramp ramp(sum wt d, 0) only on the signs, unless the corners of the cell
//    disagree. A node whose 26 lattice neighbours all share its centre ray's answer is a corner
//    of no such cell: its exact distance is never read. Only the others are searched.
//  - A polygon light's ramps have widths: its nodes are also searched where the node or a
//    neighbour sees the light partly (visibility strictly between 0 and 1) or sees a different
//    fraction (a penumbra nearby). Elsewhere the skipped answer changes a lookup by a little
//    (tests/shadow_edges_test.cpp measures it), not by the edge's place.
// Every answer depends only on the node's position (its neighbours' centre rays, their
// visibility channels' own streams): the same bits on any thread count and for any tiling.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "vdblight/core/interrupter.h"
#include "vdblight/light/light.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

struct Scene;
class Tracer;
struct VolumeLevel;

namespace bake_detail {

/// How the edges of a bake were found (for the bake's metadata and the benchmark).
struct EdgeLatticeRun {
    RayCount rays;
    uint64_t searched = 0;  ///< (node, light) pairs given findShadowEdge
    uint64_t skipped = 0;   ///< pairs stored as "no edge in range" without a search
    double seconds = 0;
};

/// True if node (i, j, k)'s search can be skipped: `blocked(i, j, k)` the centre ray's answer
/// at a node, `visibility(i, j, k)` its visibility channel (read only when `soft`, a polygon
/// light's); the 3 x 3 x 3 block around the node, clipped to the grid, decides.
bool edgeSearchSkippable(const GridSpec& grid, int i, int j, int k, bool soft,
                         const std::function<bool(int, int, int)>& blocked,
                         const std::function<float(int, int, int)>& visibility);

/// Fills level.lightShadowEdges (allocated by the caller, kFloatsPerLight per held node and
/// light) for `nodes` (linear indices, ascending; empty = every node): findShadowEdge where the search
/// is not skippable, (+-kRange, 0) elsewhere. `visibilityAt(node, light, rays)` returns a node's
/// visibility channel (read for polygon lights only, also at neighbours outside `nodes`).
EdgeLatticeRun bakeShadowEdgesOnLattice(const Scene& scene, const Tracer& tracer, const std::vector<SceneLight>& lights,
                                        VolumeLevel& level, const std::vector<std::size_t>& nodes,
                                        const std::function<float(std::size_t, std::size_t, RayCount&)>& visibilityAt, int threads,
                                        Interrupter* interrupter);

}  // namespace bake_detail
}  // namespace vdblight
