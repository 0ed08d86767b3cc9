// The point-gather pass for Greger bins and higher moments (basis/bins.h): at every node, the
// radiance is sampled through every bin (stratified inside the bin, plus NEE of emissive
// triangles with MIS and punctual lights exactly, as in bakeShGather), averaged per bin,
// and turned into one value per bin direction by the quadrature of eq. 4 / eq. 5.
//
// Works on any layout: a uniform grid (uniformLayout) or the levels of a bilevel /
// adaptive layout (layout/layout.h; seam nodes set from the coarser level as for SH).
// Determinism: node n of level l uses the sample stream (l << 56) | n, and every node is
// summed serially in double: the same bits for any thread count.
#pragma once

#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/bins.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

struct BinsBakeOptions {
    bins::BasisSpec basis;       ///< Kind::Bins or Kind::Moment
    uint32_t samplesPerBin = 1;  ///< radiance samples inside every bin (rays = 2 R^2 * this)
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    TransportOptions transport;
    /// Bake only these nodes (one tile of a bake, volume/tiles.h); the others stay 0. Null = all.
    const NodeMask* only = nullptr;
};

/// A one-level layout of the uniform grid `grid` (for bakeBins on a uniform volume).
LevelLayout uniformLayout(const GridSpec& grid);

/// Bakes a bins / moment volume on `layout`. Throws ValueError for an SH basis, zero
/// samples or threads < 0, Cancelled if the interrupter asks to stop.
Volume bakeBins(const Scene& scene, const Tracer& tracer, const LevelLayout& layout, const BinsBakeOptions& options,
                Interrupter* interrupter = nullptr, LevelsBakeStats* stats = nullptr);

}  // namespace vdblight
