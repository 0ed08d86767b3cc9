// The generic point-gather pass: bakes any basis of the registry (basis/basis.h) on any layout.
//
// At every node, directions stratified in the 2 R^2 equal-area cells of basis/bins.h (R chosen from
// the ray budget: 2 R^2 about raysPerNode, one sample per cell), NEE of emissive triangles
// (MIS) and punctual lights exactly, exactly as the bins gather samples (bake_bins.h); every
// sample goes to Basis::accumulate, and Basis::finish gives the node's channels. Uniform grids
// (uniformLayout) and the levels of a bilevel / adaptive layout (seam nodes set from the
// coarser level) alike.
// Determinism: node n of level l uses the sample stream (l << 56) | n, and every node is
// summed serially in double: the same bits for any thread count.
#pragma once

#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

struct BasisBakeOptions {
    uint32_t raysPerNode = 256;  ///< rounded to 2 R^2 (R = round(sqrt(rays / 2)), at least 1)
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    TransportOptions transport;
    /// Bake only these nodes (one tile of a bake, volume/tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
};

/// The stratification resolution R of the generic gather for a ray budget (2 R^2 rays).
int basisGatherResolution(uint32_t raysPerNode);

/// Bakes `basis` on `layout`. Throws ValueError for zero rays or threads < 0, Cancelled if the
/// interrupter asks to stop.
Volume bakeBasis(const Scene& scene, const Tracer& tracer, const LevelLayout& layout, const Basis& basis,
                 const BasisBakeOptions& options, Interrupter* interrupter = nullptr, LevelsBakeStats* stats = nullptr);

}  // namespace vdblight
