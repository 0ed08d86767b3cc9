// Small helpers the benchmark programs share: wall-clock time, the uniform grid of a given
// resolution over a box, and the free-space test for evaluation points.
#pragma once

#include <chrono>

#include "vdblight/layout.h"
#include "vdblight/trace.h"

namespace vdblight::bench {

/// Wall-clock seconds (steady clock).
inline double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// placeUniformGrid over `box` with `resolution` nodes along its longest axis.
inline GridSpec uniformGrid(const Bounds& box, int resolution) {
    GridPlacement p;
    p.resolution = resolution;
    return placeUniformGrid(box, p, 1);
}

/// A point is in free space if rays along the six axis directions first hit front faces
/// (or nothing): inside a closed solid some ray meets a back face first.
inline bool freeSpace(const Tracer& tracer, const Vec3f& x) {
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3f& d : dirs) {
        Ray r;
        r.origin = x;
        r.direction = d;
        const Hit h = tracer.intersect(r);
        if (h.hit() && dot(h.geometricNormal, d) > 0) return false;
    }
    return true;
}

}  // namespace vdblight::bench
