// Ground truth: irradiance computed directly at a point for a normal, without SH and
// without a grid, with the same light transport as the bake (light/light.h).
//
//   E(x, n) = integral over the hemisphere of n of L(w) cos(w, n) dw
// Reflected light and sky by cosine-weighted stratified directions, emissive triangles by
// NEE with the cosine weight, punctual lights exactly at the point (above
// TransportOptions::exactLightLimit point/spot lights still exactly at the point when there are
// at most `samples` of them, else one sampled per sample; bounce vertices then sample one:
// light/light.h). The standard error comes from the sample variance of the per-sample estimates.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/light/light.h"
#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;

struct ReferencePoint {
    Vec3f position;
    Vec3f normal;  ///< need not be unit length; normalised internally
};

struct ReferenceResult {
    Rgbd irradiance;
    Rgbd standardError;
};

struct ReferenceOptions {
    uint32_t samples = 65536;
    uint64_t seed = 1;
    int threads = 0;
    TransportOptions transport;
    /// With more point/spot lights than transport.exactLightLimit but at most `samples` of
    /// them, evaluate every one exactly at the point (no variance from the light choice there);
    /// false: sample one per sample at the point as well (tests of the sampler use this).
    bool punctualExactAtPoint = true;
};

/// Throws ValueError for a zero normal; Cancelled if interrupted.
std::vector<ReferenceResult> referenceIrradiance(const Scene& scene, const Tracer& tracer,
                                                 const std::vector<ReferencePoint>& points,
                                                 const ReferenceOptions& options,
                                                 Interrupter* interrupter = nullptr);

/// Comma-separated finite numbers ("1, 2.5,-3") as values: a row of readPointsCsv, or an
/// option such as --bounds. ValueError "'x' is not a number" / "is not a finite number".
std::vector<double> parseNumberList(const std::string& text);

/// Reads "x,y,z,nx,ny,nz" rows (a header line and '#' comments are skipped).
/// `worldPositions`, if given, receives the positions in double (world points far from the
/// origin keep their precision; see docs/scene.md, "Large coordinates").
std::vector<ReferencePoint> readPointsCsv(const std::string& path, std::vector<Vec3d>* worldPositions = nullptr);

/// `vdblight reference`'s answers as CSV rows x,y,z,nx,ny,nz,E_r,E_g,E_b,stderr_r,stderr_g,
/// stderr_b after a header: the points (in `scene`'s local frame) back in world coordinates.
std::string referenceCsv(const Scene& scene, const std::vector<ReferencePoint>& points,
                         const std::vector<ReferenceResult>& results);

}  // namespace vdblight
