// A generated office, like the one of Greger et al. (section 4, figures 10-12): a room with
// desks, chairs, monitors, a yellow divider, book shelves, a plant, a ceiling light panel and a
// desk lamp. The walls are tessellated so that the scene has tens of thousands of triangles
// (about 53 000 at detail 1), as an office model from a modeller would. A test scene
// (tests/support), for tests and benchmarks; not part of the installed library.
#pragma once

#include "vdblight/scene/scene.h"

namespace vdblight {

/// Builds the office in metres: the room is [0, 6] x [0, 3] x [0, 5] (y up). `detail` >= 1
/// scales the wall tessellation (cells of 0.1 / detail m). Deterministic (no randomness
/// beyond a fixed-seed hash for the book colours). Throws ValueError for detail < 1 or > 8.
Scene makeOfficeScene(int detail = 1);

}  // namespace vdblight
