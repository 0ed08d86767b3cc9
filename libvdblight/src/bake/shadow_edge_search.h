// The search behind a node's shadow edge (shadow_edges.h), internal to the bake.
#pragma once

#include "vdblight/light/light.h"
#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;
class Tracer;

namespace bake_detail {

struct ShadowEdge {
    float distance = 0;  ///< cells, signed (+ lit), clamped to +-shadow_edge::kRange
    float width = 0;     ///< cells
    float far = 0;       ///< cells: the far side of a strip narrower than kMaxStrip beyond it, 0 = none
    Vec3f direction{0, 0, 0};  ///< unit, towards the edge's nearest point, where `far` is set; else 0
};

/// Light `light`'s edge at x for a lattice of the given spacing (see shadow_edges.h): the
/// centre ray's visibility is marched outwards in kDirections directions of the plane
/// perpendicular to it, in steps of a quarter cell, and the first change is bisected to 1/64
/// of a cell; a direction stops once it is farther than the nearest change found so far. Past
/// the nearest change, the same direction is marched on for kMaxStrip cells in eighth-cell
/// steps: where x's own side comes back (bisected likewise), that is the strip's far side.
/// Deterministic (no random numbers). A point the light cannot reach counts as lit (its
/// visibility channel holds 1 there, bake_direct.h).
ShadowEdge findShadowEdge(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, double spacing,
                          RayCount& rays);

/// Writes e into a node's kFloatsPerLight floats of VolumeLevel::lightShadowEdges (shadow_edge::Part order).
void storeShadowEdge(const ShadowEdge& e, float* out);

/// The centre ray's answer at x, as findShadowEdge starts from it: true if blocked (a point the
/// light cannot reach counts as free). Its sign is the sign of x's stored distance.
bool centreRayBlocked(const Tracer& tracer, const SceneLight& light, const Vec3f& x, RayCount& rays);

}  // namespace bake_detail
}  // namespace vdblight
