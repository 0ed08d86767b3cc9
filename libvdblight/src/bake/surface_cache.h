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

#include <algorithm>
#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace bake_detail {

/// The nodes a cache over a node grid blends for a read at p with normal n (above): the
/// corners of p's cell (p clamped into the node box) with their trilinear weights, keeping
/// those in front of the surface that p sees (one shadow ray each, counted in `rays`). Calls
/// visit(node index, node position, weight) for each in corner order and returns the sum of
/// their weights (0: none takes part). Shared by VolumeSurfaceCache and the benchmark's exact
/// variants of it (bench_accuracy --probe-study), so both blend the same nodes.
template <class Visit>
float forEachVisibleNode(const Tracer& tracer, const GridSpec& grid, const Vec3f& p, const Vec3f& n, RayCount& rays,
                         Visit&& visit) {
    const int dims[3] = {grid.nx, grid.ny, grid.nz};
    int base[3];
    float frac[3];
    for (int a = 0; a < 3; ++a) {
        const double u = std::clamp((double(p[a]) - grid.origin[a]) / grid.spacing, 0.0, double(dims[a] - 1));
        base[a] = std::min(int(u), std::max(0, dims[a] - 2));
        frac[a] = dims[a] > 1 ? float(u - base[a]) : 0.0f;
    }
    float weight = 0;
    for (int c = 0; c < 8; ++c) {
        int idx[3];
        float w = 1;
        for (int a = 0; a < 3; ++a) {
            const int bit = (c >> a) & 1;
            if (bit && dims[a] < 2) { w = 0; break; }
            idx[a] = base[a] + bit;
            w *= bit ? frac[a] : 1.0f - frac[a];
        }
        if (!(w > 0)) continue;
        const Vec3f node(grid.node(idx[0], idx[1], idx[2]));
        const Vec3f d = node - p;
        if (!(dot(d, n) > 0)) continue;  // behind the surface: the other side's light
        ++rays.occluded;
        if (tracer.occluded(Ray{p, d, 0.0f, 1.0f})) continue;
        visit(std::size_t(grid.index(idx[0], idx[1], idx[2])), node, w);
        weight += w;
    }
    return weight;
}

class VolumeSurfaceCache : public SurfaceIrradianceCache {
public:
    /// `reflected`: per node of `grid` (node order), nine RGB SH radiance coefficients of the
    /// reflected light and sky (NodeSampler::reflectedCoefficients); copied.
    VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const std::vector<Rgb>& reflected);
    /// The same coefficients as the first 27 of `stride` floats per node, read in place: a probe
    /// stage volume's data (tiles.h; stage_carry.h may follow them), which must outlive the
    /// cache, so that a staged tile holds the whole pass before once, not twice.
    VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const float* reflected, std::size_t stride = 27);
    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override;

private:
    const Tracer& tracer_;
    GridSpec grid_;
    std::vector<float> own_;  ///< the copy of the first constructor
    const float* coeffs_;     ///< per node, `stride_` floats starting with nine RGB coefficients
    std::size_t stride_ = 27;
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
