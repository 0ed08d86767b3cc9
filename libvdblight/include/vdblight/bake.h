// Bake passes: fill a volume's nodes with radiance estimates.
//
// The point-gather pass (this file) estimates, at each node, the SH order-2 projection of
// the incident radiance over the whole sphere (Kontkanen & Laine section 3):
//   L_j = integral of L(w) Y_j(w) dw
// with the direction integral split as in light.h: reflected light and sky by `rays`
// stratified (scrambled Sobol) directions uniform on the sphere, emissive triangles by as
// many NEE samples, punctual lights exactly. With GatherOptions::basis the same samples are
// stored in another basis (real SH of order N, `--basis sh:N`), with everything else alike.
//
// Determinism: node n's samples depend only on (seed, n, sample number) and are summed in
// sample order in double, so the volume has the same bits for any thread count.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/light.h"
#include "vdblight/tiles.h"
#include "vdblight/volume.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;
class Basis;

struct GatherOptions {
    uint32_t raysPerNode = 256;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    TransportOptions transport;
    /// Probe-to-probe bounces (issue 15; bake/surface_cache.h): after a first pass of full
    /// path tracing, this many more passes (raysPerNode each, own seeds) end every gathered
    /// path at its first surface hit with the previous pass's reflected light interpolated
    /// there. 0 = plain path tracing. Trades the variance of long paths (light through a door)
    /// for the bias of the volume's representation at surfaces (docs/methods.md).
    int probePasses = 0;
    /// The probe pass's cache: false = the nodes' reflected light (DDGI-style); true = bins of
    /// irradiance samples taken at the surfaces by pass 0's own paths (`--probe-cache surface`;
    /// bake/surface_bins.h, docs/methods.md). One probe pass only; staged, stage 0 returns the
    /// bins' sums in Volume::surfaceBins and stage 1 reads them from the stage input.
    bool surfaceProbeCache = false;
    /// Also record per-node depth moments from the gather's own first hits (depth_moments.h,
    /// VolumeLevel::depth), for lookups that do not interpolate across walls. No extra rays.
    bool depthMoments = false;
    /// Passes of the filter across nodes after the last pass (node_filter.h: a 3x3x3 binomial
    /// kernel with the depth moments' visibility as weights): less noise, a little blur. 0 =
    /// none. Not with a tile's nodes (`only`).
    int nodeFilterPasses = 0;
    /// The filter's weights also from the nodes' error estimates (bilateral: differences the
    /// noise does not explain are kept; node_filter.h).
    bool nodeFilterByNoise = false;
    /// Bake only these nodes (one tile of a bake, tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
    /// Staged probe passes (tiles.h, "Staged bakes"): -1 = every pass; s in 0..probePasses =
    /// pass s only. A stage before the last returns a probe stage volume (probeStageBasis: the
    /// pass's reflected light; depth moments; counts; vdblight:probe_stage), the last one the
    /// bake's volume; a tile of a bake with probe passes must be baked in stages.
    int stage = -1;
    /// Stage > 0: the merged probe stage volume of stage - 1 (readProbeStage), every node.
    const Volume* stageInput = nullptr;
    /// Store the nodes in this basis (basis.h; a linear projection such as `sh:4`) instead of
    /// SH order 2 (null). Same samples, probe passes (their reflected light stays SH order 2),
    /// depth moments, error estimate, tiles and stages.
    std::shared_ptr<const Basis> basis;
};

struct BakeStats {
    uint64_t nodes = 0;
    RayCount rays;
    double seconds = 0;
    double raysPerSecond() const { return seconds > 0 ? double(rays.total()) / seconds : 0.0; }
    /// Per node (passes that estimate it: the point gathers of bake.h and bake_adaptive.h),
    /// the relative standard error of its mean irradiance over normals, from the sample
    /// variance of its samples (node_sampler.h); empty for other passes. A tile's bake
    /// (`only`, tiles.h) holds the nodes of its window only (VolumeLevel::heldNodes).
    /// kNodeInsideSolid (negative, error_summary.h) marks a node that lookups in free space
    /// do not read: inside a solid, in a volume with depth weights.
    std::vector<float> estimatedError;
    /// q-quantile (0..1) of estimatedError over the nodes that free-space lookups read
    /// (nearest rank); 0 if there is none.
    double errorQuantile(double q) const;
};

/// Bakes an SH order-2 radiance volume on `grid`. Fills volume.meta with every bake
/// parameter and statistic. Throws Cancelled if `interrupter` asks to stop.
Volume bakeShGather(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                    const GatherOptions& options, Interrupter* interrupter = nullptr,
                    BakeStats* stats = nullptr);

}  // namespace vdblight
