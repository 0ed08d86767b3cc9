#include "support/scene_generators.h"

#include <array>
#include <map>
#include <vector>

namespace vdblight {

double appendIcosphere(Scene& scene, const Vec3f& centre, float radius, int subdivisions, uint32_t materialId) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p = normalize(p);
    std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                         {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                         {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                         {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        // Split every triangle in four at its edge midpoints (shared through the map).
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            const auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize((v[a] + v[b]) * 0.5));
            return mid[key] = int(v.size()) - 1;
        };
        std::vector<std::array<int, 3>> g;
        g.reserve(f.size() * 4);
        for (const auto& tri : f) {
            const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
            g.push_back({tri[0], a, c});
            g.push_back({tri[1], b, a});
            g.push_back({tri[2], c, b});
            g.push_back({a, b, c});
        }
        f.swap(g);
    }
    double volume = 0;
    for (const auto& tri : f) {
        const Vec3d a = v[tri[0]] * double(radius);
        Vec3d b = v[tri[1]] * double(radius), c = v[tri[2]] * double(radius);
        if (dot(cross(b - a, c - a), a + b + c) < 0) std::swap(b, c);  // front face outwards
        addTriangle(scene, Vec3f(a) + centre, Vec3f(b) + centre, Vec3f(c) + centre, materialId);
        volume += dot(a, cross(b, c)) / 6.0;
    }
    return std::cbrt(volume * 3.0 / (4.0 * kPi));
}

void appendBox(Scene& scene, const Vec3f& lo, const Vec3f& hi, bool inward, uint32_t materialId) {
    auto corner = [&](int i) { return Vec3f{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z}; };
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    const Vec3f centre = (lo + hi) * 0.5f;
    for (const auto& q : quads) {
        Vec3f a = corner(q[0]), b = corner(q[1]), c = corner(q[2]), d = corner(q[3]);
        // Orient from the geometry: front face towards the centre if inward.
        const bool facesIn = dot(cross(b - a, c - a), centre - a) > 0;
        if (facesIn != inward) std::swap(b, d);
        addTriangle(scene, a, b, c, materialId);
        addTriangle(scene, a, c, d, materialId);
    }
}

double appendDisk(Scene& scene, const Vec3f& centre, float radius, int segments, uint32_t materialId) {
    for (int s = 0; s < segments; ++s) {
        const double a0 = 2 * kPi * s / segments, a1 = 2 * kPi * (s + 1) / segments;
        const Vec3f p0{float(radius * std::cos(a0)), float(radius * std::sin(a0)), 0};
        const Vec3f p1{float(radius * std::cos(a1)), float(radius * std::sin(a1)), 0};
        addTriangle(scene, centre, centre + p0, centre + p1, materialId);  // counter-clockwise from +z
    }
    const double area = 0.5 * segments * double(radius) * radius * std::sin(2 * kPi / segments);
    return std::sqrt(area / kPi);
}

}  // namespace vdblight
