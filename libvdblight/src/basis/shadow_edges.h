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
#include <cstddef>
#include <string>

namespace vdblight::shadow_edge {

/// Floats per node and light in VolumeLevel::lightShadowEdges: distance, width.
constexpr int kFloatsPerLight = 2;
/// Distances are searched up to this many cells (a cell's corners are at most sqrt 3 from any
/// point of it; the margin keeps the zero crossing in place next to clamped corners).
constexpr float kRange = 3.0f;
/// Smallest penumbra width (cells) in the ramp: a hard edge to within 1/16 of a cell.
constexpr float kMinWidth = 1.0f / 16.0f;
/// Width stored for a light without edges (the ramp is 0.5 for every distance in range).
constexpr float kNoEdge = 1.0e4f;

/// Grid base names of light i's two channels (docs/format.md, "Direct light").
inline std::string distanceGridName(std::size_t i) { return "light_edge_distance_" + std::to_string(i); }
inline std::string widthGridName(std::size_t i) { return "light_edge_width_" + std::to_string(i); }

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

}  // namespace vdblight::shadow_edge
