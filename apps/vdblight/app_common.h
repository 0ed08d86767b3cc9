// Shared pieces of the vdblight subcommands: option parsing helpers, scene set-up,
// Ctrl-C handling and CSV points. Each subcommand lives in its own cmd_*.cpp file.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <string>
#include <vector>

#include "vdblight/core/interrupter.h"
#include "vdblight/light/light.h"
#include "vdblight/core/math.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"

namespace vdblight::app {

/// Options every command that loads a scene shares.
struct SceneOptions {
    std::string path;              ///< empty: the bundled default scene
    std::string sky;               ///< "r,g,b" constant sky radiance
    std::string skyMap;            ///< equirectangular EXR
    bool allowDark = false;
    int bounces = kSafetyBounces;  ///< a safety cap: Russian roulette ends paths (light.h)
    std::string scale;             ///< --scale: metres per file unit (empty: the file's unit)
    std::string up;                ///< --up: y | z (empty: the file's metadata)
};

void addSceneOptions(CLI::App& cmd, SceneOptions& o);
/// The scene positional argument, --scale and --up alone (for commands without lighting options).
void addSceneFileOptions(CLI::App& cmd, SceneOptions& o);
/// --scale and --up alone (for commands that take scene files as options).
void addSceneFrameOptions(CLI::App& cmd, SceneOptions& o);
/// Loads `path` with the --scale / --up of `frame` and prints its warnings unless quiet.
Scene loadSceneFile(const std::string& path, const SceneOptions& frame, bool quiet, SceneLoadReport* report = nullptr);
/// Loads the scene (--scale, --up), prints its warnings unless quiet, applies sky options,
/// refuses a scene without light unless allowed. `report`, if given, says how it was read.
Scene loadSceneFromOptions(const SceneOptions& o, bool quiet, SceneLoadReport* report = nullptr);
TransportOptions transportFromOptions(const SceneOptions& o);

/// "x,y,z" -> three numbers (ValueError naming `what` otherwise).
Vec3d parseTriple(const std::string& text, const char* what);
/// "x0,y0,z0,x1,y1,z1" -> a box with lo < hi.
Bounds parseBounds(const std::string& text);

/// Checks before any long work that `path` can be created (its directory exists and is
/// writable, and it is not a directory). Throws IoError.
void checkOutputWritable(const std::string& path);

/// Writes `text` to stdout if `path` is empty, else atomically to `path` (a temporary file
/// in the same directory, then renamed): a failure never leaves a partial file.
void emitText(const std::string& path, const std::string& text);

/// Installs a SIGINT/SIGTERM handler that only sets a flag, read by the interrupter.
void installInterruptHandler();
bool interruptRequested();

/// The library's progress bar (TerminalProgress, interrupter.h), cancelled by Ctrl-C.
class ProgressBar : public TerminalProgress {
public:
    explicit ProgressBar(bool quiet) : TerminalProgress(quiet, interruptRequested) {}
};

}  // namespace vdblight::app
