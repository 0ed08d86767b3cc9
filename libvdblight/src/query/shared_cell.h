// The level-0 cell a lookup blended a point from, offered to the occlusion lookups so that they
// blend the lights' visibility with the same corners and weights instead of locating the point
// and computing the depth weights a second time (issue 33, part 4: that second interpolation
// was 892 of the default lookup's 3 285 instructions).
// (Internal to the query module.)
#pragma once

#include <cstddef>

#include "basis/shadow_edges.h"
#include "vdblight/layout/layout.h"
#include "vdblight/core/math.h"

namespace vdblight::query_detail {

/// Corner c (x bit 0, y bit 1, z bit 2) of a level-0 cell is node lower + bit * step along each
/// axis (step 0 along an axis with one node: both corners are that node), weighted weight[c]:
/// trilinear, or depth-weighted where the lookup weights by depth.
struct SharedCell {
    int lower[3] = {0, 0, 0};
    int step[3] = {0, 0, 0};
    float weight[8] = {};

    int i(int c) const { return lower[0] + (c & 1) * step[0]; }
    int j(int c) const { return lower[1] + ((c >> 1) & 1) * step[1]; }
    int k(int c) const { return lower[2] + (c >> 2) * step[2]; }
    std::size_t node(const GridSpec& grid, int c) const { return grid.index(i(c), j(c), k(c)); }
};

/// A lookup of a single-level volume whose irradiance is a blend of one level-0 cell's corners.
class SharesCell {
public:
    virtual ~SharesCell() = default;
    /// irradiance(x, n), the same bits, and in `cell` the corners and weights it blended.
    virtual Rgb irradianceSharingCell(const Vec3f& x, const Vec3f& n, SharedCell& cell) const = 0;
    /// False where the lookup cannot offer its cell (e.g. a streamed volume of several levels).
    virtual bool sharesCell() const { return true; }
};

/// `out[l]` = the lights' values (`lights` floats per node at corner c, `values(c)`) blended
/// with the cell's weights, each summed over the corners in order c = 0..7 from +0, as
/// OcclusionLookup::visibility sums (it skips corners of weight 0: adding their +0 to a sum
/// of non-negative products leaves its bits as they are).
template <class NodeValues>
inline void blendCell(const SharedCell& cell, std::size_t lights, NodeValues&& values, float* out) {
    const float* v[8];
    for (int c = 0; c < 8; ++c) v[c] = values(c);
    for (std::size_t l = 0; l < lights; ++l) {
        float s = 0.0f;
        for (int c = 0; c < 8; ++c) s += cell.weight[c] * v[c][l];
        out[l] = s;
    }
}

/// The offset (cells) of x from node (i, j, k) of `grid`, x clamped into the nodes' box as the
/// visibility lookups clamp it (NaN to the first node): what shadow_edge::cornerModel reads.
inline void offsetFromNode(const GridSpec& grid, const Vec3d& x, int i, int j, int k, float out[3]) {
    const int node[3] = {i, j, k}, dims[3] = {grid.nx, grid.ny, grid.nz};
    for (int a = 0; a < 3; ++a) {
        double u = (x[a] - grid.origin[a]) / grid.spacing;
        if (!(u > 0)) u = 0;
        u = std::min(u, double(dims[a] - 1));
        out[a] = float(u - node[a]);
    }
}

/// One light's visibility from its cell's corners (shadow_edge::visibility): `values[c]` and
/// `edges[c]` the corner's visibility and kFloatsPerLight edge floats of light l, `nodes[c]` its
/// (i, j, k), x the point. The offsets are computed only where a corner has a far side.
inline float edgeVisibility(const GridSpec& grid, const Vec3d& x, const float weight[8], const float values[8],
                            const float* const edges[8], const int nodes[8][3]) {
    float offset[8][3] = {};
    for (int c = 0; c < 8; ++c)
        if (weight[c] != 0.0f && edges[c][shadow_edge::kFar] > 0.0f) {
            for (int d = 0; d < 8; ++d) offsetFromNode(grid, x, nodes[d][0], nodes[d][1], nodes[d][2], offset[d]);
            break;
        }
    return shadow_edge::visibility(weight, values, edges, offset);
}

/// As blendCell, for a volume with shadow edges (shadow_edges.h): `out[l]` =
/// shadow_edge::visibility of the corners' values and edges (`edges(c)`: kFloatsPerLight floats
/// per light at corner c) with the cell's weights at x, as OcclusionLookup::visibility computes it.
template <class NodeValues, class NodeEdges>
inline void blendCellWithEdges(const SharedCell& cell, const GridSpec& grid, const Vec3d& x, std::size_t lights,
                               NodeValues&& values, NodeEdges&& edges, float* out) {
    const float* v[8];
    const float* e[8];
    int nodes[8][3];
    for (int c = 0; c < 8; ++c) {
        v[c] = values(c);
        e[c] = edges(c);
        nodes[c][0] = cell.i(c), nodes[c][1] = cell.j(c), nodes[c][2] = cell.k(c);
    }
    for (std::size_t l = 0; l < lights; ++l) {
        float vis[8];
        const float* edge[8];
        for (int c = 0; c < 8; ++c) {
            vis[c] = v[c][l];
            edge[c] = e[c] + l * shadow_edge::kFloatsPerLight;
        }
        out[l] = edgeVisibility(grid, x, cell.weight, vis, edge, nodes);
    }
}

}  // namespace vdblight::query_detail
