// Shadow edges: per-node, per-light data that keep a listed light's shadow edges sharp between
// the nodes of a `--direct occlusion` volume (issue 32, item 2; docs/shadow_visibility.md).
//
// The visibility channel (VolumeLevel::lightVisibility) holds each node's visibility of a
// light; interpolated trilinearly it spreads a hard shadow edge over a whole cell (outdoors the
// sun's edges cost 6 % RMS of irradiance at the default's node spacing). What interpolates
// well is not the visibility but the *signed distance to the edge*: linear across a planar
// edge, which trilinear interpolation reproduces exactly. So each node also keeps, per light:
//   - distance: the signed distance (in cells) from the node to the nearest point where the
//     ray towards the light's centre (a point or spot light's position, a polygon's centroid,
//     a directional light's direction) changes from blocked to free, measured in the plane
//     perpendicular to that ray (the shadow's boundary contains the rays, so that is the
//     distance to the boundary); positive on the lit side, clamped to +-kRange;
//   - width: the penumbra's width (cells) across that edge, 0 for point-like lights: the
//     light's extent along the search direction times blocker distance / (light distance -
//     blocker distance) at the edge (similar triangles, the PCSS estimate).
// A lookup (visibility below) blends the corners' distances and widths with the visibility
// channel's own weights, turns them into a ramp clamp(0.5 + d / w) (a rectangular light's
// penumbra across a straight blocker edge is linear in the offset), and adds the trilinear
// blend of each corner's residual (its stored visibility minus its own ramp), so that at the
// nodes the answer is the stored visibility exactly and partial blockers that the centre ray
// misses are kept as before. A light without edges (a non-planar mesh light, whose centre is
// inside it) stores width kNoEdge: the ramp is then 0.5 everywhere and the answer is the
// trilinear visibility.
//
// Math only (no tracer): the query module and shaders evaluate the same formula.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace vdblight::shadow_edge {

/// Floats per node and light in VolumeLevel::lightShadowEdges, in the order of Part.
constexpr int kFloatsPerLight = 6;
/// What each of them holds (docs/shadow_visibility.md, "A second edge"):
///  - kDistance, kWidth: the nearest edge, as above;
///  - kDirectionX..Z: the unit vector from the node towards that edge's nearest point, where
///    kFar is set (else 0): the strip's normal, which lets a lookup extend the node's two edges
///    as planes over its cell;
///  - kFar (cells, 0 = none): beyond the nearest edge, along the same direction, where the
///    node's own side comes back within kMaxStrip of it: the far side of a strip narrower than
///    a cell (a lit gap between two shadows, or a thin shadow), which one distance cannot hold.
enum Part { kDistance = 0, kWidth = 1, kDirectionX = 2, kDirectionY = 3, kDirectionZ = 4, kFar = 5 };
/// Distances are searched up to this many cells (a cell's corners are at most sqrt 3 from any
/// point of it; the margin keeps the zero crossing in place next to clamped corners).
constexpr float kRange = 3.0f;
/// Smallest penumbra width (cells) in the ramp: a hard edge to within 1/16 of a cell.
constexpr float kMinWidth = 1.0f / 16.0f;
/// Width stored for a light without edges (the ramp is 0.5 for every distance in range).
constexpr float kNoEdge = 1.0e4f;
/// The widest strip (cells) whose far side is stored: a wider one puts its two edges at
/// different nodes, which the nearest-edge distances already place.
constexpr float kMaxStrip = 1.0f;

/// Grid base names of light i's two channels (docs/format.md, "Direct light").
inline std::string distanceGridName(std::size_t i) { return "light_edge_distance_" + std::to_string(i); }
inline std::string widthGridName(std::size_t i) { return "light_edge_width_" + std::to_string(i); }
/// Grid name of any Part of light i (the first two as above).
inline std::string partGridName(int part, std::size_t i) {
    static const char* const names[kFloatsPerLight] = {"light_edge_distance_",    "light_edge_width_",
                                                       "light_edge_direction_x_", "light_edge_direction_y_",
                                                       "light_edge_direction_z_", "light_edge_far_"};
    return names[part] + std::to_string(i);
}

/// The visibility a straight edge gives at signed distance d (cells) across a penumbra of
/// width w (cells).
inline float ramp(float distance, float width) {
    return std::clamp(0.5f + distance / std::max(width, kMinWidth), 0.0f, 1.0f);
}

/// Visibility of one light at a point from its 8 corners: `weight` the lookup's corner weights
/// (summing to 1: trilinear, or depth-weighted and renormalised), `visibility[c]` the corner's
/// stored visibility, `distance[c]` / `width[c]` its edge. Equals visibility[c] at corner c.
inline float visibility(const float weight[8], const float visibility[8], const float distance[8], const float width[8]) {
    float d = 0.0f, w = 0.0f, residual = 0.0f;
    for (int c = 0; c < 8; ++c) {
        if (weight[c] == 0.0f) continue;
        d += weight[c] * distance[c];
        w += weight[c] * width[c];
        residual += weight[c] * (visibility[c] - ramp(distance[c], width[c]));
    }
    return std::clamp(ramp(d, w) + residual, 0.0f, 1.0f);
}

/// One node's own picture of the visibility at `offset` (cells, from the node to the point):
/// its edge (`edge`: kFloatsPerLight floats) extended as a plane across the cell, and, where
/// it has a far side, the strip between the two. At offset 0 it is ramp(distance, width).
inline float cornerModel(const float* edge, const float offset[3]) {
    const float d = edge[kDistance], w = edge[kWidth];
    const float t = edge[kDirectionX] * offset[0] + edge[kDirectionY] * offset[1] + edge[kDirectionZ] * offset[2];
    const float side = d < 0.0f ? -1.0f : 1.0f, near = std::fabs(d);
    const float beforeEdge = ramp(side * (near - t), w);  // the node's side of its nearest edge
    if (!(edge[kFar] > 0.0f)) return beforeEdge;
    const float beyondFar = ramp(side * (t - edge[kFar]), w);  // the node's side again, past the strip
    // A lit node sees a thin shadow: lit on either side of it. A shadowed node sees a lit gap:
    // lit only between its two edges.
    return side > 0.0f ? std::max(beforeEdge, beyondFar) : std::min(beforeEdge, beyondFar);
}

/// As visibility() above, from the corners' full edges (`edge[c]`: kFloatsPerLight floats) and
/// the point's offset from each corner (cells). Where no corner of weight > 0 has a far side it
/// is visibility() of the distances and widths, to the bit. Where one has (two edges cross the
/// cell, which a blended distance cannot hold: it closes the strip), each such corner adds its
/// own cornerModel, and the others together add the ramp of their own blended distance and
/// width (renormalised over them: a strip corner's near distance belongs to another edge than
/// theirs). Plus the same residuals, so that the answer at a node is its stored visibility.
inline float visibility(const float weight[8], const float visibility[8], const float* const edge[8],
                        const float offset[8][3]) {
    bool strip = false;
    for (int c = 0; c < 8; ++c) strip = strip || (weight[c] != 0.0f && edge[c][kFar] > 0.0f);
    if (!strip) {
        float d[8], w[8];
        for (int c = 0; c < 8; ++c) d[c] = edge[c][kDistance], w[c] = edge[c][kWidth];
        return shadow_edge::visibility(weight, visibility, d, w);
    }
    static constexpr float kAtNode[3] = {0.0f, 0.0f, 0.0f};
    float models = 0.0f, residual = 0.0f, others = 0.0f, d = 0.0f, w = 0.0f;
    for (int c = 0; c < 8; ++c) {
        if (weight[c] == 0.0f) continue;
        const float own = cornerModel(edge[c], kAtNode);  // ramp(distance, width)
        residual += weight[c] * (visibility[c] - own);
        if (edge[c][kFar] > 0.0f) {
            models += weight[c] * cornerModel(edge[c], offset[c]);
        } else {
            others += weight[c];
            d += weight[c] * edge[c][kDistance];
            w += weight[c] * edge[c][kWidth];
        }
    }
    if (others > 0.0f) models += others * ramp(d / others, w / others);
    return std::clamp(models + residual, 0.0f, 1.0f);
}

}  // namespace vdblight::shadow_edge
