// The lights of a scene as a volume lists them (direct_light.h), each with what it is made of
// in the scene, and their visibility from a point by shadow rays (issue 15, `bake --direct`).
//
// Emissive triangles are grouped into polygon lights: triangles with one material that lie in
// one plane, face the same way and share edges form one light (the two triangles of a quad
// luminaire, the emitting face of a closed fixture box, a fan of a disk). Its boundary loops
// are the edges used by one triangle only; where they do not chain into closed loops (a
// T-junction), the light keeps its triangles as loops, which Lambert's formula sums exactly.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vdblight/direct_light.h"
#include "vdblight/light.h"

namespace vdblight {

struct Scene;
class Tracer;

/// A light of the scene and its parts.
struct SceneLight {
    DirectLight light;                ///< in the scene's local frame
    std::vector<uint32_t> triangles;  ///< polygon: its emissive triangles (ascending)
    std::vector<double> triangleCdf;  ///< polygon: cumulative area of `triangles`, last = 1
    /// Point / spot / directional: the index in the order points, spots, directionals
    /// (LightSample::source of the estimator's punctual samples); -1 for polygons.
    int32_t punctual = -1;
    /// Polygon / mesh not made of scene triangles (freeLight): its loops split into triangles,
    /// three vertices each, with the sign of each (-1: a triangle that cancels area, inside a
    /// hole or a concave corner). triangleCdf is then over these triangles' absolute areas.
    std::vector<Vec3f> ownTriangles;
    std::vector<float> ownSign;
    /// Polygon / mesh: the total (absolute) area the sample points are drawn over.
    double sampledArea = 0;
};

/// A light that is not part of the scene's triangles (one placed by a user, e.g. to relight a
/// PRT file): point, spot and directional lights as they are; a polygon's or mesh's loops
/// split into a fan of triangles each, whose signed areas sum to the light's region (holes and
/// non-convex loops included), so that lightVisibility and samplePolygonLight draw points on
/// the light itself. Its shadow rays stop short of the light as for a scene light.
SceneLight freeLight(const DirectLight& light);

/// A point on a polygon or mesh light for the unit-square point (u, v), as lightVisibility
/// draws them: u picks a triangle by area and is rescaled to [0, 1) inside it (a stratified
/// set of (u, v) stays stratified over the whole light), then (u, v) is a uniform point of
/// that triangle. `normal`: the light's front normal there; `sign`: -1 on a triangle of a free
/// light that cancels area, else 1. `scene` is read only for a light made of scene triangles.
struct PolygonLightPoint {
    Vec3f position;
    Vec3f normal;
    float sign = 1;
};
PolygonLightPoint samplePolygonLight(const SceneLight& light, const Scene* scene, float u, float v);

/// Every light of the scene, in a fixed order: polygons (by smallest triangle index), then
/// point, spot and directional lights in scene order. The sky is not a light here: it stays
/// in the volume's basis in every mode.
std::vector<SceneLight> sceneLights(const Scene& scene);

/// Fraction of `light`'s contribution at x that is not blocked: 0 or 1 for point, spot and
/// directional lights (one shadow ray); for a polygon the weighted mean over `samples`
/// stratified points on its area, each weighted by its share of the light's solid angle
/// (|cos at the light| / d^2) and, if `normal` is given, by the receiver's cosine. This is
/// the ratio of shadowed to unshadowed irradiance that a lookup multiplies exactIrradiance by.
/// The points depend only on `stream` (determinism). Returns 1 when no sample carries weight.
double lightVisibility(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, uint32_t samples,
                       uint64_t stream, RayCount& rays, const Vec3f* normal = nullptr);

/// Direct irradiance at x for the unit normal n from one light with its shadows:
/// exactIrradiance times lightVisibility with the receiver's cosine (`samples` shadow rays for
/// a polygon light, one for a point, spot or directional light; none where the light does not
/// reach the normal's side). `onSurface`: x lies on a surface facing n, so the shadow rays
/// start just off it (offsetRayOrigin) rather than at x. x and n in the scene's local frame.
Rgb shadowedIrradiance(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, const Vec3f& n,
                       uint32_t samples, uint64_t stream, RayCount& rays, bool onSurface = false);

/// Direct irradiance at x for the unit normal n from `lights` with their shadows, as a run
/// time adds it to a `--direct runtime` volume: shadowedIrradiance summed over the lights
/// (light i with stream hashCombine(stream, i)). x and n in the scene's local frame.
Rgb runtimeDirectIrradiance(const Scene& scene, const Tracer& tracer, const std::vector<SceneLight>& lights,
                            const Vec3f& x, const Vec3f& n, uint32_t samples, uint64_t stream, RayCount& rays);

/// The filter that leaves the direct light of `lights` at the receiver out of a bake
/// (TransportOptions::skipAtReceiver): their triangles and punctual indices.
std::shared_ptr<const ReceiverDirectFilter> receiverFilter(const Scene& scene, const std::vector<SceneLight>& lights);

}  // namespace vdblight
