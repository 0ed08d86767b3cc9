// Scene building blocks every loader shares: adding materials and triangles (with the
// degenerate-triangle filter), the invariants consumers rely on, the content hash that
// ties a baked volume to its scene, and where the bundled Cornell box lives.
#include "vdblight/scene/scene.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "vdblight/core/errors.h"

namespace vdblight {

namespace {

std::string sceneLabel(const Scene& scene) { return "scene '" + scene.name + "'"; }

std::string formatVec(const Vec3f& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

/// Twice the area is compared with the longest edge squared, so the test is scale-free:
/// a sliver whose sine of its largest angle is below 1e-12 has no usable normal.
bool isDegenerate(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3d e0 = Vec3d(b) - Vec3d(a), e1 = Vec3d(c) - Vec3d(a), e2 = Vec3d(c) - Vec3d(b);
    const double twiceArea = length(cross(e0, e1));
    const double maxEdge2 = std::max(dot(e0, e0), std::max(dot(e1, e1), dot(e2, e2)));
    return twiceArea == 0.0 || twiceArea < 1e-12 * maxEdge2;
}

/// 64-bit FNV-1a fed with fixed-width little-endian values, so the hash is the same on
/// every platform and does not depend on struct padding.
class Fnv1a {
public:
    void byte(uint8_t b) { h_ = (h_ ^ b) * 0x100000001b3ull; }
    void u64(uint64_t v) { for (int i = 0; i < 8; ++i) byte(uint8_t(v >> (8 * i))); }
    void u32(uint32_t v) { for (int i = 0; i < 4; ++i) byte(uint8_t(v >> (8 * i))); }
    void f32(float f) { uint32_t u; std::memcpy(&u, &f, 4); u32(u); }
    void vec(const Vec3f& v) { f32(v.x); f32(v.y); f32(v.z); }
    void str(const std::string& s) { u64(s.size()); for (char c : s) byte(uint8_t(c)); }
    std::string hex() const {
        static const char* digits = "0123456789abcdef";
        std::string out(16, '0');
        for (int i = 0; i < 16; ++i) out[15 - i] = digits[(h_ >> (4 * i)) & 0xf];
        return out;
    }

private:
    uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace

Bounds Scene::bounds() const {
    Bounds b;
    for (uint32_t i : indices) b.extend(Vec3d(positions[i]));
    return b;
}

Bounds Scene::worldBounds() const {
    Bounds b = bounds();
    if (!b.empty()) { b.lo += origin; b.hi += origin; }
    return b;
}

bool Scene::hasEmissiveTriangles() const {
    for (uint32_t id : materialIds)
        if (materials[id].isEmissive()) return true;
    return false;
}

bool Scene::hasLight() const {
    if (hasEmissiveTriangles() || !sky.isBlack()) return true;
    for (const auto& l : pointLights) if (maxComponent(l.intensity) > 0) return true;
    for (const auto& l : spotLights) if (maxComponent(l.intensity) > 0) return true;
    for (const auto& l : directionalLights) if (maxComponent(l.irradiance) > 0) return true;
    return false;
}

/// Covers everything that changes the lighting; names (scene, materials) are left out so
/// that renaming does not invalidate a bake.
std::string Scene::contentHash() const {
    Fnv1a h;
    h.u64(positions.size());
    for (const auto& p : positions) h.vec(p);
    h.u64(indices.size());
    for (uint32_t i : indices) h.u32(i);
    h.u64(materialIds.size());
    for (uint32_t m : materialIds) h.u32(m);
    h.u64(materials.size());
    for (const auto& m : materials) { h.vec(m.albedo); h.vec(m.emission); h.byte(m.twoSidedEmission); }
    h.u64(pointLights.size());
    for (const auto& l : pointLights) { h.vec(l.position); h.vec(l.intensity); }
    h.u64(spotLights.size());
    for (const auto& l : spotLights) {
        h.vec(l.position); h.vec(l.direction); h.vec(l.intensity);
        h.f32(l.innerConeAngle); h.f32(l.outerConeAngle);
    }
    h.u64(directionalLights.size());
    for (const auto& l : directionalLights) { h.vec(l.direction); h.vec(l.irradiance); }
    h.vec(sky.constant);
    h.byte(sky.map ? 1 : 0);
    if (origin != Vec3d(0, 0, 0)) {  // only a moved scene hashes its origin (older hashes stay valid)
        h.str("origin");
        for (int a = 0; a < 3; ++a) { const double d = origin[a]; uint64_t u; std::memcpy(&u, &d, 8); h.u64(u); }
    }
    if (sky.map) {
        h.str(sky.map->path);
        h.u32(uint32_t(sky.map->width)); h.u32(uint32_t(sky.map->height));
        for (const auto& t : sky.map->texels) h.vec(t);
    }
    return h.hex();
}

uint32_t addMaterial(Scene& scene, Material m) {
    if (!isFinite(m.albedo) || !isFinite(m.emission))
        throw SceneError(sceneLabel(scene) + ": material '" + m.name + "' has a non-finite colour");
    // An albedo of 1 would let energy bounce forever in a closed room.
    const Rgb lo{0, 0, 0}, hi{0.999f, 0.999f, 0.999f};
    m.albedo = vmin(vmax(m.albedo, lo), hi);
    m.emission = vmax(m.emission, lo);
    scene.materials.push_back(std::move(m));
    return uint32_t(scene.materials.size() - 1);
}

void addIndexedTriangle(Scene& scene, uint32_t i0, uint32_t i1, uint32_t i2, uint32_t materialId) {
    const std::size_t n = scene.positions.size();
    if (i0 >= n || i1 >= n || i2 >= n)
        throw SceneError(sceneLabel(scene) + ": triangle vertex index out of range (" +
                         std::to_string(n) + " vertices)");
    const Vec3f &a = scene.positions[i0], &b = scene.positions[i1], &c = scene.positions[i2];
    ++scene.stats.inputTriangles;
    if (!isFinite(a) || !isFinite(b) || !isFinite(c))
        throw SceneError(sceneLabel(scene) + ": triangle with non-finite vertex " +
                         formatVec(!isFinite(a) ? a : !isFinite(b) ? b : c));
    if (isDegenerate(a, b, c)) {
        ++scene.stats.degenerateTrianglesSkipped;
        return;
    }
    scene.indices.insert(scene.indices.end(), {i0, i1, i2});
    scene.materialIds.push_back(materialId);
}

void addTriangle(Scene& scene, const Vec3f& a, const Vec3f& b, const Vec3f& c, uint32_t materialId) {
    if (!isFinite(a) || !isFinite(b) || !isFinite(c))
        throw SceneError(sceneLabel(scene) + ": triangle with non-finite vertex " +
                         formatVec(!isFinite(a) ? a : !isFinite(b) ? b : c));
    if (isDegenerate(a, b, c)) {  // do not store vertices nobody references
        ++scene.stats.inputTriangles;
        ++scene.stats.degenerateTrianglesSkipped;
        return;
    }
    const auto first = uint32_t(scene.positions.size());
    scene.positions.insert(scene.positions.end(), {a, b, c});
    addIndexedTriangle(scene, first, first + 1, first + 2, materialId);
}

void validateScene(const Scene& scene) {
    const std::string label = sceneLabel(scene);
    if (scene.triangleCount() == 0) throw SceneError(label + " has no triangles");
    if (scene.indices.size() != 3 * scene.triangleCount())
        throw SceneError(label + ": " + std::to_string(scene.indices.size()) + " indices for " +
                         std::to_string(scene.triangleCount()) + " triangles");
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        if (!isFinite(scene.positions[i]))
            throw SceneError(label + ": vertex " + std::to_string(i) + " is not finite " +
                             formatVec(scene.positions[i]));
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k)
            if (scene.indices[3 * t + k] >= scene.positions.size())
                throw SceneError(label + ": triangle " + std::to_string(t) + " has vertex index " +
                                 std::to_string(scene.indices[3 * t + k]) + " out of range (" +
                                 std::to_string(scene.positions.size()) + " vertices)");
        if (scene.materialIds[t] >= scene.materials.size())
            throw SceneError(label + ": triangle " + std::to_string(t) + " has material id " +
                             std::to_string(scene.materialIds[t]) + " out of range (" +
                             std::to_string(scene.materials.size()) + " materials)");
    }
    for (const auto& l : scene.pointLights)
        if (!isFinite(l.position) || !isFinite(l.intensity))
            throw SceneError(label + ": point light with non-finite position or intensity");
    for (const auto& l : scene.spotLights)
        if (!isFinite(l.position) || !isFinite(l.direction) || !isFinite(l.intensity))
            throw SceneError(label + ": spot light with non-finite position, direction or intensity");
    for (const auto& l : scene.directionalLights)
        if (!isFinite(l.direction) || !isFinite(l.irradiance))
            throw SceneError(label + ": directional light with non-finite direction or irradiance");
}

/// Installed layout first (bin/../share/vdblight/data), then a build tree one level below
/// the source (build/<dir>/exe -> ../../data), then the source tree this was compiled from.
std::string defaultScenePath() {
    namespace fs = std::filesystem;
    const char* fileName = "cornell_box.obj";
    std::vector<fs::path> dirs;
    if (const char* env = std::getenv("VDBLIGHT_DATA_DIR"); env && *env) dirs.emplace_back(env);
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        dirs.push_back(exe.parent_path() / ".." / "share" / "vdblight" / "data");
        dirs.push_back(exe.parent_path() / ".." / ".." / "data");
    }
#ifdef VDBLIGHT_SOURCE_DATA_DIR
    dirs.emplace_back(VDBLIGHT_SOURCE_DATA_DIR);
#endif
    std::string searched;
    for (const auto& dir : dirs) {
        const fs::path candidate = (dir / fileName).lexically_normal();
        if (fs::is_regular_file(candidate, ec)) return candidate.string();
        searched += (searched.empty() ? "" : ", ") + candidate.string();
    }
    throw IoError(std::string("default scene '") + fileName + "' not found (searched: " + searched +
                  "); set VDBLIGHT_DATA_DIR to the folder that holds it");
}

}  // namespace vdblight
