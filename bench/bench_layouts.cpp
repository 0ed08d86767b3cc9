// Benchmark of the multi-level layouts (issue 4): uniform vs bilevel vs adaptive at about
// the same node count on the default scene: node count, bake time, and RMS / max relative
// error of E(x, n) against `reference` at random free-space points (all of them, and those
// in refined cells, i.e. near geometry). Also the paper's configuration (7^3 first level,
// 3^3 refinement, 578 directions per node) and lookups per second of a multi-level volume.
//
// `--quick` shrinks every workload for a CI smoke run; the figures are then noisy.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "vdblight/bake_levels.h"
#include "vdblight/errors.h"
#include "vdblight/office_scene.h"
#include "vdblight/query_levels.h"
#include "vdblight/reference.h"
#include "vdblight/sampling.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"

using namespace vdblight;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// A point is in free space if rays along the six axis directions first hit front faces
/// (or nothing): inside a closed solid some ray meets a back face first.
bool freeSpace(const Tracer& tracer, const Vec3f& x) {
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3f& d : dirs) {
        Ray r;
        r.origin = x;
        r.direction = d;
        const Hit h = tracer.intersect(r);
        if (h.hit() && dot(h.geometricNormal, d) > 0) return false;
    }
    return true;
}

struct Config {
    const char* name;
    LevelLayout layout;
};

LevelLayout makeLayout(const Scene& scene, LayoutKind kind, int resolution, int refine, int levels) {
    GridPlacement p;
    p.resolution = resolution;
    const GridSpec g0 = placeUniformGrid(scene.bounds(), p, 1);
    LevelsPlacement lp;
    lp.kind = kind;
    lp.refine = refine;
    lp.levels = levels;
    return placeLevels(g0, scene.positions, scene.indices, lp, 1);
}

/// The layout of `kind` whose node count is closest to `target`, over first-level resolutions.
LevelLayout closestLayout(const Scene& scene, LayoutKind kind, int refine, int levels, uint64_t target) {
    LevelLayout best;
    double bestGap = 1e300;
    for (int r = 2; r <= 64; ++r) {
        LevelLayout l;
        try {
            l = makeLayout(scene, kind, r, refine, levels);
        } catch (const ValueError&) {  // too few first-level nodes on a short axis
            continue;
        }
        const double gap = std::abs(std::log(double(l.totalNodes()) / double(target)));
        if (gap < bestGap) bestGap = gap, best = std::move(l);
        if (l.totalNodes() > 4 * target) break;
    }
    return best;
}

struct ErrorStats {
    double rms = 0, max = 0;
    int count = 0;
    void add(double e) { rms += e * e, max = std::max(max, e), ++count; }
    double rmsValue() const { return count ? std::sqrt(rms / count) : 0.0; }
};

void benchLayouts(const Scene& scene, int threads, bool quick) {
    const Tracer tracer(scene);
    const uint32_t rays = quick ? 64 : 256;
    GatherOptions options;
    options.raysPerNode = rays;
    options.threads = threads;

    // Bilevel as in the paper sets the node budget; the others match it.
    const LevelLayout bilevel = makeLayout(scene, LayoutKind::Bilevel, quick ? 6 : 8, 3, 2);
    const uint64_t target = bilevel.totalNodes();
    std::vector<Config> configs = {
        {"uniform", closestLayout(scene, LayoutKind::Uniform, 2, 1, target)},
        {"bilevel K=3", bilevel},
        {"adaptive K=2 L=3", closestLayout(scene, LayoutKind::Adaptive, 2, 3, target)},
    };

    // Reference at random free-space points with random normals.
    const int wanted = quick ? 150 : 1000;
    const Bounds box = bilevel.levels[0].grid.nodeBounds();
    std::vector<ReferencePoint> points;
    Rng rng(2024);
    while (int(points.size()) < wanted) {
        const Vec3f x(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        if (freeSpace(tracer, x)) points.push_back({x, uniformSphere(rng.uniform(), rng.uniform())});
    }
    ReferenceOptions ro;
    ro.samples = quick ? 1024 : 8192;
    ro.threads = threads;
    double t0 = now();
    const std::vector<ReferenceResult> ref = referenceIrradiance(scene, tracer, points, ro);
    double meanRef = 0;
    for (const ReferenceResult& r : ref) meanRef += luminance(Rgb(r.irradiance)) / ref.size();
    std::printf("%s: %zu triangles, %d free-space points, reference %u samples each (%.1f s), %u rays per node\n",
                scene.name.c_str(), scene.triangleCount(), wanted, ro.samples, now() - t0, rays);

    const ShLevelsLookup nearMask(
        [&] {
            Volume v;
            v.basis = BasisDesc::sh2();
            v.levels = bilevel.levels;
            for (VolumeLevel& l : v.levels) l.data.assign(l.storedNodes() * 27, 0.0f);
            return v;
        }(),
        OutsidePolicy::Clamp);
    std::printf("  %-18s %9s %9s %10s %10s %10s %12s %12s\n", "layout", "nodes", "levels", "bake s", "RMS rel", "max rel",
                "RMS near", "max near");
    double rmsNear[3] = {};
    for (std::size_t c = 0; c < configs.size(); ++c) {
        LevelsBakeStats stats;
        const Volume v = bakeShGatherLevels(scene, tracer, configs[c].layout, options, nullptr, &stats);
        const IrradianceQuery q(v);
        ErrorStats all, near;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double e = luminance(q.irradiance(points[i].position, points[i].normal));
            const double r = luminance(Rgb(ref[i].irradiance));
            const double rel = std::abs(e - r) / std::max(r, 0.05 * meanRef);
            all.add(rel);
            if (nearMask.levelAt(points[i].position) > 0) near.add(rel);
        }
        rmsNear[c] = near.rmsValue();
        std::printf("  %-18s %9llu %9zu %10.2f %9.2f%% %9.2f%% %11.2f%% %11.2f%%   (%d near points)\n", configs[c].name,
                    (unsigned long long)stats.nodes, v.levels.size(), stats.seconds, 100 * all.rmsValue(),
                    100 * all.max, 100 * near.rmsValue(), 100 * near.max, near.count);
    }
    std::printf("  near geometry, RMS error vs uniform: bilevel %.2fx, adaptive %.2fx (target <= 0.70x)\n",
                rmsNear[1] / rmsNear[0], rmsNear[2] / rmsNear[0]);
}

void benchPaperConfig(const Scene& scene, int threads, bool quick) {
    const Tracer tracer(scene);
    const LevelLayout layout = makeLayout(scene, LayoutKind::Bilevel, 7, 3, 2);
    GatherOptions options;
    options.raysPerNode = quick ? 64 : 578;
    options.threads = threads;
    LevelsBakeStats stats;
    const Volume v = bakeShGatherLevels(scene, tracer, layout, options, nullptr, &stats);
    std::printf("paper configuration (7^3 first level, 3^3 refinement, %u directions): %llu nodes (%llu seam), "
                "bake %.2f s on %d threads (paper: 24 min; target < 1 s)\n",
                options.raysPerNode, (unsigned long long)stats.nodes, (unsigned long long)stats.seamNodes,
                stats.seconds, int(std::get<int64_t>(v.meta.at("threads"))));
}

void benchQuery(const Scene& scene, bool quick) {
    const Tracer tracer(scene);
    GatherOptions options;
    options.raysPerNode = 1;  // values do not matter for lookup speed
    const Volume volume = bakeShGatherLevels(scene, tracer, makeLayout(scene, LayoutKind::Adaptive, 8, 3, 3), options);
    const IrradianceQuery query(volume);
    const std::size_t n = quick ? 200'000 : 2'000'000;
    std::vector<Vec3f> points(n), normals(n);
    Rng rng(123);
    const Bounds b = volume.levels[0].grid.nodeBounds();
    for (std::size_t i = 0; i < n; ++i) {
        points[i] = Vec3f(b.lo + b.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        normals[i] = uniformSphere(rng.uniform(), rng.uniform());
    }
    double best = 0;
    Rgb sink{0, 0, 0};
    for (int r = 0; r < (quick ? 1 : 5); ++r) {
        const double t0 = now();
        for (std::size_t i = 0; i < n; ++i) sink += query.irradiance(points[i], normals[i]);
        best = std::max(best, double(n) / (now() - t0));
    }
    std::printf("query (adaptive, 3 levels, %zu nodes, 1 thread): %.2f M lookups/s per thread (target >= 3)  [checksum %.3g]\n",
                std::size_t(volume.meta.count("nodes") ? std::get<int64_t>(volume.meta.at("nodes")) : 0), best / 1e6,
                double(sink.x));
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int threads = 0;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true;
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else {
            std::fprintf(stderr, "usage: vdblight_bench_layouts [--quick] [--threads N]\n");
            return 2;
        }
    }
    std::printf("vdblight_bench_layouts%s\n", quick ? " (quick smoke run, noisy figures)" : "");
    try {
        const Scene scene = loadScene(defaultScenePath());
        benchLayouts(scene, threads, quick);
        benchLayouts(makeOfficeScene(1), threads, quick);  // the paper's kind of scene (office_scene.h)
        benchPaperConfig(scene, threads, quick);
        benchQuery(scene, quick);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench_layouts: %s\n", e.what());
        return 1;
    }
    return 0;
}
