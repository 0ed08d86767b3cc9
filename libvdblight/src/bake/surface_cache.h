// The reflected light and sky of an earlier pass's volume as a SurfaceIrradianceCache
// (light.h): "probe-to-probe bounces" (DDGI, Majercik et al. 2019), issue 15. (Internal to
// the bake module.)
//
// At a surface point p with normal n the irradiance is interpolated trilinearly from the
// eight nodes of p's cell (position clamped into the node box), each node's SH order-2
// radiance of reflected light and sky convolved with the cosine lobe for n. A node takes
// part only if it lies in front of the surface (dot(node - p, n) > 0) and p sees it (one
// shadow ray each): nodes behind a wall, or inside it, would carry the other side's light.
// The weights of the nodes that take part are renormalised; with none, the lookup fails and
// the path continues (an unbiased fallback).
//
// What remains biased: the nodes' irradiance stands for p's (near-field occlusion at
// corners, gradients across a cell), SH order 2 for the reflected light's directions, and
// the earlier pass's own noise, which every later pass averages over many nodes instead of
// removing.
#pragma once

#include <vector>

#include "vdblight/layout.h"
#include "vdblight/light.h"
#include "vdblight/sh.h"
#include "vdblight/volume.h"

namespace vdblight {

class Tracer;

namespace bake_detail {

class VolumeSurfaceCache : public SurfaceIrradianceCache {
public:
    /// `reflected`: per node of `grid` (node order), nine RGB SH radiance coefficients of the
    /// reflected light and sky (NodeSampler::reflectedCoefficients); copied.
    VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const std::vector<Rgb>& reflected);
    /// The same coefficients as 27 floats per node, read in place: a probe stage volume's data
    /// (tiles.h), which must outlive the cache, so that a staged tile holds the whole pass
    /// before once, not twice.
    VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const float* reflected);
    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override;

private:
    const Tracer& tracer_;
    GridSpec grid_;
    std::vector<float> own_;  ///< the copy of the first constructor
    const float* coeffs_;     ///< per node, 27 floats: nine RGB coefficients
    float lobe_[sh::kCoeffs];  ///< A_l of each coefficient's band, applied at lookup
};

/// Staged probe passes (tiles.h, "Staged bakes"): which passes a gather with `probePasses`
/// runs for GatherOptions::stage (-1: all), checked against the stage input.
struct PassRange {
    int first = 0, last = 0;
};
PassRange stagePasses(int probePasses, int stage, const Volume* stageInput, const GridSpec& grid, bool depthMoments);


/// The probe stage volume of a stage before the last: `reflected` as its data, `depth` (may
/// be empty) and the counts of `meta` (common bake metadata) with probe_stage = `stage`.
/// `shape`: the baked level (its grid and, for a tile, its window of nodes, which `reflected`
/// and `depth` hold).
Volume stageVolume(const VolumeLevel& shape, const std::vector<Rgb>& reflected, std::vector<float> depth, Metadata meta,
                   int stage, int probePasses);

}  // namespace bake_detail
}  // namespace vdblight
