// Benchmark of the multi-level layouts (issue 4): uniform vs bilevel vs adaptive at about
// the same node count on the default scene: node count, bake time, and RMS / max relative
// error of E(x, n) against `reference` at random free-space points (all of them, and those
// in refined cells, i.e. near geometry). Also the paper's configuration (7^3 first level,
// 3^3 refinement, 578 directions per node) and lookups per second of a multi-level volume.
//
// Every layout is compared in two directional bases: SH order 2 and Greger bins (`--bins R`,
// default 17 = the paper's 578 bins), whose directional floor is much lower, with the
// floor of each basis measured by projecting it at the query points themselves. `--sweep
// R1,R2,...` repeats the comparison over node budgets (first-level resolutions) and prints
// the best refined / uniform ratio per budget and basis with a bootstrap range.
//
// `--quick` shrinks every workload for a CI smoke run; the figures are then noisy.
//
// Its parts (layouts.h): layouts_probe.cpp (layouts, error metric, bakes and floors per
// basis) and layouts_sweep.cpp (the sweep); this file holds the table at one node budget, the
// paper's configuration, the lookup speed and main.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "bench_util.h"
#include "layouts.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/light/light.h"
#include "query/query_levels.h"
#include "vdblight/reference/reference.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

#include "support/office_scene.h"

using namespace vdblight;
using namespace vdblight::bench_layouts;

namespace {

using bench::freeSpace;
using bench::now;

/// One scene's tables at the node budget of the bilevel layout on the --first-level grid: every
/// layout in SH2, then in bins:R if asked, then the sweep if asked (or only the sweep).
void benchLayouts(const Scene& scene, int threads, bool quick, const LayoutBenchOptions& lo = {}) {
    const Tracer tracer(scene);
    const uint32_t rays = lo.rays ? lo.rays : (quick ? 64 : 256);
    const bool smoke = quick;  // --quick (CI): the bins floor at 16x rays and most sweep layouts are skipped
    if (!lo.decompose) quick = true;  // the quick path skips the 4x bakes and the 16x point projections
    GatherOptions options;
    options.raysPerNode = rays;
    options.threads = threads;

    // Bilevel as in the paper sets the node budget; the others match it (baked nodes; culled
    // layouts count only the nodes they keep, so culling frees budget for refinement).
    const LevelLayout bilevel = makeLayout(scene, LayoutKind::Bilevel, lo.firstLevel ? lo.firstLevel : (quick ? 6 : 8), 3, 2);
    const uint64_t target = bilevel.totalNodes();
    std::vector<Config> configs = {
        {"uniform", closestLayout(scene, LayoutKind::Uniform, 2, 1, target)},
        {"bilevel K=3", bilevel},
        {"adaptive K=2 L=3", closestLayout(scene, LayoutKind::Adaptive, 2, 3, target)},
        {"bilevel K=3 culled",
         closestLayout([&](int r) { return makeCulledLayout(scene, tracer, LayoutKind::Bilevel, r, 3, 2); }, target)},
        {"adaptive K=2 L=3 cull",
         closestLayout([&](int r) { return makeCulledLayout(scene, tracer, LayoutKind::Adaptive, r, 2, 3); }, target)},
    };
    if (!quick || !lo.decompose) {
        configs.push_back({"adaptive K=2 L=3 D", closestLayout([&](int r) {
                               return makeLayout(scene, LayoutKind::Adaptive, r, 2, 3, 0.5);
                           }, target)});
        configs.push_back({"adaptive K=2 L=4", closestLayout(scene, LayoutKind::Adaptive, 2, 4, target)});
        configs.push_back({"bilevel K=2", closestLayout(scene, LayoutKind::Bilevel, 2, 2, target)});
    }

    // Reference at random free-space points with random normals.
    const int wanted = quick && lo.decompose ? 150 : 1000;
    const Bounds box = bilevel.levels[0].grid.nodeBounds();
    std::vector<ReferencePoint> points;
    Rng rng(2024);
    while (int(points.size()) < wanted) {
        const Vec3f x(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        if (freeSpace(tracer, x)) points.push_back({x, uniformSphere(rng.uniform(), rng.uniform())});
    }
    ReferenceOptions ro;
    ro.samples = quick && lo.decompose ? 1024 : 8192;
    ro.threads = threads;
    double t0 = now();
    const std::vector<ReferenceResult> ref = referenceIrradiance(scene, tracer, points, ro);
    double meanRef = 0;
    for (const ReferenceResult& r : ref) meanRef += luminance(Rgb(r.irradiance)) / ref.size();
    std::printf("%s: %zu triangles, %d free-space points, reference %u samples each (%.1f s), %u rays per node\n",
                scene.name.c_str(), scene.triangleCount(), wanted, ro.samples, now() - t0, rays);
    const Probe probe{scene, tracer, points, ref, meanRef};
    if (lo.sweepOnly) {
        benchSweep(probe, lo, rays, threads, smoke);
        return;
    }

    const ShLevelsLookup nearMask(
        [&] {
            Volume v;
            v.basis = BasisDesc::sh2();
            v.levels = volumeLevels(bilevel.levels);
            for (VolumeLevel& l : v.levels) l.data.assign(l.storedNodes() * 27, 0.0f);
            return v;
        }(),
        OutsidePolicy::Clamp);
    const auto relError = [&](std::size_t i, const Rgb& e) {
        const double r = luminance(Rgb(ref[i].irradiance));
        return std::abs(double(luminance(e)) - r) / std::max(r, 0.05 * meanRef);
    };
    const auto isNear = [&](std::size_t i) { return nearMask.levelAt(points[i].position) > 0; };

    // Error floor of any SH order-2 layout: the SH projection baked at each query point itself
    // (no spatial interpolation), at N and at 16 N rays: SH truncation + Monte Carlo noise.
    const RadianceEstimator estimator(scene, tracer, options.transport);
    std::vector<double> sh16(points.size(), 0.0);  // luminance of E from the SH2 projection at the point, 16 N rays
    const auto pointFloor = [&](uint32_t n, std::vector<double>* keep) {
        std::vector<double> err(points.size());
        tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
            Rgbd c[sh::kCoeffs];
            RayCount count;
            projectIncidentRadiance(estimator, points[i].position, n, options.seed, 1'000'000 + i, c, count);
            Rgb f[sh::kCoeffs];
            for (int j = 0; j < sh::kCoeffs; ++j) f[j] = Rgb(c[j]);
            const Rgb e = sh::irradiance(f, points[i].normal);
            err[i] = relError(i, e);
            if (keep) (*keep)[i] = luminance(e);
        });
        ErrorStats near;
        for (std::size_t i = 0; i < points.size(); ++i)
            if (isNear(i)) near.add(err[i]);
        return near.rmsValue();
    };
    const double floorN = pointFloor(rays, nullptr), floor16 = quick ? 0.0 : pointFloor(16 * rays, &sh16);
    std::printf("  SH2 projected at the query points themselves (no interpolation), near geometry: RMS %.2f%% at %u "
                "rays",
                100 * floorN, rays);
    if (!quick) std::printf(", %.2f%% at %u rays (SH truncation floor)", 100 * floor16, 16 * rays);
    std::printf("\n");

    std::printf("  %-22s %7s %7s %9s %3s %7s %9s %9s %9s %10s %9s %9s\n", "layout", "baked", "culled", "dense box", "L",
                "bake s", "RMS rel", "RMS near", "max near", "near 4xN", "no-noise", "spatial");
    std::vector<double> rmsNear(configs.size()), rmsClean(configs.size()), rmsSpatial(configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c) {
        const auto measure = [&](uint32_t n, ErrorStats& all, ErrorStats& near, ErrorStats& spatial, double& seconds) {
            GatherOptions o = options;
            o.raysPerNode = n;
            LevelsBakeStats stats;
            const Volume v = bakeShGatherLevels(scene, tracer, configs[c].layout, o, nullptr, &stats);
            seconds = stats.seconds;
            const IrradianceQuery q(v);
            for (std::size_t i = 0; i < points.size(); ++i) {
                const Rgb e = q.irradiance(points[i].position, points[i].normal);
                const double rel = relError(i, e);
                all.add(rel);
                if (!isNear(i)) continue;
                near.add(rel);
                const double r = luminance(Rgb(ref[i].irradiance));
                spatial.add(std::abs(double(luminance(e)) - sh16[i]) / std::max(r, 0.05 * meanRef));
            }
        };
        ErrorStats all, near, spatial, all4, near4, spatial4;
        double seconds = 0, seconds4 = 0;
        measure(rays, all, near, spatial, seconds);
        if (!quick) measure(4 * rays, all4, near4, spatial4, seconds4);
        rmsNear[c] = near.rmsValue();
        rmsClean[c] = quick ? 0.0 : noiseFree(near.rmsValue(), near4.rmsValue());
        rmsSpatial[c] = quick ? 0.0 : noiseFree(spatial.rmsValue(), spatial4.rmsValue());
        std::printf("  %-22s %7llu %7llu %9.0f %3zu %7.2f %8.2f%% %8.2f%% %8.1f%% %9.2f%% %8.2f%% %8.2f%%\n",
                    configs[c].name, (unsigned long long)configs[c].layout.totalNodes(),
                    (unsigned long long)configs[c].layout.culledNodes, configs[c].layout.denseEquivalentNodes(),
                    configs[c].layout.levels.size(), seconds,
                    100 * all.rmsValue(), 100 * near.rmsValue(), 100 * near.max, 100 * near4.rmsValue(),
                    100 * rmsClean[c], 100 * rmsSpatial[c]);
    }
    std::printf("  (%d near points: in cells the %llu-node bilevel refines; 'no-noise' extrapolates N and 4N rays; "
                "'spatial' is the no-noise error against the SH2 projection at the point itself, i.e. interpolation "
                "only)\n",
                [&] {
                    int n = 0;
                    for (std::size_t i = 0; i < points.size(); ++i) n += isNear(i);
                    return n;
                }(),
                (unsigned long long)target);
    std::printf("  near geometry, RMS error vs uniform at %u rays:", rays);
    std::size_t best = 1;
    for (std::size_t c = 1; c < configs.size(); ++c) {
        std::printf("%s %s %.2fx", c > 1 ? "," : "", configs[c].name, rmsNear[c] / rmsNear[0]);
        if (rmsNear[c] < rmsNear[best]) best = c;
    }
    std::printf(" (target <= 0.70x)\n");
    if (!quick) {
        std::printf("  without Monte Carlo noise:");
        for (std::size_t c = 1; c < configs.size(); ++c)
            std::printf("%s %s %.2fx", c > 1 ? "," : "", configs[c].name, rmsClean[c] / rmsClean[0]);
        std::printf("\n  interpolation error only (spatial):");
        for (std::size_t c = 1; c < configs.size(); ++c)
            std::printf("%s %s %.2fx", c > 1 ? "," : "", configs[c].name, rmsSpatial[c] / rmsSpatial[0]);
        std::printf("\n");
    }
    std::printf("  [sh2] 30%% target %s: best %s at %.2fx uniform's RMS near geometry (%llu vs %llu nodes)\n",
                rmsNear[best] <= 0.70 * rmsNear[0] ? "MET" : "NOT met", configs[best].name, rmsNear[best] / rmsNear[0],
                (unsigned long long)configs[best].layout.totalNodes(), (unsigned long long)configs[0].layout.totalNodes());

    if (lo.binsResolution > 0) {
        // The same layouts, node budgets, points, reference and error metric in a basis whose
        // directional floor is lower than SH2's (culled layouts are left out: BinsLookup
        // refuses a sparse level 0, and their rows equal the unculled ones above).
        const BasisChoice b = binsBasis(lo.binsResolution);
        const std::vector<char> near = nearPoints(probe, bilevel);
        const uint32_t bRays = b.raysPerNode(rays);
        const double floorB = rmsNearOf(probe, projectAtPoints(probe, b, rays), near);
        std::printf("  [%s] %s projected at the query points themselves (no interpolation, blended bins), near "
                    "geometry: RMS %.2f%% at %u rays",
                    b.name.c_str(), b.name.c_str(), 100 * floorB, bRays);
        if (!smoke)
            std::printf(", %.2f%% at %u rays (bin floor)",
                        100 * rmsNearOf(probe, projectAtPoints(probe, b, 16 * rays), near), b.raysPerNode(16 * rays));
        std::printf("\n  [%s] %-22s %7s %3s %7s %9s %9s %9s\n", b.name.c_str(), "layout", "baked", "L", "bake s",
                    "RMS rel", "RMS near", "max near");
        std::vector<double> rmsB;
        std::vector<std::size_t> used;
        for (std::size_t c = 0; c < configs.size(); ++c) {
            if (std::strstr(configs[c].name, "cull")) continue;
            double seconds = 0, maxN = 0, all = 0;
            const double r = rmsNearOf(probe, bakeAndQuery(probe, configs[c].layout, b, rays, threads, &seconds), near,
                                     &maxN, &all);
            rmsB.push_back(r), used.push_back(c);
            std::printf("  [%s] %-22s %7llu %3zu %7.2f %8.2f%% %8.2f%% %8.1f%%\n", b.name.c_str(), configs[c].name,
                        (unsigned long long)configs[c].layout.totalNodes(), configs[c].layout.levels.size(), seconds,
                        100 * all, 100 * r, 100 * maxN);
        }
        std::printf("  [%s] near geometry, RMS error vs uniform at %u rays:", b.name.c_str(), bRays);
        std::size_t bestB = 1;
        for (std::size_t k = 1; k < used.size(); ++k) {
            std::printf("%s %s %.2fx", k > 1 ? "," : "", configs[used[k]].name, rmsB[k] / rmsB[0]);
            if (rmsB[k] < rmsB[bestB]) bestB = k;
        }
        std::printf(" (target <= 0.70x; point floor %.2fx uniform)\n", floorB / rmsB[0]);
        std::printf("  [%s] 30%% target %s: best %s at %.2fx uniform's RMS near geometry (%llu vs %llu nodes)\n",
                    b.name.c_str(), rmsB[bestB] <= 0.70 * rmsB[0] ? "MET" : "NOT met", configs[used[bestB]].name,
                    rmsB[bestB] / rmsB[0], (unsigned long long)configs[used[bestB]].layout.totalNodes(),
                    (unsigned long long)configs[0].layout.totalNodes());
    }
    if (!lo.sweep.empty()) benchSweep(probe, lo, rays, threads, smoke);
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
                "bake %.2f s on %d threads, %.2f M rays (%.2f M shadow) (paper: 24 min; target < 1 s)\n",
                options.raysPerNode, (unsigned long long)stats.nodes, (unsigned long long)stats.seamNodes,
                stats.seconds, int(std::get<int64_t>(v.meta.at("threads"))), double(stats.rays.total()) / 1e6,
                double(stats.rays.occluded) / 1e6);
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

/// bins:R compared beside SH2 by default (its point floor: docs/methods.md, issue 4).
constexpr int kDefaultBins = 17;

int main(int argc, char** argv) {
    bool quick = false;
    int threads = 0;
    std::string only;  // --scene cornell|office: one scene's layout table only
    LayoutBenchOptions lo;
    bool binsGiven = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true;
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--scene") && i + 1 < argc) only = argv[++i];
        else if (!std::strcmp(argv[i], "--first-level") && i + 1 < argc) lo.firstLevel = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--rays") && i + 1 < argc) lo.rays = uint32_t(std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--no-decompose")) lo.decompose = false;
        else if (!std::strcmp(argv[i], "--sweep-only")) lo.sweepOnly = true;
        else if (!std::strcmp(argv[i], "--bins") && i + 1 < argc) lo.binsResolution = std::atoi(argv[++i]), binsGiven = true;
        else if (!std::strcmp(argv[i], "--sweep") && i + 1 < argc) {
            for (const char* p = argv[++i]; *p;) {
                char* end = nullptr;
                const long r = std::strtol(p, &end, 10);
                if (end == p || r < 2 || r > 64) {
                    std::fprintf(stderr, "vdblight_bench_layouts: --sweep wants first-level resolutions 2..64, e.g. 4,6,8\n");
                    return 2;
                }
                lo.sweep.push_back(int(r));
                p = *end == ',' ? end + 1 : end;
            }
        } else {
            std::fprintf(stderr, "usage: vdblight_bench_layouts [--quick] [--threads N] [--scene cornell|office] "
                                 "[--first-level R] [--rays N] [--no-decompose] [--bins R (0: no bins table)] "
                                 "[--sweep R1,R2,... [--sweep-only]]\n");
            return 2;
        }
    }
    if (lo.binsResolution < 0) {
        std::fprintf(stderr, "vdblight_bench_layouts: --bins must be >= 0\n");
        return 2;
    }
    if (lo.binsResolution == 0 && !binsGiven) lo.binsResolution = quick ? 4 : kDefaultBins;
    if (quick && lo.sweep.empty()) lo.sweep = {5};  // the sweep's code path once, one budget, two layouts
    if (!only.empty() && only != "cornell" && only != "office") {
        std::fprintf(stderr, "vdblight_bench_layouts: --scene must be cornell or office\n");
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines as they come when redirected (long full runs)
    std::printf("vdblight_bench_layouts%s\n", quick ? " (quick smoke run, noisy figures)" : "");
    try {
        const Scene scene = loadScene(defaultScenePath());
        if (only.empty() || only == "cornell") benchLayouts(scene, threads, quick, lo);
        if (only.empty() || only == "office")
            benchLayouts(makeOfficeScene(1), threads, quick, lo);  // the paper's kind of scene (office_scene.h)
        if (!only.empty()) return 0;
        benchPaperConfig(scene, threads, quick);
        benchQuery(scene, quick);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench_layouts: %s\n", e.what());
        return 1;
    }
    return 0;
}
