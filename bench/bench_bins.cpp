// Benchmark of Greger bins and moments (issue 4): on the default scene, the paper's
// configuration (7^3 first level, 3^3 refinement, 2 * 17^2 = 578 directions per node) with
// its bake time beside the paper's 24 minutes and beside an SH bake with as many rays in
// the same run; RMS / max relative error of E(x, n) against `reference` at random
// free-space points for SH order 2 and for bins with and without blending neighbouring
// bins; and lookups per second per thread.
//
// `--quick` shrinks every workload for a CI smoke run; the figures are then noisy.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <vector>

#include "bake/bake_bins.h"
#include "query/bins_lookup.h"
#include "query/query_levels.h"
#include "vdblight/reference/reference.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup
#include "bench_args.h"
#include "bench_util.h"

using namespace vdblight;
using bench::freeSpace;
using bench::now;

namespace {

LevelLayout makeLayout(const Scene& scene, LayoutKind kind, int resolution, int refine, int levels) {
    const GridSpec g0 = bench::uniformGrid(scene.bounds(), resolution);
    if (kind == LayoutKind::Uniform) return uniformLayout(g0);
    LevelsPlacement lp;
    lp.kind = kind;
    lp.refine = refine;
    lp.levels = levels;
    return placeLevels(g0, scene.positions, scene.indices, lp, 1);
}

BinsBakeOptions binsOptions(const char* basis, uint32_t samples, int threads) {
    BinsBakeOptions o;
    o.basis = bins::parseBasisSpec(basis);
    o.samplesPerBin = samples;
    o.threads = threads;
    return o;
}

struct ErrorStats {
    double sum2 = 0, max = 0;
    int count = 0;
    void add(double e) { sum2 += e * e, max = std::max(max, e), ++count; }
    double rms() const { return count ? std::sqrt(sum2 / count) : 0.0; }
};

void benchPaperConfig(const Scene& scene, const Tracer& tracer, int threads, bool quick) {
    const LevelLayout layout = makeLayout(scene, LayoutKind::Bilevel, 7, 3, 2);
    LevelsBakeStats bs, ss;
    const Volume b = bakeBins(scene, tracer, layout, binsOptions(quick ? "bins:8" : "bins:17", 1, threads), nullptr, &bs);
    GatherOptions sh;
    sh.raysPerNode = uint32_t(bins::parseBasisSpec(quick ? "bins:8" : "bins:17").binCount());
    sh.threads = threads;
    bakeShGatherLevels(scene, tracer, layout, sh, nullptr, &ss);
    std::printf("paper configuration (7^3 first level, 3^3 refinement, %s = %u directions, 1 ray per bin): %llu nodes "
                "(%llu seam), bake %.2f s on %d threads (paper: 24 min = 1440 s, %.0fx; target < 1 s); SH order 2 "
                "with %u rays/node on the same layout: %.2f s (bins/SH time %.2f)\n",
                b.basis.kind.c_str(), sh.raysPerNode, (unsigned long long)bs.nodes, (unsigned long long)bs.seamNodes,
                bs.seconds, int(std::get<int64_t>(b.meta.at("threads"))), 1440.0 / bs.seconds, sh.raysPerNode,
                ss.seconds, bs.seconds / ss.seconds);
    // The paper looked radiance up in a radiosity solution: one ray per direction. The
    // closest in ray count here is direct light only (one ray + one NEE shadow ray each).
    BinsBakeOptions direct = binsOptions(quick ? "bins:8" : "bins:17", 1, threads);
    direct.transport.maxBounces = 0;
    LevelsBakeStats ds;
    bakeBins(scene, tracer, layout, direct, nullptr, &ds);
    std::printf("  the same with 0 bounces (direct light only; about the paper's ray count): %.2f s, %.1f M rays\n",
                ds.seconds, double(ds.rays.total()) / 1e6);
}

void benchError(const Scene& scene, const Tracer& tracer, int threads, bool quick) {
    const LevelLayout layout = makeLayout(scene, LayoutKind::Uniform, quick ? 6 : 10, 1, 1);
    const int wanted = quick ? 150 : 1000;
    const Bounds box = layout.levels[0].grid.nodeBounds();
    std::vector<ReferencePoint> points;
    Rng rng(77);
    while (int(points.size()) < wanted) {
        const Vec3f x(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        if (freeSpace(tracer, x)) points.push_back({x, uniformSphere(rng.uniform(), rng.uniform())});
    }
    ReferenceOptions ro;
    ro.samples = quick ? 1024 : 8192;
    ro.threads = threads;
    // A second set at the nodes themselves (free-space nodes, random normals): no spatial
    // interpolation, so what remains is the directional representation (and noise).
    const GridSpec& grid = layout.levels[0].grid;
    for (std::size_t node = 0; node < grid.nodeCount() && int(points.size()) < 2 * wanted; ++node) {
        const Vec3f x(grid.node(node));
        if (freeSpace(tracer, x)) points.push_back({x, uniformSphere(rng.uniform(), rng.uniform())});
    }
    const std::size_t firstNode = std::size_t(wanted);
    const std::vector<ReferenceResult> ref = referenceIrradiance(scene, tracer, points, ro);
    double meanRef = 0;
    for (std::size_t i = 0; i < firstNode; ++i) meanRef += luminance(Rgb(ref[i].irradiance)) / double(firstNode);
    std::printf("error at %d free-space points with random normals (uniform %d^3 nodes, reference %u samples; relative "
                "to max(E_ref, 5 %% of the mean)):\n",
                wanted, layout.levels[0].grid.nx, ro.samples);
    std::printf("  (\"at nodes\": %zu free-space node positions with random normals: the directional error alone)\n",
                points.size() - firstNode);
    std::printf("  %-24s %8s %8s %10s %10s %14s %14s\n", "basis", "rays", "bake s", "RMS rel", "max rel", "RMS at nodes",
                "max at nodes");
    auto report = [&](const char* name, uint32_t rays, double seconds, const VolumeLookup& q) {
        ErrorStats s, atNodes;
        for (std::size_t i = 0; i < points.size(); ++i) {
            const double e = luminance(q.irradiance(points[i].position, normalize(points[i].normal)));
            const double r = luminance(Rgb(ref[i].irradiance));
            (i < firstNode ? s : atNodes).add(std::abs(e - r) / std::max(r, 0.05 * meanRef));
        }
        std::printf("  %-24s %8u %8.2f %9.2f%% %9.2f%% %13.2f%% %13.2f%%\n", name, rays, seconds, 100 * s.rms(),
                    100 * s.max, 100 * atNodes.rms(), 100 * atNodes.max);
        return atNodes.rms();
    };
    GatherOptions sh;
    sh.threads = threads;
    sh.raysPerNode = quick ? 128 : 578;
    BakeStats st;
    const Volume shv = bakeShGather(scene, tracer, layout.levels[0].grid, sh, nullptr, &st);
    report("sh2", sh.raysPerNode, st.seconds, ShUniformLookup(shv, OutsidePolicy::Clamp));
    struct Case {
        const char* basis;
        uint32_t samples;
    };
    const std::vector<Case> cases = quick ? std::vector<Case>{{"bins:8", 2}}
                                          : std::vector<Case>{{"bins:8", 4}, {"bins:17", 1}, {"bins:17", 4}};
    for (const Case& c : cases) {
        LevelsBakeStats bs;
        const Volume v = bakeBins(scene, tracer, layout, binsOptions(c.basis, c.samples, threads), nullptr, &bs);
        const uint32_t rays = uint32_t(v.basis.channelCount()) * c.samples;
        char name[64];
        std::snprintf(name, sizeof name, "%s nearest bin", c.basis);
        const double nearest = report(name, rays, bs.seconds, BinsLookup(v, OutsidePolicy::Clamp, false));
        std::snprintf(name, sizeof name, "%s blended bins", c.basis);
        const double blended = report(name, rays, bs.seconds, BinsLookup(v, OutsidePolicy::Clamp, true));
        std::printf("    blending neighbouring bins: RMS error at nodes x%.2f vs nearest bin\n", blended / nearest);
    }
}

void benchQuery(const Scene& scene, const Tracer& tracer, bool quick) {
    for (LayoutKind kind : {LayoutKind::Uniform, LayoutKind::Adaptive}) {
        const LevelLayout layout = makeLayout(scene, kind, 8, 2, 3);
        const Volume v = bakeBins(scene, tracer, layout, binsOptions("bins:17", 1, 0));
        const bench::LookupInputs in = bench::randomLookups(v.levels[0].grid.nodeBounds(), quick ? 200'000 : 2'000'000);
        for (bool blend : {false, true}) {
            const BinsLookup q(v, OutsidePolicy::Clamp, blend);
            Rgb sink{0, 0, 0};
            const double best = bench::lookupRate(q, in, quick ? 1 : 3, sink);
            std::printf("query bins:17 (%s, %zu levels, %llu nodes, %s, 1 thread): %.2f M lookups/s  [checksum %.3g]\n",
                        layoutName(kind), v.levels.size(), (unsigned long long)layout.totalNodes(),
                        blend ? "blended bins" : "nearest bin", best / 1e6, double(sink.x));
        }
    }
}

/// Reference moment H^n(r) = (n+1)/2 * integral of L max(0, w . r)^n: directions drawn from
/// the normalised lobe pdf (n+1)/(2 pi) cos^n, so the estimate is pi * mean radiance. The
/// radiance is path traced with full emission on a hit (infinite direction pdf: no NEE at
/// the first vertex, so no MIS partner is needed). Independent of the bins code.
double referenceMoment(const RadianceEstimator& est, const Vec3f& x, const Vec3f& r, int n, uint32_t samples,
                       uint64_t seed) {
    Vec3f t, b;
    orthonormalBasis(r, t, b);
    Rng rng(seed, 7);
    double sum = 0;
    RayCount count;
    for (uint32_t i = 0; i < samples; ++i) {
        float u, v;
        sobol02(i, seed, u, v);
        const float c = std::pow(1.0f - u, 1.0f / float(n + 1)), sn = std::sqrt(std::max(0.0f, 1.0f - c * c));
        const float phi = float(2 * kPi) * v;
        const Vec3f d = normalize(t * (sn * std::cos(phi)) + b * (sn * std::sin(phi)) + r * c);
        sum += luminance(est.gatherRadiance(x, d, std::numeric_limits<float>::infinity(), rng, count));
    }
    return kPi * sum / samples;
}

void benchMoment(const Scene& scene, const Tracer& tracer, int threads, bool quick) {
    const LevelLayout layout = makeLayout(scene, LayoutKind::Uniform, quick ? 4 : 8, 1, 1);
    LevelsBakeStats bs;
    const Volume v = bakeBins(scene, tracer, layout, binsOptions(quick ? "moment:8:8" : "moment:8", 1, threads), nullptr, &bs);
    const BinsLookup q(v, OutsidePolicy::Clamp);
    {  // error against the independent reference, at free-space nodes and random free-space points
        const RadianceEstimator est(scene, tracer);
        const GridSpec& g = v.levels[0].grid;
        const int wanted = quick ? 40 : 200;
        const uint32_t samples = quick ? 512 : 16384;
        std::vector<Vec3f> xs, rs;
        Rng rng(31);
        for (std::size_t node = 0; node < g.nodeCount() && int(xs.size()) < wanted; ++node)
            if (freeSpace(tracer, Vec3f(g.node(node)))) xs.push_back(Vec3f(g.node(node)));
        const std::size_t firstRandom = xs.size();
        const Bounds box = g.nodeBounds();
        while (xs.size() < firstRandom + std::size_t(wanted)) {
            const Vec3f x(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
            if (freeSpace(tracer, x)) xs.push_back(x);
        }
        for (std::size_t i = 0; i < xs.size(); ++i) rs.push_back(uniformSphere(rng.uniform(), rng.uniform()));
        std::vector<double> ref(xs.size());
        tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), xs.size(), [&](std::size_t i) {
                ref[i] = referenceMoment(est, xs[i], rs[i], 8, samples, 1000 + i);
            });
        });
        double mean = 0;
        for (double r : ref) mean += r / double(ref.size());
        ErrorStats atNodes, between;
        for (std::size_t i = 0; i < xs.size(); ++i) {
            const double e = luminance(q.irradiance(xs[i], rs[i]));
            (i < firstRandom ? atNodes : between).add(std::abs(e - ref[i]) / std::max(ref[i], 0.05 * mean));
        }
        std::printf("%s vs an independent glossy reference (%u lobe samples): RMS rel %.2f%% (max %.2f%%) at %d "
                    "free-space nodes, %.2f%% (max %.2f%%) at %d random free-space points\n",
                    v.basis.kind.c_str(), samples, 100 * atNodes.rms(), 100 * atNodes.max, atNodes.count,
                    100 * between.rms(), 100 * between.max, between.count);
    }
    const std::size_t n = quick ? 100'000 : 1'000'000;
    Rng rng(9);
    const Bounds b = v.levels[0].grid.nodeBounds();
    Rgb sink{0, 0, 0};
    const double t0 = now();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3f x(b.lo + b.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        const Vec3f nrm = uniformSphere(rng.uniform(), rng.uniform()), view = uniformSphere(rng.uniform(), rng.uniform());
        sink += q.irradiance(x, normalize(bins::reflectView(view, nrm)));
    }
    const double rate = double(n) / (now() - t0);
    std::printf("%s (%llu nodes, %d bins): bake %.2f s; %.2f M reflected-view lookups/s (1 thread, incl. reflection "
                "and random numbers)  [checksum %.3g]\n",
                v.basis.kind.c_str(), (unsigned long long)bs.nodes, v.basis.channelCount(), bs.seconds, rate / 1e6,
                double(sink.x));
}

}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_bins", {{"--threads", "N"}});
    if (!args.parse(argc, argv)) return 2;
    const bool quick = args.quick();
    const int threads = args.integer("--threads", 0);
    std::printf("vdblight_bench_bins%s\n", quick ? " (quick smoke run, noisy figures)" : "");
    try {
        const Scene scene = loadScene(defaultScenePath());
        const Tracer tracer(scene);
        std::printf("scene %s: %zu triangles\n", scene.name.c_str(), scene.triangleCount());
        benchPaperConfig(scene, tracer, threads, quick);
        benchError(scene, tracer, threads, quick);
        benchQuery(scene, tracer, quick);
        benchMoment(scene, tracer, threads, quick);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench_bins: %s\n", e.what());
        return 1;
    }
    return 0;
}
