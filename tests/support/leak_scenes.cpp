// Generated leak scenes (leak_scenes.h): closed boxes as solids, closed rooms around them.
#include "support/leak_scenes.h"

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"

#include "support/scene_generators.h"

namespace vdblight {

namespace {
Bounds box(Vec3d lo, Vec3d hi) {
    Bounds b;
    b.lo = lo;
    b.hi = hi;
    return b;
}

uint32_t material(Scene& s, const char* name, Rgb albedo, Rgb emission = {0, 0, 0}) {
    Material m;
    m.name = name;
    m.albedo = albedo;
    m.emission = emission;
    return addMaterial(s, m);
}

/// A horizontal quad at height y over [x0,x1] x [z0,z1], front face up or down.
void horizontalQuad(Scene& s, float y, float x0, float x1, float z0, float z1, bool up, uint32_t mat) {
    const Vec3f a{x0, y, z0}, b{x1, y, z0}, c{x1, y, z1}, d{x0, y, z1};
    // (b - a) x (c - a) = (+x) x (+x+z) points along -y.
    if (up) {
        addTriangle(s, a, c, b, mat);
        addTriangle(s, a, d, c, mat);
    } else {
        addTriangle(s, a, b, c, mat);
        addTriangle(s, a, c, d, mat);
    }
}

void addSolid(LeakScene& l, Vec3d lo, Vec3d hi, uint32_t mat) {
    appendBox(l.scene, Vec3f(lo), Vec3f(hi), /*inward=*/false, mat);
    l.solids.push_back(box(lo, hi));
}

double distanceToBox(const Vec3d& p, const Bounds& b) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double d = std::max({b.lo[a] - p[a], 0.0, p[a] - b.hi[a]});
        d2 += d * d;
    }
    return std::sqrt(d2);
}
}  // namespace

bool LeakScene::inDomain(const Vec3d& p) const {
    for (int a = 0; a < 3; ++a)
        if (!(p[a] > open.lo[a] && p[a] < open.hi[a])) return false;
    for (const Bounds& s : solids)
        if (s.contains(p)) return false;
    return true;
}

double LeakScene::distanceToSurface(const Vec3d& p) const {
    double d = std::numeric_limits<double>::max();
    for (int a = 0; a < 3; ++a) {
        if (openSurfaces >> (2 * a) & 1) d = std::min(d, p[a] - open.lo[a]);
        if (openSurfaces >> (2 * a + 1) & 1) d = std::min(d, open.hi[a] - p[a]);
    }
    for (const Bounds& s : solids) d = std::min(d, distanceToBox(p, s));
    return d;
}

LeakScene makeThinWallScene() {
    LeakScene l;
    l.scene.name = "thin_wall_door";
    const uint32_t wall = material(l.scene, "wall", {0.7f, 0.7f, 0.7f});
    const uint32_t light = material(l.scene, "light", {0, 0, 0}, {12, 12, 12});
    l.open = box({0, 0, 0}, {4, 2, 2});
    appendBox(l.scene, Vec3f(l.open.lo), Vec3f(l.open.hi), /*inward=*/true, wall);
    // The dividing wall, as three solids around the door; they reach a little into the room's
    // walls so that no face of theirs is coplanar with a room face.
    constexpr double e = 0.01;
    addSolid(l, {1.95, -e, -e}, {2.05, 2 + e, 0.6}, wall);
    addSolid(l, {1.95, -e, 1.4}, {2.05, 2 + e, 2 + e}, wall);
    addSolid(l, {1.95, 1.4, 0.6}, {2.05, 2 + e, 1.4}, wall);
    horizontalQuad(l.scene, 1.99f, 0.6f, 1.4f, 0.6f, 1.4f, /*up=*/false, light);
    return l;
}

LeakScene makeTownScene() {
    LeakScene l;
    l.scene.name = "small_town";
    const uint32_t ground = material(l.scene, "ground", {0.5f, 0.5f, 0.45f});
    const uint32_t wall = material(l.scene, "block", {0.7f, 0.6f, 0.5f});
    l.open = box({0, 0, 0}, {8, 3, 8});
    l.openSurfaces = 1u << 2;  // the ground; the other faces of `open` are air
    horizontalQuad(l.scene, 0.0f, -2.0f, 10.0f, -2.0f, 10.0f, /*up=*/true, ground);
    const double heights[9] = {1.2, 2.1, 0.8, 1.6, 2.6, 1.0, 0.7, 1.9, 1.4};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            const double x = 0.7 + 2.55 * i, z = 0.7 + 2.55 * k;
            addSolid(l, {x, -0.01, z}, {x + 1.55, heights[3 * i + k], z + 1.55}, wall);
        }
    l.scene.sky.constant = {0.5f, 0.6f, 0.8f};
    l.scene.directionalLights.push_back({normalize(Vec3f(-0.4f, -1.0f, -0.3f)), {3.0f, 2.8f, 2.5f}});
    return l;
}

LeakScene makeBarsScene() {
    LeakScene l;
    l.scene.name = "bed_bars";
    const uint32_t wall = material(l.scene, "wall", {0.7f, 0.7f, 0.7f});
    const uint32_t wood = material(l.scene, "wood", {0.6f, 0.4f, 0.3f});
    const uint32_t light = material(l.scene, "light", {0, 0, 0}, {10, 10, 10});
    l.open = box({0, 0, 0}, {3, 2, 3});
    appendBox(l.scene, Vec3f(l.open.lo), Vec3f(l.open.hi), /*inward=*/true, wall);
    addSolid(l, {0.8, 0.45, 0.8}, {2.2, 0.55, 2.2}, wood);  // mattress slab
    for (int b = 0; b < 8; ++b) {                           // headboard and foot bars
        const double x = 0.8 + 0.2 * b;
        addSolid(l, {x, -0.01, 0.74}, {x + 0.06, 1.1, 0.8}, wood);
        addSolid(l, {x, -0.01, 2.2}, {x + 0.06, 0.9, 2.26}, wood);
    }
    horizontalQuad(l.scene, 1.99f, 1.1f, 1.9f, 1.1f, 1.9f, /*up=*/false, light);
    return l;
}

LeakScene makeMazeScene(float crack) {
    LeakScene l;
    l.scene.name = crack > 0 ? "maze_cracked" : "maze";
    const uint32_t wall = material(l.scene, "wall", {0.7f, 0.7f, 0.7f});
    constexpr double W = 4, H = 1.2, e = 0.01, t = 0.05;  // t: half the wall thickness
    l.open = box({0, 0, 0}, {W, H, W});
    appendBox(l.scene, Vec3f(l.open.lo), Vec3f(l.open.hi), /*inward=*/true, wall);
    const auto addWall = [&](Vec3d lo, Vec3d hi) {
        if (crack > 0) appendCrackedBox(l.scene, Vec3f(lo), Vec3f(hi), crack, wall);
        else appendBox(l.scene, Vec3f(lo), Vec3f(hi), /*inward=*/false, wall);
        l.solids.push_back(box(lo, hi));
    };
    // The serpentine: long walls at z = 0.8, 1.6, 2.4, 3.2, floor to ceiling, leaving a
    // 0.8 wide passage at alternate ends.
    for (int i = 0; i < 4; ++i) {
        const double z = 0.8 * (i + 1);
        if (i % 2 == 0) addWall({-e, -e, z - t}, {W - 0.8, H + e, z + t});
        else addWall({0.8, -e, z - t}, {W + e, H + e, z + t});
    }
    addWall({2.0 - t, -e, -e}, {2.0 + t, H + e, 0.45});      // cross wall in the first corridor
    addWall({1.6 - t, -e, 1.75}, {1.6 + t, H + e, 2.25});    // free-standing segment
    addWall({2.6 - t, 0.7, 2.5}, {2.6 + t, H + e, 3.1});     // lintel over the fourth corridor
    l.scene.pointLights.push_back({{3.6f, 1.0f, 3.6f}, {2.0f, 2.0f, 2.0f}});
    return l;
}

std::vector<EvalPoint> leakEvalPoints(const LeakScene& scene, const Bounds& box, double maxDistance, int count,
                                      uint64_t seed) {
    std::vector<EvalPoint> out;
    Rng rng(seed, 0x1eacu);
    for (uint64_t tries = 0; int(out.size()) < count; ++tries) {
        if (tries > 1000ull * uint64_t(count) + 100000) throw ValueError("too few points lie near surfaces in the box");
        const Vec3d p = box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform());
        if (!scene.inDomain(p) || scene.distanceToSurface(p) > maxDistance) continue;
        const float u = rng.uniform(), v = rng.uniform();
        out.push_back({Vec3f(p), uniformSphere(u, v)});
    }
    return out;
}

void appendCrackedBox(Scene& scene, const Vec3f& lo, const Vec3f& hi, float gap, uint32_t materialId) {
    // Each face of the box, shrunk by `gap` within its plane and oriented outwards.
    const Vec3f centre = (lo + hi) * 0.5f;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            Vec3f q[4];
            for (int c = 0; c < 4; ++c) {
                q[c][axis] = side ? hi[axis] : lo[axis];
                q[c][u] = (c == 1 || c == 2) ? hi[u] - gap : lo[u] + gap;
                q[c][v] = (c >= 2) ? hi[v] - gap : lo[v] + gap;
            }
            Vec3f a = q[0], b = q[1], c = q[2], d = q[3];
            if (dot(cross(b - a, c - a), a - centre) < 0) std::swap(b, d);
            addTriangle(scene, a, b, c, materialId);
            addTriangle(scene, a, c, d, materialId);
        }
}

}  // namespace vdblight
