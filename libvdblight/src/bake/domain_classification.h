// The anti-aliased pass's per-cell sampling rays and their domain classification
// (Kontkanen & Laine's Algorithm 2 and the fallback; bake_antialiased.h describes the pass).
// Internal to the bake module (domain_classification.cpp, antialiased_gather.cpp; tests
// include it as "../libvdblight/src/bake/domain_classification.h").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bake/bake_antialiased.h"
#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

struct Scene;

/// One candidate sampling ray of a cell and its classification.
struct CellSample {
    Vec3f origin;
    Vec3f direction;
    bool accepted = false;  ///< origin taken to be in the domain of interest
};

/// The candidate rays of cell `cell` (index cx-major like nodes) and, for
/// DomainMode::Interior, their classification by Algorithm 2 followed by `fallback` (All
/// accepts every origin). `hits` (optional) receives the first hit of each accepted sampling
/// ray. `scene` is the one `tracer` was built from. This is the classification the bake
/// uses.
std::vector<CellSample> classifyCell(const Scene& scene, const Tracer& tracer, const GridSpec& grid, std::size_t cell,
                                     uint32_t rays, uint64_t seed, DomainMode domain, RayCount& count,
                                     std::vector<Hit>* hits = nullptr, const DomainFallback& fallback = {});

}  // namespace vdblight
