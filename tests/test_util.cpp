#include "test_util.h"

#include <gtest/gtest.h>

#include "vdblight/scene/scene.h"

#include <sstream>

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#include "support/scene_generators.h"

namespace vdblight::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
    std::random_device rd;
    for (int attempt = 0; attempt < 100; ++attempt) {
        fs::path p = fs::temp_directory_path() /
                     ("vdblight_test_" + std::to_string(::getpid()) + "_" + std::to_string(rd()));
        std::error_code ec;
        if (fs::create_directory(p, ec)) {
            path_ = p;
            return;
        }
    }
    throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

void writeTextFile(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + path);
}

std::string readTextFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

int runCommand(const std::string& command, std::string* output) {
    std::string full = command + " 2>&1";
    FILE* pipe = ::popen(full.c_str(), "r");
    if (!pipe) return -1;
    std::array<char, 4096> buf;
    std::string text;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) text.append(buf.data(), n);
    const int status = ::pclose(pipe);
    if (output) *output = text;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

namespace {
Scene singleMaterialScene(const char* name, const Rgb& albedo, const Rgb& emission) {
    Scene scene;
    scene.name = name;
    Material m;
    m.name = name;
    m.albedo = albedo;
    m.emission = emission;
    scene.materials.push_back(m);
    return scene;
}
}  // namespace

Scene makeEmissiveDisk(float radius, const Rgb& radiance, int segments, float* effectiveRadius) {
    Scene scene = singleMaterialScene("emissive_disk", {0, 0, 0}, radiance);
    const double r = appendDisk(scene, {0, 0, 0}, radius, segments, 0);
    if (effectiveRadius) *effectiveRadius = float(r);
    return scene;
}

Scene makeEmissiveSphere(float radius, const Rgb& radiance, int subdivisions, float* effectiveRadius) {
    Scene scene = singleMaterialScene("emissive_sphere", {0, 0, 0}, radiance);
    const double r = appendIcosphere(scene, {0, 0, 0}, radius, subdivisions, 0);
    if (effectiveRadius) *effectiveRadius = float(r);
    return scene;
}

Scene makeFurnaceBox(const Vec3f& lo, const Vec3f& hi, const Rgb& emission, const Rgb& albedo) {
    Scene scene = singleMaterialScene("furnace", albedo, emission);
    appendBox(scene, lo, hi, /*inward=*/true, 0);
    return scene;
}

Scene makeConstantSky(const Rgb& L) {
    Scene s;
    s.name = "sky";
    Material m;
    m.albedo = {0, 0, 0};
    addMaterial(s, m);
    addTriangle(s, {1e4f, 0, 0}, {1e4f, 1e-3f, 0}, {1e4f, 0, 1e-3f}, 0);
    s.sky.constant = L;
    return s;
}

std::string writeMovedCornell(const TempDir& dir, const std::string& name, double scale, const double offset[3]) {
    const std::string obj = defaultScenePath();
    std::ifstream in(obj);
    std::ostringstream out;
    out.precision(17);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0) {
            std::istringstream v(line.substr(2));
            double x, y, z;
            v >> x >> y >> z;
            out << "v " << x * scale + offset[0] << ' ' << y * scale + offset[1] << ' ' << z * scale + offset[2] << '\n';
        } else {
            out << line << '\n';
        }
    }
    writeTextFile(dir.file(name + ".obj"), out.str());
    std::ifstream mtl(obj.substr(0, obj.size() - 4) + ".mtl");
    std::ostringstream m;
    m << mtl.rdbuf();
    writeTextFile(dir.file("cornell_box.mtl"), m.str());
    return dir.file(name + ".obj");
}

void expectWhiteFurnace(const std::vector<Vec3f>& points, const std::function<Rgb(const Vec3f&, const Vec3f&)>& irradiance,
                        const Rgb& emission, float albedo, double tolerance) {
    for (std::size_t i = 0; i < points.size(); ++i)
        for (const Vec3f n : {Vec3f(0, 0, 1), Vec3f(-1, 0, 0), normalize(Vec3f(1, -2, 3))}) {
            const Rgb e = irradiance(points[i], n);
            for (int c = 0; c < 3; ++c) {
                const double want = kPi * emission[c] / (1.0 - albedo);
                EXPECT_NEAR(e[c], want, tolerance * want) << "point " << i << " channel " << c;
            }
        }
}

}  // namespace vdblight::test
