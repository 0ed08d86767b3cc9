// From a file's coordinates to a Scene's: metres and +Y up (docs/scene.md, "Units and axes").
// Shared by the Assimp path and the PLY reader, so that --scale and --up mean the same thing
// for every format.
#pragma once

#include <string>

#include "vdblight/core/math.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

/// A rotation (a signed axis permutation) times a uniform scale: scene = m * file.
struct FileFrame {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    Vec3f apply(const Vec3f& p) const {
        const double x = p.x, y = p.y, z = p.z;
        return {float(m[0][0] * x + m[0][1] * y + m[0][2] * z), float(m[1][0] * x + m[1][1] * y + m[1][2] * z),
                float(m[2][0] * x + m[2][1] * y + m[2][2] * z)};
    }
};

/// `metresPerUnit` times, if `zUp`, the rotation of a Z-up right-handed file into Y-up:
/// (x, y, z) -> (x, z, -y) (Blender's, 3ds Max's and most CAD files' Z becomes our Y).
FileFrame makeFileFrame(double metresPerUnit, bool zUp);

/// Refuses a --scale that is not 0 (= the file's unit) or a finite positive number.
void checkLoadOptions(const SceneLoadOptions& options);

/// "1 unit = 0.01 m" style text for SceneStats::units.
std::string describeUnit(double metresPerUnit);

}  // namespace vdblight
