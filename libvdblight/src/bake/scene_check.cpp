// Faces whose back side is seen from open space (scene_check.h).
#include "vdblight/bake/scene_check.h"

#include <algorithm>
#include <cmath>

#include "core/parallel_for.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

SceneCheckResult findBackfacingTriangles(const Scene& scene, const Tracer& tracer, const SceneCheckOptions& o) {
    if (o.resolution < 1 || o.resolution > 1024)
        throw ValueError("the probe resolution must be in [1, 1024], got " + std::to_string(o.resolution));
    if (o.raysPerPoint < 1) throw ValueError("rays per probe must be at least 1");
    if (!(o.maxBackfaceFraction >= 0.0 && o.maxBackfaceFraction < 1.0))
        throw ValueError("the back-face fraction must be in [0, 1), got " + std::to_string(o.maxBackfaceFraction));
    if (o.minHits < 1) throw ValueError("the minimum hit count must be at least 1");
    if (o.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");

    const Bounds b = scene.bounds();
    const Vec3d size = b.size();
    const double longest = std::max({size.x, size.y, size.z});
    if (!(longest > 0.0)) throw SceneError("the scene bounds are empty");
    const double h = longest / o.resolution;
    int n[3];
    for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::ceil(size[a] / h - 1e-9)));
    // Probes at (i + f) * step with f irrational-ish so that no probe lies on a face of
    // axis-aligned geometry with "round" coordinates.
    constexpr double kOffset = 0.5 + 0.0618034;
    const std::size_t probes = std::size_t(n[0]) * n[1] * n[2];
    const std::size_t tris = scene.triangleCount();

    // Per z-slab counts, reduced in slab order (determinism for any thread count).
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> slabHits(n[2]);
    std::vector<uint64_t> slabOpen(n[2], 0);
    core::parallelFor(std::size_t(n[2]), o.threads, [&](std::size_t slab) {
        const int k = int(slab);
        std::vector<uint32_t> local;  // triangles hit from behind by the current probe
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                const std::size_t probe = (std::size_t(k) * n[1] + j) * n[0] + i;
                const Vec3d pd(b.lo.x + (i + kOffset) * size.x / n[0], b.lo.y + (j + kOffset) * size.y / n[1],
                               b.lo.z + (k + kOffset) * size.z / n[2]);
                const Vec3f p(pd);
                const uint64_t scramble = hashCombine(o.seed, probe);
                local.clear();
                for (uint32_t s = 0; s < o.raysPerPoint; ++s) {
                    float u, v;
                    sobol02(s, scramble, u, v);
                    Ray ray;
                    ray.origin = p;
                    ray.direction = uniformSphere(u, v);
                    const Hit hit = tracer.intersect(ray);
                    if (hit.hit() && dot(hit.geometricNormal, ray.direction) > 0.0f) local.push_back(hit.triangle);
                }
                if (double(local.size()) > o.maxBackfaceFraction * o.raysPerPoint) continue;
                ++slabOpen[k];
                std::sort(local.begin(), local.end());
                for (std::size_t a = 0; a < local.size();) {
                    std::size_t e = a;
                    while (e < local.size() && local[e] == local[a]) ++e;
                    slabHits[k].push_back({local[a], uint32_t(e - a)});
                    a = e;
                }
            }
    });

    SceneCheckResult r;
    r.probes = probes;
    r.raysTraced = uint64_t(probes) * o.raysPerPoint;
    std::vector<uint64_t> hits(tris, 0);
    for (int k = 0; k < n[2]; ++k) {
        r.openProbes += slabOpen[k];
        for (const auto& [t, c] : slabHits[k]) hits[t] += c;
    }
    for (std::size_t t = 0; t < tris; ++t)
        if (hits[t] >= o.minHits) r.backfacing.push_back({uint32_t(t), hits[t]});
    std::sort(r.backfacing.begin(), r.backfacing.end(), [](const BackfacingTriangle& x, const BackfacingTriangle& y) {
        return x.hits != y.hits ? x.hits > y.hits : x.triangle < y.triangle;
    });
    return r;
}

}  // namespace vdblight
