// Generated scenes in which point sampling leaks darkness out of walls (Kontkanen & Laine,
// section 8), with their exact domain of interest, for tests and the leak benchmark (test
// scenes, tests/support: not part of the installed library).
//
// Every solid is a closed axis-aligned box with front faces outwards; an enclosing room is
// a closed box with front faces inwards. The domain of interest is then exactly: inside
// `open` and outside every box of `solids`.
#pragma once

#include <vector>

#include "vdblight/core/math.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

struct LeakScene {
    Scene scene;
    Bounds open;                ///< the open space (room interior, or the air above the ground)
    std::vector<Bounds> solids; ///< closed solid boxes inside `open`
    /// Which faces of `open` are surfaces (bit 2a: the low side of axis a, bit 2a + 1: the
    /// high side): all six for a room, only the ground (bit 2) for the town under the sky.
    unsigned openSurfaces = 0x3f;

    /// True if p is in the domain of interest (strictly inside `open`, outside every solid).
    bool inDomain(const Vec3d& p) const;
    /// Distance from p (in the domain) to the nearest surface: a face of `open` that is a
    /// surface (openSurfaces) or a solid.
    double distanceToSurface(const Vec3d& p) const;
};

/// A closed room [0,4]x[0,2]x[0,2] split at x = 2 by a wall 0.1 thick with a door
/// (0.8 wide, 1.4 high); an emissive ceiling panel lights the x < 2 side only.
LeakScene makeThinWallScene();

/// A small town: a ground plane (front face up) with closed blocks of different heights
/// under a constant sky and a sun (directional light). `open` is the air above the ground.
LeakScene makeTownScene();

/// A closed room with an emissive ceiling panel and a "bed": a row of thin bars 0.06 thick
/// and a slab on top of them.
LeakScene makeBarsScene();

/// A maze of closed walls: a closed room [0,4]x[0,1.2]x[0,4] lit by a point light, with
/// closed box walls 0.1 thick forming a serpentine corridor (four long walls attached
/// alternately to the x = 0 and x = 4 room walls), a short cross wall, a free-standing
/// wall segment and a lintel hanging from the ceiling. No two walls touch; walls reaching a
/// room face go 0.01 into it, so no wall face is coplanar with a room face. With
/// `crack` > 0 every wall is built by appendCrackedBox (faces shrunk by `crack`), the room
/// stays closed; `solids` are the walls' boxes either way.
LeakScene makeMazeScene(float crack = 0.0f);

/// `count` evaluation points for leak measurements: uniformly random in `box`, kept if in
/// the domain of interest and within `maxDistance` of a surface; each with a uniformly
/// random unit normal. Deterministic in `seed`. Throws ValueError if too few points qualify.
struct EvalPoint {
    Vec3f position;
    Vec3f normal;
};
std::vector<EvalPoint> leakEvalPoints(const LeakScene& scene, const Bounds& box, double maxDistance, int count,
                                      uint64_t seed);

/// Appends a box of six separate faces, each shrunk by `gap` at its edges so that cracks
/// of width about `gap` open along the box's edges (section 7); front faces outwards.
void appendCrackedBox(Scene& scene, const Vec3f& lo, const Vec3f& hi, float gap, uint32_t materialId);

}  // namespace vdblight
