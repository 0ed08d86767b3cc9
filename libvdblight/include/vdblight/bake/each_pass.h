// Each pass alone, its options, its statistics and the call that runs it: the point gather
// (below), multi-level and error-targeted gathers, depth moments, the direct-light plan,
// photons, solid culling. BakeRequest (bake/each_pass.h) holds these; most callers need only bake/each_pass.h.
//
// Bake passes: fill a volume's nodes with radiance estimates.
//
// The point-gather pass (this file) estimates, at each node, the SH order-2 projection of
// the incident radiance over the whole sphere (Kontkanen & Laine section 3):
//   L_j = integral of L(w) Y_j(w) dw
// with the direction integral split as in light/light.h: reflected light and sky by `rays`
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

#include "vdblight/light/direct_light.h"
#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/volume.h"

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
    /// Also record per-node depth moments from the gather's own first hits (basis/depth_moments.h,
    /// VolumeLevel::depth), for lookups that do not interpolate across walls. No extra rays.
    bool depthMoments = false;
    /// Passes of the filter across nodes after the last pass (node_filter.h: a 3x3x3 binomial
    /// kernel with the depth moments' visibility as weights): less noise, a little blur. 0 =
    /// none. Not with a tile's nodes (`only`).
    int nodeFilterPasses = 0;
    /// The filter's weights also from the nodes' error estimates (bilateral: differences the
    /// noise does not explain are kept; node_filter.h).
    bool nodeFilterByNoise = false;
    /// Probe passes draw their directions from each node's map of pass 0's radiance per
    /// direction (bake/direction_guide.h), weighted back to unbiased, instead of uniformly:
    /// fewer rays spent on dark directions where the light comes through an opening. Needs
    /// probe passes; not with staged bakes (the map is not kept between stages).
    bool guideProbeDirections = false;
    /// With one probe pass, blend pass 0's values into the probe pass's by pooled inverse
    /// variance (volume/first_pass_blend.h): pass 0's full paths are not thrown away. Not staged.
    bool blendFirstPass = false;
    /// With the surface probe cache, trace more full paths from the nodes whose pass-0 error is
    /// far above the bake's median (bake/extra_cache_paths.h), for the cache's bins only: less
    /// noise where light comes through an opening. Not staged.
    bool extraCachePaths = false;
    /// The extra paths per such node (bake/extra_cache_paths.h: 256 in the preview, 128 in
    /// `--quality fast`, whose grid has twice the nodes).
    uint32_t extraCachePathsPerNode = 256;
    /// Pass 0 in two rounds at the same total rays: a quarter of raysPerNode at every node, then
    /// the rest shared by the nodes' pooled error (bake/first_pass_by_error.h): more rays where
    /// light comes through an opening. Not tiled or staged.
    bool firstPassByError = false;
    /// The probe pass likewise in two rounds (one probe pass): its own pilot errors share the
    /// rest of its rays (`--quality fast`: less noise at the nodes by furniture and behind a
    /// door, docs/time_to_accuracy.md). Not tiled or staged.
    bool probePassByError = false;
    /// Bake only these nodes (one tile of a bake, volume/tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
    /// Staged probe passes (volume/tiles.h, "Staged bakes"): -1 = every pass; s in 0..probePasses =
    /// pass s only. A stage before the last returns a probe stage volume (probeStageBasis: the
    /// pass's reflected light; depth moments; counts; vdblight:probe_stage), the last one the
    /// bake's volume; a tile of a bake with probe passes must be baked in stages.
    int stage = -1;
    /// Stage > 0: the merged probe stage volume of stage - 1 (readProbeStage), every node.
    const Volume* stageInput = nullptr;
    /// Store the nodes in this basis (basis/basis.h; a linear projection such as `sh:4`) instead of
    /// SH order 2 (null). Same samples, probe passes (their reflected light stays SH order 2),
    /// depth moments, error estimate, tiles and stages.
    std::shared_ptr<const Basis> basis;
};

struct BakeStats {
    uint64_t nodes = 0;
    RayCount rays;
    double seconds = 0;
    double raysPerSecond() const { return seconds > 0 ? double(rays.total()) / seconds : 0.0; }
    /// Per node (passes that estimate it: the point gathers of bake/each_pass.h and bake/each_pass.h),
    /// the relative standard error of its mean irradiance over normals, from the sample
    /// variance of its samples (node_sampler.h); empty for other passes. A tile's bake
    /// (`only`, volume/tiles.h) holds the nodes of its window only (VolumeLevel::heldNodes).
    /// kNodeInsideSolid (negative, volume/volume.h) marks a node that lookups in free space
    /// do not read: inside a solid, in a volume with depth weights.
    std::vector<float> estimatedError;
    /// A tile's point gather with the pass-0 blend (GatherOptions::blendFirstPass): pass 0's
    /// values and errors over its window, which the merge blends in (its pooled variances cross
    /// tile borders; volume/tiles.h). Empty otherwise.
    std::vector<float> firstPassValues, firstPassError;
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

// ---------------------------------------------------------------------------------------------
// The point-gather pass on a multi-level layout (layout/layout.h).
//
// Every node that is not a seam node is baked exactly like a uniform node
// (projectIncidentRadiance); the sample stream of node n of level l is (l << 56) | n, so
// level 0 of a bilevel volume has the same bits as the uniform volume on the same grid.
// Seam nodes are then set from the coarser level (applySeamConstraints), coarse to fine.

namespace vdblight {

struct LevelsBakeStats : BakeStats {
    uint64_t seamNodes = 0;  ///< nodes set from the coarser level instead of baked
};

/// Bakes an SH order-2 radiance volume on `layout`. Same determinism, cancelling and
/// metadata as bakeShGather, plus layout, refine, per-level node counts and seam nodes.
Volume bakeShGatherLevels(const Scene& scene, const Tracer& tracer, const LevelLayout& layout,
                          const GatherOptions& options, Interrupter* interrupter = nullptr,
                          LevelsBakeStats* stats = nullptr);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Error-targeted point gather: each node samples in rounds until its estimated relative
// standard error of irradiance falls below a target or a maximum ray count is reached, so
// that easy regions stop early.
//
// Rounds: samples [0, minRays), then doubling the total (minRays, 2 minRays, 4 minRays, ...,
// maxRays) of the node's stratified sequence, so every round ends on a power-of-two multiple
// of the first and keeps the (0,2)-sequence stratification. A node that stops after N samples
// holds exactly the bits of the fixed-budget bake (bake/each_pass.h) with N rays per node.
//
// The error estimate is of the node's mean irradiance over all normal directions,
// Ebar = (1/4) * integral of L over the sphere (luminance) = pi * Y00 * L00: the irradiance
// the SH DC term carries, which has no SH truncation error. Its standard error is taken from
// the sample variance of the per-sample estimates of Ebar (conservative for the stratified
// direction part); relative error = standard error / Ebar, where Ebar includes exactly
// evaluated punctual lights (which add no variance). A node stops when this estimate times
// a margin for the uncertainty of a variance estimated from n samples (the 10 % chi-square
// quantile: 1.33 at n = 16, 1.13 at n = 64, 1.03 at n = 1024) is at most the target at the
// end of two consecutive rounds (path-traced samples are heavy-tailed: a small round that
// happens to miss its rare large samples looks converged), so a node takes at least two
// rounds unless its variance is exactly zero. A node
// whose Ebar is zero with zero variance (dark, or a constant sky) stops at the first round.
// The reported achieved error is the plain estimate (without the margin).
//
// Determinism: a node's decisions depend only on its own samples, so the volume has the same
// bits for any thread count.

namespace vdblight {

struct AdaptiveOptions {
    double targetError = 0.05;  ///< relative standard error of Ebar at which a node stops
    uint32_t minRays = 64;      ///< first round (>= 2); small rounds have unreliable variances
    uint32_t maxRays = 4096;    ///< a node never takes more
    uint64_t seed = 1;
    int threads = 0;
    TransportOptions transport;
    /// Probe-to-probe bounces as GatherOptions::probePasses (bake/each_pass.h); every pass samples to
    /// the target. The per-node error then excludes the earlier passes' noise.
    int probePasses = 0;
    /// As GatherOptions (bake/each_pass.h): one tile's nodes, and one stage of a staged bake (volume/tiles.h).
    const NodeMask* only = nullptr;
    int stage = -1;
    const Volume* stageInput = nullptr;
};

struct AdaptiveStats : BakeStats {
    std::vector<uint32_t> raysPerNode;    ///< gathered rays (samples) per node (a tile: per node of its window)
    uint64_t samples = 0;                 ///< sum of raysPerNode
    uint64_t nodesAtMax = 0;              ///< nodes that stopped at maxRays without meeting the rule
    // estimatedError (BakeStats): the achieved relative standard error per node.
};

/// Bakes an SH order-2 radiance volume on `grid`, node by node to the target error.
/// Throws ValueError for a target that is not in (0, 1], minRays < 2 or maxRays < minRays.
Volume bakeShGatherAdaptive(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                            const AdaptiveOptions& options, Interrupter* interrupter = nullptr,
                            AdaptiveStats* stats = nullptr);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The depth-moment pass: per node of any volume (every layout, basis and bake method), the
// depth moments of basis/depth_moments.h from first-hit rays cast from the node itself.
//
// The rays are the first rays of the point gather: node n of level l uses the stream
// (l << 56) | linear index and the same scrambled Sobol directions, so for a point gather with
// as many rays (and the same seed) these are exactly the gather's first hits. They are traced
// again here (first hits only, in 16-ray packets), which keeps the pass one small function
// that every pass, including the anti-aliased and photon ones whose rays do not start at the
// nodes, can call after baking.
//
// Deterministic: node values depend only on (seed, stream, ray count) and are summed in ray
// order, so the result has the same bits for any thread count.

namespace vdblight {

class Tracer;
class Interrupter;

struct DepthOptions {
    uint32_t raysPerNode = 256;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    /// Bake only these nodes (one tile of a bake, volume/tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
};

struct DepthStats {
    uint64_t rays = 0;
    double seconds = 0;
};

/// One node's depth moments (out: depth::kFloatsPerNode floats) from `rays` first-hit rays
/// at x with the gather's directions for (seed, stream); `spacing` is the node's level spacing.
void nodeDepthMoments(const Tracer& tracer, const Vec3f& x, double spacing, uint64_t seed, uint64_t stream,
                      uint32_t rays, float* out, RayCount& count);

/// Fills VolumeLevel::depth of every level of `volume` and records the pass in its metadata
/// (depth_moments, depth_rays_per_node). Throws ValueError for 0 rays, Cancelled if asked.
void bakeDepthMoments(const Tracer& tracer, Volume& volume, const DepthOptions& options,
                      Interrupter* interrupter = nullptr, DepthStats* stats = nullptr);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Direct light out of the SH (issue 15, `bake --direct runtime | occlusion`; light/direct_light.h).
//
// A bake in these modes first chooses the lights whose direct light it leaves out of the
// basis (planDirectLight), bakes with TransportOptions::skipAtReceiver set to the plan's
// filter, and then (occlusion) bakes each chosen light's visibility at every node
// (bakeLightVisibility). The lights are chosen by their measured contribution to the volume:
// at a subset of nodes, the light's mean irradiance over all normals times its visibility
// from the node (shadow rays), summed; not by power alone, so a bright light behind a wall
// ranks below a dim one in the room.

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;

struct DirectOptions {
    DirectMode mode = DirectMode::Baked;
    /// Occlusion: how many lights get a visibility channel (the most important ones), 1..16.
    int maxLights = 4;
    /// Shadow rays per node and polygon light for the visibility channels (stratified over its area).
    uint32_t visibilitySamples = 64;
    /// Occlusion: also bake each light's shadow edges (shadow_edges.h), which keep its shadow
    /// edges sharp between the nodes. false: the visibility channels alone (as before issue 32).
    bool shadowEdges = true;
    /// Occlusion: each chosen quad light listed as splitLights x splitLights pieces
    /// (splitQuadLight), each with its own visibility channel and edges, 1 (whole) .. 4. The
    /// lookup's direct light is exact irradiance x visibility per listed light: a light whose
    /// part a blocker hides while the receiver's horizon cuts another part is off by that
    /// product, and its pieces much less (docs/shadow_visibility.md, "Split lights"). The
    /// receivers still leave the whole light out of the SH.
    int splitLights = 1;
    /// Ranking: at most this many nodes (evenly strided) and shadow rays per polygon light there.
    uint32_t rankingNodes = 512;
    uint32_t rankingSamples = 16;
    uint64_t seed = 1;
    int threads = 0;
};

/// ValueError naming the option unless 1 <= maxLights <= 16 and 1 <= splitLights <= 4
/// (DirectOptions): planDirectLight checks them, and a BakeRequest before it bakes anything.
void checkDirectLightCounts(int maxLights, int splitLights);

/// Which lights a bake leaves out at the receiver, in the scene's local frame.
struct DirectPlan {
    DirectMode mode = DirectMode::Baked;
    std::vector<SceneLight> lights;     ///< runtime: every light; occlusion: the chosen K, most important first
    std::vector<double> contribution;   ///< per light in `lights`: measured share of the volume's direct light (0..1)
    std::size_t sceneLightCount = 0;
    std::shared_ptr<const ReceiverDirectFilter> filter;  ///< for TransportOptions::skipAtReceiver (null: baked)
};

/// Chooses the lights (see above). Throws ValueError for occlusion in a scene without lights
/// and for maxLights outside 1..16.
DirectPlan planDirectLight(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const DirectOptions& options);

/// Writes the plan into a baked single-level volume: Volume::direct (mode, lights) and, for
/// occlusion, level 0's lightVisibility (lightVisibility() of light/light.h at each node; a
/// node the light cannot reach at all -- behind a one-sided polygon, outside a spot's cone --
/// gets 1, so that interpolating towards the lit side is not darkened by it) and, with
/// DirectOptions::shadowEdges, level 0's lightShadowEdges (shadow_edges.h). Deterministic:
/// the samples of node n and light i depend on (seed, n, i) only. With `only` (one tile of a
/// bake, volume/tiles.h) only those nodes are baked (direct_visibility_rays counts their rays).
void bakeLightVisibility(const Scene& scene, const Tracer& tracer, const DirectPlan& plan, const DirectOptions& options,
                         Volume& volume, Interrupter* interrupter = nullptr, const NodeMask* only = nullptr);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// The photon pass (Pacanowski et al. 2009, section 3.3): photons traced from the lights
// fill a grid of irradiance vectors (basis/irradiance_vectors.h).
//
// Each photon path segment is walked through the node lattice without further ray tests
// (forEachFaceCrossing, internal: src/bake/face_crossing.h);
// every time it crosses a plane of nodes (a voxel face) inside the node box, its
// contribution goes to the nearest node on that plane, for the direction delta that faces
// the light: a photon travelling along +a feeds I_{-a} (docs/format.md, "sign convention").
// Assigning a crossing to the nearest node is counting the photons through the node's dual
// face, a square of side h centred on it, clipped by the node box: area h^2, halved on the
// box's boundary and quartered on its edges (the paper's A_delta).
//
// The flux through a face is the irradiance times its area, whatever the photons' angles,
// so <I_delta, delta> = sum(phi) / A estimates the irradiance on a surface facing delta.
// The estimators differ in the vector each photon adds (w = direction towards the light):
//  - Flux (default): phi w / |w_a| / A. Unbiased for the whole irradiance vector
//    integral of L w dw: crossings are distributed as L |w_a| dw dA.
//  - PaperCosine: phi w / A, the paper's formula. Its delta component converges to
//    integral of L w_a^2 dw, not the irradiance (2/3 of it under a uniform sky; see
//    docs/methods.md and tests/photons_test.cpp).
//
// Determinism: photon i's random numbers depend only on (seed, i). Photons are processed in
// fixed-size batches (the size depends only on the photon count and the grid), each batch
// accumulating into its own float buffer; each buffer is rounded once to 128-bit fixed point
// and added to the total exactly (volume/tiles.h). Same seed, same bits for any thread count,
// and for any split of the batches into tiles (a tile traces a run of batches; the merge adds
// the tiles' sums: volume/tiles.h, docs/scaling.md).

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;

enum class PhotonEstimator { Flux, PaperCosine };

struct PhotonOptions {
    uint64_t photons = 1'000'000;  ///< photons emitted in total
    uint64_t seed = 1;
    int threads = 0;               ///< 0 = all hardware threads
    PhotonEstimator estimator = PhotonEstimator::Flux;
    /// maxBounces = diffuse reflections a photon may make (by default a safety cap that
    /// roulette makes unreachable, light/light.h); Russian roulette by albedo from the first
    /// reflection (survival probability = the largest albedo component, at most
    /// kRouletteMaxSurvival).
    TransportOptions transport;
    /// Tiles (volume/tiles.h): tiles > 0 traces only the batches of tile `tile` of `tiles`
    /// (photonTileBatches; tracePhotons only).
    int tiles = 0;
    int tile = 0;
};

/// Upper bound on PhotonOptions::photons (more is refused with a time estimate).
constexpr uint64_t kMaxPhotons = 20'000'000'000ull;

/// Throws ValueError for 0 photons or more than kMaxPhotons (with a rough time estimate).
void checkPhotonCount(uint64_t photons);

struct PhotonStats {
    uint64_t photons = 0;
    uint64_t segments = 0;   ///< path segments walked through the grid
    uint64_t crossings = 0;  ///< face crossings added to the grid
    RayCount rays;
    double seconds = 0;
    uint64_t batches = 0;
    uint64_t batchSize = 0;
};

/// Bakes an irradiance-vector volume on `grid` (at least 2 nodes along every axis): the
/// sums of every batch (tracePhotons), normalised by photonVolume.
/// Throws ValueError (bad options or grid, options.tiles > 0), SceneError (nothing emits), Cancelled.
Volume bakePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                   Interrupter* interrupter = nullptr, PhotonStats* stats = nullptr);

/// The exact sums (volume/tiles.h) of the batches `options` selects (every batch, or a tile's
/// run), and in `meta` the volume's metadata with the counts (rays, segments, crossings) of
/// those batches. `stats->photons`: the photons traced. Throws as bakePhotons, and
/// ValueError for a tile outside 0 .. batches - 1.
PhotonSums tracePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                        Interrupter* interrupter = nullptr, PhotonStats* stats = nullptr, Metadata* meta = nullptr);

/// Photons per batch for a photon count and grid size (never a function of threads): at
/// least 1/256 of the photons (so at most 256 batches: the fixed-point range of
/// volume/tiles.h relies on it) and enough that adding a batch's buffer to the total costs
/// little next to tracing it.
uint64_t photonBatchSize(uint64_t photons, std::size_t nodes);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Solid culling for multi-level layouts (issue 4, "sparse"): nodes that a query in open
// space can never read are left out (inactive: not baked, not stored).
//
// The rule (conservative, docs/format.md "Levels"):
//  1. Leaf cells are the cells a query interpolates in: level-0 cells and the children of
//     refined cells, that are not refined themselves. A leaf cell is *geometry-free* when no
//     triangle overlaps it (the exact test that drives refinement, with the same half-spacing
//     extension at the node-box border; for the finest level LevelsPlacement::keepFinestGeometry).
//  2. Geometry-free leaf cells are joined into connected regions through shared faces (a
//     point just outside each face centre is located in the layout). A region is one piece of
//     space that no surface crosses, so it lies wholly inside or wholly outside any solid.
//  3. A region is *solid* when rays from the centres of (up to `maxCellsPerComponent`, evenly
//     chosen) of its cells in `raysPerCell` fixed directions never escape the scene and at
//     least `backfaceFraction` of them first hit a triangle from behind (ray . geometric
//     normal > 0). Majority back faces rather than all back faces, because closed solids are
//     often modelled without the face they stand on (the Cornell blocks have no bottom: from
//     inside, the downward rays see the floor's front); a parity test needs watertight,
//     non-overlapping solids, which scenes rarely are. An escape (hole to the outside) always
//     keeps the region.
//  4. A node of level l is culled when every cell of level l that has it as a corner and
//     exists (inside the box; for l >= 1 a child of a refined cell) is a solid leaf. Corners of
//     refined cells and of non-solid leaves are therefore always kept, so a query in a
//     non-solid cell, and the seam constraints, only read kept nodes.

namespace vdblight {

class Tracer;

struct SolidCullOptions {
    int raysPerCell = 16;            ///< fixed spherical Fibonacci directions
    int maxCellsPerComponent = 256;  ///< cells of a region whose rays vote
    double backfaceFraction = 0.5;   ///< a region is solid at or above this fraction of back-face hits
};

struct SolidCullStats {
    uint64_t leafCells = 0;          ///< leaf cells of all levels
    uint64_t freeLeafCells = 0;      ///< of which geometry-free
    uint64_t regions = 0;            ///< connected regions of geometry-free leaf cells
    uint64_t solidRegions = 0;
    uint64_t solidCells = 0;
    uint64_t nodesBefore = 0;        ///< nodes of the layout before culling
    uint64_t nodesCulled = 0;
    std::vector<uint64_t> culledPerLevel;
};

/// Solid leaf cells of every level (lower-corner linear indices, ascending), by the rule
/// above. Requires layout.hasFinestGeometry for multi-level layouts (ValueError otherwise).
std::vector<std::vector<uint64_t>> classifySolidCells(const LevelLayout& layout, const Tracer& tracer,
                                                      const SolidCullOptions& options = {},
                                                      SolidCullStats* stats = nullptr);

/// Linear indices (ascending) of the nodes of level `level` that rule 4 culls, given the
/// solid cells of every level. Level 0 considers every node of its box.
std::vector<uint64_t> culledNodes(const LevelLayout& layout, const std::vector<std::vector<uint64_t>>& solid,
                                  std::size_t level);

/// Classifies and removes the culled nodes from the layout's levels (level 0 becomes sparse
/// if any of its nodes is culled). A single-level layout is left unchanged. Returns the
/// number of nodes removed.
uint64_t cullSolidNodes(LevelLayout& layout, const Tracer& tracer, const SolidCullOptions& options = {},
                        SolidCullStats* stats = nullptr);

}  // namespace vdblight
