// Direct light kept out of the volume's basis (issue 15, `bake --direct`).
//
// SH order 2 cannot hold the clamped cosine of a luminaire a metre away: in the office scene
// that costs 6.9 % RMS of irradiance while the indirect light costs 0.7 %. Engines therefore
// bake only indirect light into probes and add the direct light of their important lights at
// run time (Unreal's stationary lights, Unity's mixed lights with per-probe occlusion). A
// volume says which of three modes it was baked in:
//  - baked:     everything in the basis (the historical behaviour);
//  - runtime:   the basis holds indirect light only; the file lists every light of the scene
//               and the run time adds their direct light with its own shadows;
//  - occlusion: the basis holds indirect light plus the direct light of lights outside a
//               chosen few; each of the chosen few is listed and has a per-node visibility
//               channel (0..1), and a lookup adds exactIrradiance(light, x, n) times the
//               trilinearly interpolated visibility.
//
// This header holds the light description that travels in the file and the exact,
// unshadowed irradiance of each kind: closed forms for point, spot and directional lights,
// Lambert's contour formula clipped to the receiver's hemisphere for planar polygons.
// It depends on nothing but core/math.h, so that the query module can use it without the tracer.
#pragma once

#include <string>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

enum class DirectMode { Baked, Runtime, Occlusion };

/// "baked" / "runtime" / "occlusion".
const char* directModeName(DirectMode mode);
/// Parses a mode name; throws ValueError naming the accepted values.
DirectMode parseDirectMode(const std::string& name);

/// One light as stored in a volume's light list (docs/format.md, "Direct light").
/// Positions are in the volume's frame (world positions in a written file).
struct DirectLight {
    /// Polygon: one planar region (loops around `normal`). Mesh: connected emissive triangles
    /// of one material that are not coplanar (a bulb, a box emitting on all faces): each loop
    /// is one triangle, counter-clockwise around its own front normal.
    enum class Kind { Point, Spot, Directional, Polygon, Mesh };
    Kind kind = Kind::Point;
    Vec3d position;            ///< point, spot
    Vec3d direction{0, -1, 0}; ///< spot: unit axis it points along; directional: unit travel direction
    /// point / spot: intensity W/sr (spot: on the axis); directional: irradiance W/m^2 facing
    /// the light; polygon: emitted radiance W/(m^2 sr).
    Rgb value;
    double innerCone = 0, outerCone = kPi / 4;  ///< spot half-angles (glTF convention)
    bool twoSided = false;     ///< polygon: emits from both faces
    Vec3d normal{0, 0, 1};     ///< polygon: unit front normal
    /// Polygon: boundary loops, each counter-clockwise around `normal` (holes clockwise).
    /// The region is their signed sum, so a light may also be a set of triangles.
    std::vector<std::vector<Vec3d>> loops;

    /// Moves the light by `offset` (positions and polygon vertices; directions unchanged).
    void translate(const Vec3d& offset);
    /// Total polygon / mesh area (signed sum of the loops' areas; 0 for other kinds).
    double area() const;
};

/// A one-sided square panel: centre `centre`, emitting on the side of `normal` (any length
/// but zero), side `size`, as a Lambertian emitter of `intensity` W/sr along its normal (its
/// radiance is intensity / size^2, so the intensity at angle a off the normal is intensity *
/// cos a). One loop, counter-clockwise around the normal, along the tangents of
/// orthonormalBasis(normal). Throws ValueError for a zero normal or a size that is not positive.
DirectLight squareLight(const Vec3d& centre, const Vec3d& normal, double size, const Rgb& intensity);

/// The glTF spot falloff the radiance estimator uses: squared linear ramp of the cosine
/// between the outer and the inner cone; `fromLight` is the unit direction light -> receiver.
double spotFalloff(const DirectLight& spot, const Vec3d& fromLight);

/// Newell's vector of a loop of vertices: twice its vector area (its normal times twice its
/// area). A mesh light's triangle faces the side it points to.
Vec3d newellVector(const std::vector<Vec3d>& loop);

/// Which face of a light's plane (front normal `normal`, through p) x sees: +1 the front, -1 the
/// back of a two-sided light, 0 none. Decides which loops exactIrradiance counts and with what sign.
double facingSide(const Vec3d& normal, const Vec3d& p, bool twoSided, const Vec3d& x);

/// Exact irradiance (W/m^2) at x on a surface with unit normal n from `light`, without
/// shadows: I cos / d^2 for point and spot (times the falloff), E cos for directional,
/// and for a polygon L/2 * sum over its edges of theta_i (n . gamma_i) after clipping the
/// polygon to the hemisphere around n (Lambert 1760; Arvo 1995, eq. 1). A mesh is the sum of
/// its triangles facing x (exact for a convex emitter; a non-convex one's self-shadowing is
/// left to the visibility).
Rgb exactIrradiance(const DirectLight& light, const Vec3d& x, const Vec3d& n);

/// Mean of exactIrradiance over all normals at x: (1/4) * integral of the light's radiance
/// over the sphere of directions (I / (4 d^2), E / 4, L * solid angle / 4). What the light
/// adds to a volume's mean irradiance at x (the importance of a light, shadows aside).
Rgb meanIrradiance(const DirectLight& light, const Vec3d& x);

/// The lights of a volume (empty in baked mode). In occlusion mode light i has visibility
/// channel i (VolumeLevel::lightVisibility).
struct DirectLightSet {
    DirectMode mode = DirectMode::Baked;
    std::vector<DirectLight> lights;

    bool hasVisibility() const { return mode == DirectMode::Occlusion && !lights.empty(); }
};

/// One light as the one-line text stored in the file's metadata and the manifest
/// (docs/format.md), and back. parseDirectLight throws FormatError naming the problem.
std::string formatDirectLight(const DirectLight& light);
DirectLight parseDirectLight(const std::string& text);

}  // namespace vdblight
