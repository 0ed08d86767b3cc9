// Windowing of SH order-2 coefficients against ringing (issue 8).
//
// The order-2 irradiance of a single direction of light (a delta) is, with c the cosine
// between the normal and the light, E(c) = 1/4 + c/2 + (5/16)(3c^2 - 1)/2 (per unit
// irradiance): it dips to -0.040 at c = -0.53, so a strong directional light gives negative
// irradiance behind it. Irradiance is linear in the radiance and every non-negative radiance
// is a sum of deltas, so a window that makes the delta's response non-negative makes every
// non-negative radiance's irradiance non-negative.
//
// The window: band l multiplied by w_l = 1 / (1 + lambda l^2 (l+1)^2) (a spline window),
// with the smallest lambda for which the delta's response is >= 0 on [-1, 1]:
// lambda = 0.177732, w = (1, 0.584478, 0.135165). It blurs the lighting; its error cost is
// printed by tests/stress_test.cpp.
#pragma once

#include "vdblight/volume/volume.h"

namespace vdblight {

namespace sh {
constexpr double kNonNegativeWindowLambda = 0.17773185154477653;
constexpr double kNonNegativeWindow[3] = {1.0, 0.5844783340242528, 0.1351653344388044};
}  // namespace sh

/// Multiplies the bands of every node of an SH order-2 volume by sh::kNonNegativeWindow and
/// records it in the metadata (`sh_window`). Throws ValueError for a non-SH volume or one
/// already windowed.
void applyShWindow(Volume& volume);

}  // namespace vdblight
