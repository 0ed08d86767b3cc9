// The passes of the bake module (pass.h), one file each (pass_<name>.cpp, the class inside
// it); pass_registry.cpp lists them. (Internal to the bake module.)
#pragma once

#include <string>
#include <vector>

#include "vdblight/bake/bake.h"

namespace vdblight::bake_detail {

const Pass& gatherPass();       ///< point gather on a uniform grid (bake.h), back-face invalidation
const Pass& adaptivePass();     ///< error-targeted point gather (bake_adaptive.h)
const Pass& antialiasedPass();  ///< Kontkanen-Laine anti-aliased gather (bake_antialiased.h)
const Pass& levelsPass();       ///< point gather on bilevel / adaptive levels (bake_levels.h)
const Pass& binsPass();         ///< Greger bins and moments on any layout (bake_bins.h)
const Pass& photonsPass();      ///< Pacanowski photons into irradiance vectors (photons.h)

/// The layout options the levels and bins passes share (pass_levels.cpp): refine, levels,
/// refine distance; and their rule beyond the declared ranges.
std::vector<PassOption> layoutOptions();
void checkLayoutOptions(const BakeRequest& request);

/// What a volume of a registry basis holds, for Pass::summaryStored: "(basis sh:4: radiance
/// SH coefficients, bands 0..4, 25 Vec3f grids)" (bake_summary.cpp).
std::string storedBasisSummary(const BakeSummaryInput& in);

/// Why the point gathers (gather, adaptive) cannot tile these options, or "".
std::string pointGatherUntileable(const BakeRequest& request);

}  // namespace vdblight::bake_detail
