// Procedural scene pieces for tests and benchmarks: shapes whose lighting has a closed form
// (disks, spheres, closed boxes) and large meshes for throughput measurements. Part of the
// test scenes (tests/support, vdblight_test_scenes), not of the installed library.
#pragma once

#include <cstdint>

#include "vdblight/scene/scene.h"

namespace vdblight {

/// Appends a geodesic sphere (icosahedron subdivided `subdivisions` times: 20 * 4^s
/// triangles) with front faces pointing outwards. Returns the radius of the sphere with
/// the same volume, the best single radius for comparing with closed forms.
double appendIcosphere(Scene& scene, const Vec3f& centre, float radius, int subdivisions, uint32_t materialId);

/// Appends the six faces of the box [lo, hi] (two triangles each), front faces pointing
/// into the box if `inward`, out of it otherwise.
void appendBox(Scene& scene, const Vec3f& lo, const Vec3f& hi, bool inward, uint32_t materialId);

/// Appends a flat disk (triangle fan of `segments` triangles) of radius R in the plane
/// through `centre` with normal +z, front face +z. Returns the radius of the circle with
/// the polygon's area.
double appendDisk(Scene& scene, const Vec3f& centre, float radius, int segments, uint32_t materialId);

}  // namespace vdblight
