// The default bake's grid rule (issue 15): a node budget instead of a fixed count on the
// longest axis, so that an elongated scene (two rooms side by side, a corridor) gets the
// same spacing on every axis and as many nodes as a cube of the same volume.
#pragma once

#include <cstdint>

#include "vdblight/math.h"

namespace vdblight {

/// The nodes on the longest axis that a node budget's grid stays between.
constexpr int kBudgetMinNodesOnLongestAxis = 16;
constexpr int kBudgetMaxNodesOnLongestAxis = 64;
/// The grid of a bake without a node budget, resolution or spacing: nodes on the longest axis.
constexpr int kDefaultResolution = 16;

/// The spacing that puts about `nodes` nodes in `box` (placeUniformGrid, layout.h):
/// (volume / nodes)^(1/3), each extent counted as at least 1/16 of the longest (a flat scene
/// is not given a vanishing spacing), then kept between longest / 64 and longest / 16, so the
/// grid has 16..64 nodes on its longest axis whatever the shape. Throws ValueError for an
/// empty or non-finite box or nodes = 0.
double spacingForNodeBudget(const Bounds& box, uint64_t nodes);

}  // namespace vdblight
