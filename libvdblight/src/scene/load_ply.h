// vdblight's own PLY reader (replaces Assimp for .ply, whose 5.2.5 importer crashes or hangs
// on some corrupt files: docs/measurements/robustness.md, "Sanitizers and fuzzing").
#pragma once

#include <string>

#include "vdblight/scene/scene.h"

namespace vdblight {

/// Reads a PLY file (ascii 1.0, binary_little_endian 1.0, binary_big_endian 1.0): the x, y, z
/// of element "vertex" and the list "vertex_indices" (or "vertex_index") of element "face",
/// polygons fan-triangulated, one default grey material; everything else is skipped. Header
/// lines with an unknown keyword are skipped with a warning (report.warnings) unless they
/// could declare data. Coordinates are scaled and rotated as `options` say (file_frame.h).
/// Validated, recentred like loadScene. Every count and size is checked against the bytes
/// left in the file before anything is allocated. Throws SceneError (one line, naming the
/// file) on any malformed input.
Scene loadPlyScene(const std::string& path, const SceneLoadOptions& options, SceneLoadReport& report);

}  // namespace vdblight
