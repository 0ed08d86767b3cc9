#include "app_common.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"

namespace vdblight::app {

namespace fs = std::filesystem;

void addSceneOptions(CLI::App& cmd, SceneOptions& o) {
    addSceneFileOptions(cmd, o);
    cmd.add_option("--sky", o.sky, "Constant sky radiance r,g,b in W/(m^2 sr) where rays escape (default 0,0,0)");
    cmd.add_option("--sky-map", o.skyMap, "Equirectangular EXR sky (radiance), +Y up; overrides --sky");
    cmd.add_option("--bounces", o.bounces,
                   "Cap on diffuse reflections per light path (0 = direct light only). Russian roulette ends "
                   "paths without bias; the default cap is a safety that no path reaches, a smaller one drops "
                   "the light of later bounces")
        ->check(CLI::Range(0, 1 << 20))
        ->capture_default_str();
    cmd.add_flag("--allow-dark", o.allowDark, "Bake even if the scene has no light (the result is black)");
}

void addSceneFileOptions(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("scene", o.path,
                   "Scene file: glTF (.gltf .glb), OBJ, PLY, FBX (binary, ascii), COLLADA (.dae), 3DS, STL, OFF, .x "
                   "or any other format Assimp reads (docs/scene.md); the summary names the format and the "
                   "meshes/instances read. Default: the bundled Cornell box");
    addSceneFrameOptions(cmd, o);
}

void addSceneFrameOptions(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("--scale", o.scale,
                   "Metres per file unit, overriding the file's unit (FBX UnitScaleFactor, COLLADA <unit>); "
                   "default: the file's unit, or 1 where the format has none")
;
    cmd.add_option("--up", o.up, "The file's up axis, y or z, overriding its metadata (FBX, COLLADA); default: "
                                 "the metadata, or y where the format has none. Scenes are +Y up");
}

Scene loadSceneFile(const std::string& path, const SceneOptions& frame, bool quiet, SceneLoadReport* report) {
    SceneLoadOptions load;
    if (!frame.scale.empty()) {  // checked here, so that a bad value is one line like every other error
        std::size_t used = 0;
        double s = 0;
        try { s = std::stod(frame.scale, &used); } catch (const std::exception&) { used = 0; }
        if (used != frame.scale.size() || !(std::isfinite(s) && s > 0))
            throw ValueError("--scale must be a positive number of metres per file unit, got '" + frame.scale + "'");
        load.scale = s;
    }
    if (!frame.up.empty() && frame.up != "y" && frame.up != "z")
        throw ValueError("--up must be y or z, got '" + frame.up + "'");
    load.up = frame.up == "z" ? UpAxis::Z : frame.up == "y" ? UpAxis::Y : UpAxis::FromFile;
    SceneLoadReport local;
    SceneLoadReport& read = report ? *report : local;
    Scene scene = loadScene(path, load, &read);
    if (!quiet)
        for (const std::string& w : read.warnings) std::cerr << "vdblight: warning: " << w << "\n";
    return scene;
}

Scene loadSceneFromOptions(const SceneOptions& o, bool quiet, SceneLoadReport* report) {
    Scene scene = loadSceneFile(o.path.empty() ? defaultScenePath() : o.path, o, quiet, report);
    if (!o.sky.empty()) {
        const Vec3d c = parseTriple(o.sky, "--sky");
        if (c.x < 0 || c.y < 0 || c.z < 0) throw ValueError("--sky radiance must not be negative");
        scene.sky.constant = Rgb(c);
    }
    if (!o.skyMap.empty()) scene.sky.map = loadSkyMap(o.skyMap);
    if (!scene.hasLight() && !o.allowDark)
        throw SceneError("scene '" + scene.name +
                         "' has no light (no emissive material, punctual light or sky): the volume would be black; "
                         "add --sky r,g,b or pass --allow-dark");
    if (!quiet && scene.stats.degenerateTrianglesSkipped > 0)
        std::cerr << "vdblight: warning: skipped " << scene.stats.degenerateTrianglesSkipped
                  << " degenerate triangles\n";
    return scene;
}

TransportOptions transportFromOptions(const SceneOptions& o) {
    TransportOptions t;
    t.maxBounces = o.bounces;
    return t;
}

Vec3d parseTriple(const std::string& text, const char* what) {
    std::vector<double> v;
    try {
        v = parseNumberList(text);
    } catch (const ValueError& e) {
        throw ValueError(std::string(what) + ": " + e.what());
    }
    if (v.size() != 3) throw ValueError(std::string(what) + " needs three comma-separated numbers, got '" + text + "'");
    return {v[0], v[1], v[2]};
}

Bounds parseBounds(const std::string& text) {
    std::vector<double> v;
    try {
        v = parseNumberList(text);
    } catch (const ValueError& e) {
        throw ValueError(std::string("--bounds: ") + e.what());
    }
    if (v.size() != 6) throw ValueError("--bounds needs six numbers x0,y0,z0,x1,y1,z1, got '" + text + "'");
    Bounds b;
    b.lo = {v[0], v[1], v[2]};
    b.hi = {v[3], v[4], v[5]};
    if (!(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z))
        throw ValueError("--bounds must have x0 < x1, y0 < y1 and z0 < z1");
    return b;
}

void checkOutputWritable(const std::string& path) {
    if (path.empty()) throw IoError("no output path given");
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) throw IoError("cannot write '" + path + "': it is a directory");
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec)) throw IoError("cannot write '" + path + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw IoError("cannot write '" + path + "': directory '" + dir.string() + "' is not writable");
}

void emitText(const std::string& path, const std::string& text) {
    if (path.empty()) {
        std::cout << text;
        return;
    }
    writeFileAtomically(path, text);
}

namespace {
std::atomic<bool> gInterrupted{false};
extern "C" void onSignal(int) { gInterrupted = true; }
}  // namespace

void installInterruptHandler() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}
bool interruptRequested() { return gInterrupted.load(); }

}  // namespace vdblight::app
