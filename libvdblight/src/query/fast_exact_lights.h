// The exact direct light of the lights an occlusion volume lists, as the lookups add it at
// every query: the same closed forms as exactIrradiance (direct_light.h), with the polygon's
// contour sum in float instead of double (issue 33, part 4: the double contour with its four
// double atan2 calls was 853 of the default lookup's 3 285 instructions).
//
// The polygon term: its vertices are taken relative to the receiver in double (no
// cancellation however far the volume is from the origin), then clipped and summed in float
// with float atan2. Since issue 33's tenth session (session 24) the lookups take the NanoVDB
// shader's own float operations (shaders/vdblight_nanovdb_lights.h): the edges' terms added
// in float in its order, the same normal (floatPathNormal), and point, spot and directional
// lights in float too, so that query and the shader give the same bits where the lights are
// the same floats (a bake's are; where a clipped polygon's terms cancel, a last-bit
// difference had left them ~1e-4 apart). exactIrradiance stays the reference (export,
// OcclusionLookup::direct, the tests compare against it). Mesh lights take the float path
// too since session 25, each triangle on the side its own plane decides in double; a polygon
// or mesh with a loop of more than kMaxVertices vertices is evaluated by exactIrradiance.
// (Internal to the query module.)
#pragma once

#include <cstddef>
#include <vector>

#include "float4.h"
#include "vdblight/light/direct_light.h"

namespace vdblight::query_detail {

/// atan2(y, x) for y >= 0 (an angle in [0, pi]) in float, within 2e-7 of it relative (the
/// polygon's edge angles; query_fast_paths_test checks it against std::atan2 in double). No
/// library call: the libm float atan2 was a third of the float contour's instructions.
float atan2NonNegative(float y, float x);
/// atan2NonNegative in each lane of four, with the same bits, branch-free (the polygon's edges
/// four at a time: the scalar one's data-dependent branches were mispredicted at random normals).
Float4 atan2NonNegative4(Float4 y, Float4 x);

/// The normal the float path takes for a lookup's normal n: n itself where its squared length
/// is within kUnitSquaredLength of 1 (any float normalisation leaves it there), else n
/// normalised in double and rounded. Why not always normalised: at a receiver that sees a
/// polygon as a sliver of its hemisphere the answer moves by ~1e-4 of itself for a change of n
/// in its last bit, and the NanoVDB shader (shaders/vdblight_nanovdb_lights.h, the same rule)
/// has no double to normalise with: the same n gives the two the same bits (issue 33).
constexpr float kUnitSquaredLength = 1e-6f;
Vec3f floatPathNormal(const Vec3f& n);

class FastExactLights {
public:
    /// Loops of at most this many vertices take the float path (every quad and triangle light,
    /// every mesh light).
    static constexpr std::size_t kMaxVertices = 8;

    explicit FastExactLights(const std::vector<DirectLight>& lights);
    std::size_t size() const { return lights_.size(); }
    /// exactIrradiance(lights[i], x, n) within float rounding; n of unit length.
    Rgb irradiance(std::size_t i, const Vec3d& x, const Vec3d& n) const { return irradiance(i, x, n, Vec3f(n)); }
    /// The same with the float path's normal given: nf, n rounded to float or floatPathNormal's.
    Rgb irradiance(std::size_t i, const Vec3d& x, const Vec3d& n, const Vec3f& nf) const;
    /// True if light i takes the float path.
    bool floatPath(std::size_t i) const { return float_[i]; }
    /// True if light i is a point, spot or directional light, evaluated in float as the NanoVDB
    /// shader does (shaders/vdblight_nanovdb_lights.h), operation for operation: its direction
    /// and cone cosines rounded to float as the file stores them, its position minus x taken in
    /// double and rounded once (the shader's float difference where both are floats, and no
    /// cancellation far from the origin).
    bool floatPunctual(std::size_t i) const { return punctual_[i].kind >= 0; }

private:
    /// A point, spot or directional light as the shader reads it (kind -1: another kind).
    struct Punctual {
        int kind = -1;
        Rgb value;
        Vec3f direction;
        Vec3d position;
        float cosInner = 0, cosOuter = 0;
    };
    Rgb punctual(const Punctual& p, const Vec3d& x, const Vec3f& n) const;

    std::vector<DirectLight> lights_;
    std::vector<Punctual> punctual_;
    std::vector<char> float_;
    std::vector<char> quad_;  ///< float path, one loop of four vertices (fast_exact_lights.cpp: quadContour)
    std::vector<std::vector<Vec3d>> triangleNormals_;  ///< a mesh light's per-loop Newell vectors (else empty)
};

}  // namespace vdblight::query_detail
