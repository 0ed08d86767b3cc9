// Surface samples (Leonhardt & Bohn 4.1): area-weighted random candidates thinned by
// Poisson-disk elimination, then farthest-point clusters.
//
// Why this scheme: candidates are drawn per unit area, so the result does not depend on how
// the surfaces are tessellated (unlike vertices); elimination in candidate order is the
// paper's thinning step without its particle tracing (which only serves to find surfaces
// reachable from inside, and needs a point inside the scene); and it is a pure function of
// the seed. Only samples facing the same side eliminate each other, so both faces of a thin
// wall keep their samples.
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "sample_grid.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

namespace {

/// A point drawn uniformly by area over the scene's triangles (`cdf`: 0, then their cumulative areas,
/// `area` the total) from its own random stream: the triangle, the point and its normal.
struct AreaPoint {
    std::size_t triangle;
    Vec3f p, n;
};
AreaPoint areaPoint(const Scene& scene, const std::vector<double>& cdf, double area, Rng& rng) {
    const double u = toUnitDouble((uint64_t(rng.next()) << 32) | rng.next()) * area;
    std::size_t t = std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
    t = std::min(std::max<std::size_t>(t, 1), cdf.size() - 1) - 1;  // cdf has one entry per triangle + 1
    float b1, b2;
    uniformTriangle(rng.uniform(), rng.uniform(), b1, b2);
    const Vec3f a = scene.vertex(t, 0), b = scene.vertex(t, 1), c = scene.vertex(t, 2);
    return {t, a * (1.0f - b1 - b2) + b * b1 + c * b2, normalize(cross(b - a, c - a))};
}

struct Candidate {
    Vec3f p, n;
    uint32_t tri;
};

using prt_detail::SampleGrid;

}  // namespace

std::vector<uint32_t> clusterSamples(const std::vector<Vec3f>& points, uint32_t clusterSize, std::vector<Vec3f>* roots) {
    if (points.empty()) throw ValueError("cannot cluster zero samples");
    if (clusterSize == 0) throw ValueError("cluster size must be positive");
    const std::size_t n = points.size();
    const std::size_t k = std::max<std::size_t>(1, std::size_t(std::lround(double(n) / clusterSize)));
    std::vector<float> nearest(n, std::numeric_limits<float>::infinity());
    std::vector<uint32_t> owner(n, 0);
    std::vector<Vec3f> r;
    std::size_t next = 0;
    for (std::size_t c = 0; c < k; ++c) {
        r.push_back(points[next]);
        std::size_t best = 0;
        float bestD = -1.0f;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3f d = points[i] - points[next];
            const float d2 = dot(d, d);
            if (d2 < nearest[i]) {
                nearest[i] = d2;
                owner[i] = uint32_t(c);
            }
            if (nearest[i] > bestD) {
                bestD = nearest[i];
                best = i;
            }
        }
        next = best;
    }
    if (roots) *roots = r;
    return owner;
}

SurfaceSamples generateSurfaceSamples(const Scene& scene, double radius, uint32_t targetCount, uint32_t clusterSize,
                                      uint64_t seed) {
    if (radius < 0 || !std::isfinite(radius)) throw ValueError("sample radius must be positive");
    if (radius == 0 && targetCount == 0) throw ValueError("sample count must be positive");
    if (clusterSize == 0) throw ValueError("cluster size must be positive");
    const std::size_t tris = scene.triangleCount();
    std::vector<double> cdf(tris + 1, 0.0);
    for (std::size_t t = 0; t < tris; ++t) {
        const Vec3d a(scene.vertex(t, 0)), b(scene.vertex(t, 1)), c(scene.vertex(t, 2));
        cdf[t + 1] = cdf[t] + 0.5 * length(cross(b - a, c - a));
    }
    const double area = cdf[tris];
    if (!(area > 0)) throw SceneError("scene has no surface area to sample");
    // Random sequential packing fills about 55% of the plane with disks of radius r/2.
    if (radius == 0) radius = std::sqrt(0.55 * 4.0 * area / (kPi * double(targetCount)));
    const double expected = 0.55 * 4.0 * area / (kPi * radius * radius);
    if (expected > 5e7) {
        throw ValueError("sample radius " + std::to_string(radius) + " gives about " +
                         std::to_string(uint64_t(expected)) + " samples (over 50 million): choose a larger radius");
    }
    const std::size_t candidates = std::max<std::size_t>(64, std::size_t(expected * 12.0));

    const float r = float(radius), r2 = r * r;
    const float cell = r;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    std::vector<Candidate> accepted;
    for (std::size_t k = 0; k < candidates; ++k) {
        Rng rng(seed, k);
        const AreaPoint drawn = areaPoint(scene, cdf, area, rng);
        const Vec3f p = drawn.p, n = drawn.n;
        const std::size_t t = drawn.triangle;
        const int cx = int(std::floor(p.x / cell)), cy = int(std::floor(p.y / cell)), cz = int(std::floor(p.z / cell));
        bool free = true;
        for (int dz = -1; dz <= 1 && free; ++dz)
            for (int dy = -1; dy <= 1 && free; ++dy)
                for (int dx = -1; dx <= 1 && free; ++dx) {
                    const auto it = grid.find(SampleGrid::cellKey(cx + dx, cy + dy, cz + dz));
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second) {
                        const Vec3f d = accepted[j].p - p;
                        if (dot(d, d) < r2 && dot(accepted[j].n, n) > 0.0f) {
                            free = false;
                            break;
                        }
                    }
                }
        if (!free) continue;
        grid[SampleGrid::cellKey(cx, cy, cz)].push_back(uint32_t(accepted.size()));
        accepted.push_back({p, n, uint32_t(t)});
    }

    // Area per sample: uniform points (by area) go to their nearest same-facing sample.
    std::vector<Vec3f> pts(accepted.size()), nrm(accepted.size());
    for (std::size_t i = 0; i < accepted.size(); ++i) pts[i] = accepted[i].p, nrm[i] = accepted[i].n;
    const SampleGrid owners(pts, nrm, cell);
    std::vector<double> areaCount(accepted.size(), 0.0);
    const std::size_t areaPoints = 32 * accepted.size();
    double assigned = 0;
    for (std::size_t k = 0; k < areaPoints; ++k) {
        Rng rng(hashCombine(seed, 0x5eedu), k);
        const AreaPoint drawn = areaPoint(scene, cdf, area, rng);
        const uint32_t owner = owners.nearestFacing(drawn.p, drawn.n);
        if (owner == SampleGrid::kNone) continue;
        areaCount[owner] += 1.0;
        assigned += 1.0;
    }

    std::vector<Vec3f> roots;
    const std::vector<uint32_t> owner = clusterSamples(pts, clusterSize, &roots);
    std::vector<uint32_t> order(accepted.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return owner[x] < owner[y]; });

    SurfaceSamples s;
    s.radius = radius;
    s.areaPerSample = area / double(accepted.size());
    s.clusterRoot = roots;
    s.clusterBegin.assign(roots.size() + 1, 0);
    for (uint32_t i : order) {
        const Candidate& c = accepted[i];
        s.position.push_back(c.p);
        s.normal.push_back(c.n);
        s.albedo.push_back(scene.material(c.tri).albedo);
        s.cluster.push_back(owner[i]);
        s.area.push_back(float(assigned > 0 ? areaCount[i] / assigned * area : area / double(accepted.size())));
        s.clusterBegin[owner[i] + 1]++;
    }
    for (std::size_t c = 0; c < roots.size(); ++c) s.clusterBegin[c + 1] += s.clusterBegin[c];
    return s;
}

}  // namespace vdblight
