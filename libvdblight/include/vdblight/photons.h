// The photon pass (Pacanowski et al. 2009, section 3.3): photons traced from the lights
// fill a grid of irradiance vectors (irradiance_vectors.h).
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
// and added to the total exactly (photon_sums.h). Same seed, same bits for any thread count,
// and for any split of the batches into tiles (a tile traces a run of batches; the merge adds
// the tiles' sums: tiles.h, docs/scaling.md).
#pragma once

#include <cstdint>

#include "vdblight/layout.h"
#include "vdblight/light.h"
#include "vdblight/photon_sums.h"
#include "vdblight/volume.h"

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
    /// roulette makes unreachable, light.h); Russian roulette by albedo from the first
    /// reflection (survival probability = the largest albedo component, at most
    /// kRouletteMaxSurvival).
    TransportOptions transport;
    /// Tiles (tiles.h): tiles > 0 traces only the batches of tile `tile` of `tiles`
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

/// The exact sums (photon_sums.h) of the batches `options` selects (every batch, or a tile's
/// run), and in `meta` the volume's metadata with the counts (rays, segments, crossings) of
/// those batches. `stats->photons`: the photons traced. Throws as bakePhotons, and
/// ValueError for a tile outside 0 .. batches - 1.
PhotonSums tracePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                        Interrupter* interrupter = nullptr, PhotonStats* stats = nullptr, Metadata* meta = nullptr);

/// Photons per batch for a photon count and grid size (never a function of threads): at
/// least 1/256 of the photons (so at most 256 batches: the fixed-point range of
/// photon_sums.h relies on it) and enough that adding a batch's buffer to the total costs
/// little next to tracing it.
uint64_t photonBatchSize(uint64_t photons, std::size_t nodes);

}  // namespace vdblight
