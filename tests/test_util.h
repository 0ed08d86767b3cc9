// Helpers shared by the tests: a self-removing temporary directory and generators of
// scenes whose lighting has a closed form.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "vdblight/scene/scene.h"

namespace vdblight::test {

/// A fresh directory under the system temp directory, removed with its contents when the
/// object goes out of scope. Tests never write into the working directory.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

/// Writes `text` to `path` (throws on failure).
void writeTextFile(const std::string& path, const std::string& text);
/// The whole file at `path` (throws if it cannot be read).
std::string readTextFile(const std::string& path);

/// Runs a shell command, returns its exit status; stdout+stderr are captured in `output`.
int runCommand(const std::string& command, std::string* output = nullptr);

/// A flat disk of radius R in the plane z = 0 centred at the origin, emitting radiance
/// `radiance` towards +z only, tessellated into `segments` triangles (fan).
/// Its irradiance at (0, 0, h) facing -z is pi L sin^2(alpha), tan(alpha) = R_eff / h,
/// where R_eff (returned through effectiveRadius) is the radius of the circle with the
/// polygon's area (exact to O(segments^-4) on the axis).
Scene makeEmissiveDisk(float radius, const Rgb& radiance, int segments, float* effectiveRadius = nullptr);

/// A sphere of radius R at the origin emitting `radiance` outwards (geodesic tessellation
/// with `subdivisions` levels of an icosahedron). From distance d > R its irradiance facing
/// the centre is pi L (R/d)^2 (up to tessellation; the effective radius is returned).
Scene makeEmissiveSphere(float radius, const Rgb& radiance, int subdivisions, float* effectiveRadius = nullptr);

/// A closed axis-aligned box [lo, hi] whose every face emits `emission` inwards and reflects
/// `albedo` (white furnace: E = pi Le / (1 - rho) everywhere inside).
Scene makeFurnaceBox(const Vec3f& lo, const Vec3f& hi, const Rgb& emission, const Rgb& albedo);

/// The furnace's answer at each of `points` for three normals (+z, -x and an oblique one):
/// every channel of irradiance(x, n) within `tolerance` (relative) of pi Le / (1 - albedo).
/// Constant radiance is band-limited, so an SH volume of any order has no truncation error.
void expectWhiteFurnace(const std::vector<Vec3f>& points, const std::function<Rgb(const Vec3f&, const Vec3f&)>& irradiance,
                        const Rgb& emission, float albedo, double tolerance);

/// A constant sky of radiance L and one tiny, far, black triangle (a scene needs a triangle):
/// no ray of a bake near the origin can hit it (solid angle ~1e-14 sr), so E = pi L.
Scene makeConstantSky(const Rgb& L);

/// Copies the bundled Cornell box (OBJ + MTL) into `dir` as NAME.obj with every vertex scaled
/// by `scale` and moved by `offset`; returns the OBJ's path.
std::string writeMovedCornell(const TempDir& dir, const std::string& name, double scale, const double offset[3]);

}  // namespace vdblight::test
