// Loading a scene file with options (unit, up axis) and a report of how it was read
// (format, meshes and instances, unit, up axis, warnings). docs/scene.md, "Formats".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "vdblight/scene.h"

namespace vdblight {

/// The up axis of a file's coordinates. vdblight's scenes are +Y up (docs/scene.md).
enum class UpAxis { FromFile, Y, Z };

/// How loadScene reads a file's coordinates.
struct SceneLoadOptions {
    /// > 0: metres per file unit, overriding the file's own unit (FBX UnitScaleFactor,
    /// COLLADA <unit meter>). 0: the file's unit, or 1 where the format has none.
    double scale = 0.0;
    /// Y or Z: the file's up axis, overriding its metadata (FBX GlobalSettings, COLLADA
    /// <up_axis>). FromFile: the metadata, or Y where the format has none.
    UpAxis up = UpAxis::FromFile;
};

/// How a file was read.
struct SceneLoadReport {
    std::string format;              ///< e.g. "FBX (binary)", "COLLADA", "STL (ascii)"
    std::size_t meshes = 0;          ///< distinct meshes with triangles
    std::size_t meshInstances = 0;   ///< placements of those meshes by the node hierarchy
    double metresPerUnit = 1.0;      ///< scale applied to the file's coordinates
    std::string units;               ///< e.g. "1 unit = 0.01 m (FBX UnitScaleFactor 1 cm)"
    std::string up;                  ///< the file's up axis and its source, e.g. "Z (COLLADA <up_axis>)"
    bool defaultAlbedoOnly = false;  ///< no material of the file was used: every surface has albedo 0.8
    std::vector<std::string> warnings;  ///< one line each: what was read in spite of a problem
};

/// Loads a scene: every format Assimp 5.2 reads (glTF 2.0, OBJ+MTL, FBX, COLLADA, 3DS, STL,
/// OFF, .x, ...: supportedSceneExtensions()) through Assimp, PLY (ascii, binary little/big-endian)
/// through vdblight's own reader (docs/scene.md, "PLY"). Converts to metres and +Y up as the
/// file says or `options` override; applies node transforms (instancing included),
/// triangulates, joins identical vertices, drops degenerate faces (counted in
/// Scene::stats). A diffuse texture's mean colour is the albedo where the texture is a PNG.
/// A scene far from the world origin is recentred (recenterScene). Problems that do not stop
/// the load (an unknown PLY header line, a missing OBJ material library, unread textures)
/// are in `report->warnings`. Throws SceneError / IoError / ValueError
/// (a bad option) with a one-line message.
Scene loadScene(const std::string& path, const SceneLoadOptions& options, SceneLoadReport* report = nullptr);

/// How the scene file was read, for summaries: "FBX (binary): 3 meshes in 4 instances,
/// 1 unit = 0.01 m (FBX UnitScaleFactor 1 cm), up axis Z (FBX UpAxis)".
std::string describeSceneSource(const SceneLoadReport& report);

/// The file extensions loadScene reads, lower case with the dot, sorted (".3ds", ".dae", ...).
std::vector<std::string> supportedSceneExtensions();

}  // namespace vdblight
