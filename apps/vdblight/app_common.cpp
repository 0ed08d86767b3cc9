#include "app_common.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

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

std::string describeSceneSource(const SceneLoadReport& s) {
    std::ostringstream out;
    out << s.format << ": " << s.meshes << (s.meshes == 1 ? " mesh" : " meshes") << " in " << s.meshInstances
        << (s.meshInstances == 1 ? " instance" : " instances") << ", " << s.units << ", up axis " << s.up;
    if (s.defaultAlbedoOnly) out << ", no materials: default albedo 0.8";
    return out.str();
}

TransportOptions transportFromOptions(const SceneOptions& o) {
    TransportOptions t;
    t.maxBounces = o.bounces;
    return t;
}

namespace {
std::vector<double> parseNumbers(const std::string& text) {
    std::vector<double> values;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        std::size_t used = 0;
        double v;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            throw ValueError("'" + item + "' is not a number");
        }
        while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
        if (used != item.size()) throw ValueError("'" + item + "' is not a number");
        if (!std::isfinite(v)) throw ValueError("'" + item + "' is not a finite number");
        values.push_back(v);
    }
    return values;
}
}  // namespace

Vec3d parseTriple(const std::string& text, const char* what) {
    std::vector<double> v;
    try {
        v = parseNumbers(text);
    } catch (const ValueError& e) {
        throw ValueError(std::string(what) + ": " + e.what());
    }
    if (v.size() != 3) throw ValueError(std::string(what) + " needs three comma-separated numbers, got '" + text + "'");
    return {v[0], v[1], v[2]};
}

Bounds parseBounds(const std::string& text) {
    std::vector<double> v;
    try {
        v = parseNumbers(text);
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

std::vector<ReferencePoint> readPointsCsv(const std::string& path, std::vector<Vec3d>* worldPositions) {
    std::ifstream in(path);
    if (!in) throw IoError("cannot read points file '" + path + "'");
    std::vector<ReferencePoint> points;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        std::vector<double> v;
        try {
            v = parseNumbers(line);
        } catch (const ValueError& e) {
            if (points.empty() && lineNo == 1) continue;  // a header line
            throw ValueError(path + ":" + std::to_string(lineNo) + ": " + e.what());
        }
        if (v.size() != 6)
            throw ValueError(path + ":" + std::to_string(lineNo) + ": expected x,y,z,nx,ny,nz (6 numbers), got " +
                             std::to_string(v.size()));
        ReferencePoint p;
        p.position = Vec3f(float(v[0]), float(v[1]), float(v[2]));
        p.normal = Vec3f(float(v[3]), float(v[4]), float(v[5]));
        if (!(length(p.normal) > 0))
            throw ValueError(path + ":" + std::to_string(lineNo) + ": the normal is zero");
        points.push_back(p);
        if (worldPositions) worldPositions->emplace_back(v[0], v[1], v[2]);
    }
    if (points.empty()) throw ValueError("points file '" + path + "' has no rows");
    return points;
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

double nowSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

void installInterruptHandler() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
}
bool interruptRequested() { return gInterrupted.load(); }

ProgressBar::ProgressBar(bool quiet) : enabled_(!quiet && ::isatty(STDERR_FILENO)) {}

void ProgressBar::start(const char* task, uint64_t total) {
    task_ = task;
    total_ = total;
    startTime_ = nowSeconds();
    lastDraw_ = 0;
    if (enabled_) draw(0, false);
}

void ProgressBar::progress(uint64_t done) {
    if (!enabled_) return;
    const double now = nowSeconds();
    double last = lastDraw_.load();
    if (now - last < 0.2 && done < total_) return;  // at most five redraws a second
    if (!lastDraw_.compare_exchange_strong(last, now)) return;
    bool expected = false;
    if (!drawing_.compare_exchange_strong(expected, true)) return;
    draw(done, false);
    drawing_ = false;
}

bool ProgressBar::wasInterrupted() { return interruptRequested(); }

void ProgressBar::end() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void ProgressBar::draw(uint64_t done, bool) {
    const double fraction = total_ ? double(done) / double(total_) : 1.0;
    const double elapsed = nowSeconds() - startTime_;
    const int width = 30;
    const int filled = int(fraction * width);
    std::string bar(std::size_t(filled), '#');
    bar.resize(width, '.');
    std::string eta = fraction > 0.001 ? formatSeconds(elapsed / fraction - elapsed) : "?";
    std::fprintf(stderr, "\r\033[K%s [%s] %5.1f%%  %s/%s  ETA %s", task_, bar.c_str(), 100.0 * fraction,
                 formatCount(double(done)).c_str(), formatCount(double(total_)).c_str(), eta.c_str());
    std::fflush(stderr);
}

std::string formatSeconds(double s) {
    char buf[64];
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s) / 3600, (int(s) % 3600) / 60);
    return buf;
}

std::string formatCount(double n) {
    char buf[64];
    if (n >= 1e9) std::snprintf(buf, sizeof buf, "%.2f G", n / 1e9);
    else if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.2f M", n / 1e6);
    else if (n >= 1e4) std::snprintf(buf, sizeof buf, "%.1f k", n / 1e3);
    else std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}

std::string formatBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024 && u < 4) {
        bytes /= 1024;
        ++u;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
    return buf;
}

}  // namespace vdblight::app
