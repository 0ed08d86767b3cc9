// Scene check for reversed normals (Kontkanen & Laine, section 7): faces whose back side is
// seen from open space. The domain of interest treats every back-face as "inside a solid",
// so a face with reversed normals shrinks the domain; this lists such faces for the user.
//
// "Open space" (conservative): probe points on a regular grid over the scene bounds (cell
// centres, offset by an irrational fraction so that no probe lies on an axis-aligned face);
// each probe shoots `raysPerPoint` uniformly distributed directions. A probe is in open space
// only if at most `maxBackfaceFraction` of its rays first hit a back-face. A probe inside a
// closed solid sees only back-faces (fraction 1); even with one face of that solid flipped,
// that face covers at most a hemisphere, so the fraction stays >= 1/2 > 0.25 (the default).
// A face is listed if at least `minHits` rays from open-space probes hit its back side first.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;
class Tracer;

struct SceneCheckOptions {
    int resolution = 32;               ///< probes along the longest side of the scene bounds
    uint32_t raysPerPoint = 128;       ///< directions per probe
    double maxBackfaceFraction = 0.25; ///< a probe with more back-face hits is not open space
    uint32_t minHits = 1;              ///< back-face hits from open space needed to list a face
    uint64_t seed = 1;
    int threads = 0;                   ///< 0 = all cores
};

struct BackfacingTriangle {
    uint32_t triangle = 0;  ///< index into the scene's triangles
    uint64_t hits = 0;      ///< rays from open-space probes that hit its back side first
};

struct SceneCheckResult {
    uint64_t probes = 0;       ///< probe points tested
    uint64_t openProbes = 0;   ///< of which in open space
    uint64_t raysTraced = 0;
    std::vector<BackfacingTriangle> backfacing;  ///< sorted by hits (descending), then index
};

/// Finds the faces whose back side is seen from open space. Deterministic for any thread
/// count. Throws ValueError on out-of-range options.
SceneCheckResult findBackfacingTriangles(const Scene& scene, const Tracer& tracer, const SceneCheckOptions& options);

}  // namespace vdblight
