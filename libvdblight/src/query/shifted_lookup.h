// Lookups of volumes far from the world origin (docs/scene.md, "Large coordinates").
#pragma once

#include <memory>

#include "vdblight/query/query.h"

namespace vdblight {

/// `create(volume, outside)`, except for a volume whose node box lies far from the origin
/// (recenteringAnchor(box) != 0): the lookup is then built on a copy whose grids are moved by
/// minus that anchor, and wrapped so that every point (float or double) is moved the same
/// way in double before the lookup sees it. Near the origin nothing changes.
std::unique_ptr<VolumeLookup> createAnchored(const Volume& volume, OutsidePolicy outside,
                                             std::unique_ptr<VolumeLookup> (*create)(const Volume&, OutsidePolicy));

/// Wraps `inner`, built on grids moved by minus `anchor`, as createAnchored does (for
/// lookups not built from a Volume, such as the streamed one of query_stream.h).
std::unique_ptr<VolumeLookup> shiftLookup(std::unique_ptr<VolumeLookup> inner, const Vec3d& anchor);

}  // namespace vdblight
