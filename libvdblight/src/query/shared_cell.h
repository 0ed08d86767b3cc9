// The level-0 cell a lookup blended a point from, offered to the occlusion lookups so that they
// blend the lights' visibility with the same corners and weights instead of locating the point
// and computing the depth weights a second time (issue 33, part 4: that second interpolation
// was 892 of the default lookup's 3 285 instructions).
// (Internal to the query module.)
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>

#include "basis/shadow_edges.h"
#include "float4.h"
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

/// shadow_edge::visibility(weight, visibility, distance, width), bit for bit: the corners' own
/// ramps (eight divisions) and weighted terms in the lanes of two vectors, then the three sums
/// over the corners in order c = 0..7, skipping corners of weight 0, as the scalar loop does.
inline float edgeVisibility(const float weight[8], const float visibility[8], const float distance[8], const float width[8]) {
    float wd[8], ww[8], wr[8];
    for (int half = 0; half < 8; half += 4) {
        const Float4 w = load4(weight + half), d = load4(distance + half), e = load4(width + half);
        const Float4 floor = Float4{1, 1, 1, 1} * shadow_edge::kMinWidth;
        const Float4 zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
        const Float4 r = 0.5f + d / (e < floor ? floor : e);  // ramp: std::clamp(r, 0, 1) below
        const Float4 ramp = r < zero ? zero : (one < r ? one : r);
        const Float4 terms[3] = {w * d, w * e, w * (load4(visibility + half) - ramp)};
        std::memcpy(wd + half, &terms[0], sizeof(Float4));
        std::memcpy(ww + half, &terms[1], sizeof(Float4));
        std::memcpy(wr + half, &terms[2], sizeof(Float4));
    }
    float d = 0.0f, w = 0.0f, residual = 0.0f;
    for (int c = 0; c < 8; ++c) {
        if (weight[c] == 0.0f) continue;
        d += wd[c];
        w += ww[c];
        residual += wr[c];
    }
    return std::clamp(shadow_edge::ramp(d, w) + residual, 0.0f, 1.0f);
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

/// One light's visibility from its cell's corners (shadow_edge::visibility, the same bits):
/// `values[c]` and `edges[c]` the corner's visibility and kFloatsPerLight edge floats of light
/// l, `nodes[c]` its (i, j, k), x the point. Where no corner of weight > 0 has a far side (most
/// cells) the corners' ramps run in vector lanes (edgeVisibility above); the offsets are
/// computed only where one has.
inline float edgeVisibility(const GridSpec& grid, const Vec3d& x, const float weight[8], const float values[8],
                            const float* const edges[8], const int nodes[8][3]) {
    bool strip = false;
    for (int c = 0; c < 8; ++c) strip = strip || (weight[c] != 0.0f && edges[c][shadow_edge::kFar] > 0.0f);
    if (!strip) {
        float distance[8], width[8];
        for (int c = 0; c < 8; ++c) {
            distance[c] = edges[c][shadow_edge::kDistance];
            width[c] = edges[c][shadow_edge::kWidth];
        }
        return edgeVisibility(weight, values, distance, width);
    }
    float offset[8][3] = {};
    for (int d = 0; d < 8; ++d) offsetFromNode(grid, x, nodes[d][0], nodes[d][1], nodes[d][2], offset[d]);
    return shadow_edge::visibility(weight, values, edges, offset);
}

/// As blendCell, for a volume with shadow edges (shadow_edges.h): `out[l]` =
/// shadow_edge::visibility of the corners' values and edges (`edges(c)`: kFloatsPerLight floats
/// per light at corner c) with the cell's weights at x, as OcclusionLookup::visibility computes it
/// (edgeVisibility, the same bits).
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
