// vdblight_bench_converge: skip what a scene does not need (issue 8).
//
// Part 1, error-targeted bake (bake_adaptive.h) on the default scene: the fixed-budget bake
// with N rays per node has a worst node error; the error-targeted bake with that target and
// at most N rays reaches it everywhere. Printed: gathered rays and wall time of both, the
// estimated error distribution, and the error of each node's mean irradiance (SH DC) against
// a converged estimate (independent seed, 16x the rays) -- measured, not estimated.
//
// Part 2, many lights (light/light_tree.h): a 64 x 64 floor with blocks and L point
// lights scattered over it (total intensity fixed), L = 100 ... 10000. Each light count is
// baked to the same target error (error-targeted bake) with the oriented light tree
// ("oriented", the default), with the earlier power/distance tree ("tree", before:
// TransportOptions::orientedLightTree = false) and, where it is affordable, with every light
// evaluated exactly at every vertex ("exact"). Printed: seconds, rays, the measured error
// against a converged estimate, and per light count the rays each sampler needs at equal
// (target) error against the exact path, and the time growth with the light count.
// Part 3, many emissive triangles: the same floor under L small emitters, the global power
// CDF (before) against the oriented light tree (now), rays at equal target error.
// `--quick` shrinks the workloads for CI.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "bench_args.h"
#include "bench_scenes.h"
#include "bench_util.h"

#include "support/scene_generators.h"

using namespace vdblight;

namespace {
double ebarOf(const float* node) {
    constexpr double kY00 = 0.28209479177387814;
    return kPi * kY00 * double(luminance(Rgb(node[0], node[1], node[2])));
}

// Converged mean irradiance per node (independent seed, `rays` per node); prints the
// converged values' own worst estimated relative standard error.
std::vector<double> convergedEbar(const Scene& s, const Tracer& tracer, const GridSpec& g, uint32_t rays,
                                  const TransportOptions& t) {
    AdaptiveOptions o;
    o.targetError = 1e-9;
    o.minRays = o.maxRays = rays;
    o.seed = 424242;
    o.transport = t;
    AdaptiveStats st;
    const Volume v = bakeShGatherAdaptive(s, tracer, g, o, nullptr, &st);
    std::vector<double> out(g.nodeCount());
    for (std::size_t n = 0; n < out.size(); ++n) out[n] = ebarOf(v.levels[0].data.data() + n * 27);
    std::printf("(converged values: %u rays per node, their own estimated relative standard error p50 %.4f, max %.4f)\n",
                rays, st.errorQuantile(0.5), st.errorQuantile(1.0));
    return out;
}

struct Measured {
    double max = 0, p95 = 0, rms = 0;
};
Measured measure(const Volume& v, const std::vector<double>& truth) {
    std::vector<double> e;
    for (std::size_t n = 0; n < truth.size(); ++n)
        if (truth[n] > 0) e.push_back(std::abs(ebarOf(v.levels[0].data.data() + n * 27) - truth[n]) / truth[n]);
    std::sort(e.begin(), e.end());
    Measured m;
    if (e.empty()) return m;
    double s2 = 0;
    for (double x : e) s2 += x * x;
    m.rms = std::sqrt(s2 / e.size());
    m.max = e.back();
    m.p95 = e[std::min(e.size() - 1, std::size_t(std::ceil(0.95 * e.size())) - 1)];
    return m;
}

/// One layer of nodes 1.5 above the 64 x 64 floor of the generated scenes (bench_scenes.h),
/// between the blocks, none inside one.
GridSpec betweenTheBlocks(bool quick) {
    GridSpec g;
    g.origin = Vec3d(4, 1.5, 4);
    g.spacing = quick ? 16 : 8;
    g.nx = g.nz = quick ? 4 : 8;
    g.ny = 1;
    return g;
}

void partAdaptive(bool quick) {
    const Scene s = loadScene(defaultScenePath());
    const Tracer tracer(s);
    const GridSpec g = bench::uniformGrid(s.bounds(), quick ? 5 : 8);
    const uint32_t budget = quick ? 512 : 2048;
    std::printf("\n== Error-targeted bake: default scene, %d x %d x %d nodes, fixed budget %u rays/node ==\n", g.nx, g.ny,
                g.nz, budget);
    const std::vector<double> truth = convergedEbar(s, tracer, g, 16 * budget, TransportOptions{});

    AdaptiveOptions fixed;
    fixed.targetError = 1e-9;
    fixed.minRays = fixed.maxRays = budget;
    AdaptiveStats f;
    const Volume vf = bakeShGatherAdaptive(s, tracer, g, fixed, nullptr, &f);
    const Measured mf = measure(vf, truth);

    std::printf("%-30s %10s %8s %12s %12s %12s %12s %12s\n", "bake", "rays/node", "seconds", "est.err p50",
                "est.err max", "meas.err rms", "meas.err p95", "meas.err max");
    std::printf("%-30s %10.0f %8.3f %12.4f %12.4f %12.4f %12.4f %12.4f\n", "fixed", double(f.samples) / g.nodeCount(),
                f.seconds, f.errorQuantile(0.5), f.errorQuantile(1.0), mf.rms, mf.p95, mf.max);
    // Equal maximum error: the target starts at the fixed bake's worst estimated error and is
    // lowered until the error-targeted bake's worst MEASURED error is at most the fixed one's.
    for (double factor : {1.0, 0.8, 0.65, 0.5, 0.4}) {
        AdaptiveOptions o;
        o.targetError = factor * f.errorQuantile(1.0);
        o.maxRays = budget;
        AdaptiveStats a;
        const Volume va = bakeShGatherAdaptive(s, tracer, g, o, nullptr, &a);
        const Measured ma = measure(va, truth);
        char name[64];
        std::snprintf(name, sizeof name, "error-targeted %.4f", o.targetError);
        std::printf("%-30s %10.0f %8.3f %12.4f %12.4f %12.4f %12.4f %12.4f\n", name, double(a.samples) / g.nodeCount(),
                    a.seconds, a.errorQuantile(0.5), a.errorQuantile(1.0), ma.rms, ma.p95, ma.max);
        if (ma.max <= mf.max) {
            std::printf("at equal maximum measured error (%.4f <= %.4f): error-targeted / fixed gathered rays %.3f, "
                        "all rays %.3f, seconds %.3f\n",
                        ma.max, mf.max, double(a.samples) / double(f.samples),
                        double(a.rays.total()) / double(f.rays.total()), a.seconds / f.seconds);
            break;
        }
    }

    // A sweep of targets: rays used and honesty (share of nodes within 1.5x of the target).
    std::printf("%-8s %10s %8s %14s %14s\n", "target", "rays/node", "seconds", "within 1.5x", "nodes at max");
    for (double target : {0.08, 0.04, 0.02, 0.01}) {
        AdaptiveOptions t;
        t.targetError = target;
        t.maxRays = 16 * budget;
        AdaptiveStats st;
        const Volume v = bakeShGatherAdaptive(s, tracer, g, t, nullptr, &st);
        int within = 0, total = 0;
        for (std::size_t n = 0; n < truth.size(); ++n) {
            if (!(truth[n] > 0)) continue;
            ++total;
            if (std::abs(ebarOf(v.levels[0].data.data() + n * 27) - truth[n]) / truth[n] <= 1.5 * target) ++within;
        }
        std::printf("%-8.3f %10.0f %8.3f %13.1f%% %14llu\n", target, double(st.samples) / g.nodeCount(), st.seconds,
                    100.0 * within / total, (unsigned long long)st.nodesAtMax);
    }
}

void partManyLights(bool quick) {
    const double target = 0.03;
    std::printf("\n== Many lights: 64 x 64 floor + 16 blocks, L point lights, baked to target error %.2f ==\n", target);
    std::printf("%-7s %-9s %8s %10s %12s %12s %12s\n", "lights", "lights", "seconds", "rays/node", "shadow rays",
                "meas.err p95", "meas.err max");
    const std::vector<int> counts = quick ? std::vector<int>{100, 1000} : std::vector<int>{100, 300, 1000, 3000, 10000};
    double firstSampled[2] = {0, 0}, firstExact = 0;
    for (int lights : counts) {
        const Scene s = bench::manyLightsScene(lights);
        const Tracer tracer(s);
        const GridSpec g = betweenTheBlocks(quick);
        TransportOptions t;
        t.maxBounces = 2;
        const std::vector<double> truth = convergedEbar(s, tracer, g, quick ? 8192 : 65536, t);
        double raysExact = 0, raysMode[2] = {0, 0};
        for (int mode : {0, 1, 2}) {  // 0: tree (before), 1: oriented (now), 2: exact
            const bool exact = mode == 2;
            const char* name = mode == 0 ? "tree" : (mode == 1 ? "oriented" : "exact");
            if (exact && lights > (quick ? 100 : 1000)) {
                std::printf("%-7d %-9s %8s  (skipped: every light at every vertex)\n", lights, "exact", "-");
                continue;
            }
            AdaptiveOptions o;
            o.targetError = target;
            o.maxRays = 16384;
            o.transport = t;
            o.transport.exactLightLimit = exact ? (1u << 30) : 16;
            o.transport.orientedLightTree = mode != 0;
            AdaptiveStats st;
            const Volume v = bakeShGatherAdaptive(s, tracer, g, o, nullptr, &st);
            const Measured m = measure(v, truth);
            if (std::getenv("VDBLIGHT_BENCH_DEBUG"))
                for (std::size_t n = 0; n < truth.size(); ++n)
                    std::printf("   node %zu truth %.5f baked %.5f est %.4f rays %u\n", n, truth[n],
                                ebarOf(v.levels[0].data.data() + n * 27), st.estimatedError[n], st.raysPerNode[n]);
            std::printf("%-7d %-9s %8.3f %10.0f %12llu %12.4f %12.4f\n", lights, name, st.seconds,
                        double(st.samples) / g.nodeCount(), (unsigned long long)st.rays.occluded, m.p95, m.max);
            if (exact) raysExact = double(st.samples);
            else raysMode[mode] = double(st.samples);
            double& first = mode == 2 ? firstExact : firstSampled[mode];
            if (first == 0) first = st.seconds;
            else
                std::printf("        %s: light count x%.0f, time x%.2f\n", name, double(lights) / counts[0], st.seconds / first);
        }
        if (raysExact > 0)
            std::printf("        rays per node at equal target error vs the exact path: tree (before) x%.2f, oriented (now) x%.2f\n",
                        raysMode[0] / raysExact, raysMode[1] / raysExact);
        std::printf("        oriented vs tree at equal target error: rays x%.2f\n", raysMode[1] / raysMode[0]);
    }
}

// Part 3: the same floor lit by L small one-sided emissive triangles facing down (total power
// fixed) instead of point lights: the global power CDF (before) against the oriented light
// tree (now), baked to the same target error.
Scene manyEmittersScene(int count) {
    Scene s = bench::manyLightsScene(0);
    Material m;
    m.name = "small_emitter";
    const float side = 0.2f;
    m.emission = Rgb(1, 1, 1) * (2000.0f / float(count) / (0.5f * side * side * float(kPi)));
    const uint32_t id = addMaterial(s, m);
    Rng rng(99);
    for (int l = 0; l < count; ++l) {
        const Vec3f p(64 * rng.uniform(), 0.5f + 3.5f * rng.uniform(), 64 * rng.uniform());
        const float r = 0.5f + rng.uniform();
        (void)r;
        addTriangle(s, p, p + Vec3f(side, 0, 0), p + Vec3f(0, 0, side), id);  // normal -y: facing the floor
    }
    s.name = "many_emitters_" + std::to_string(count);
    return s;
}

void partManyEmitters(bool quick) {
    const uint32_t rays = quick ? 1024 : 4096;
    std::printf("\n== Many emissive triangles: 64 x 64 floor + 16 blocks, L small emitters facing down, %u rays per node ==\n",
                rays);
    std::printf("%-8s %-7s %8s %14s %14s %12s\n", "emitters", "choice", "seconds", "est.err p50", "est.err p95",
                "meas.err rms");
    const std::vector<int> counts = quick ? std::vector<int>{1000} : std::vector<int>{100, 1000, 10000};
    for (int count : counts) {
        const Scene s = manyEmittersScene(count);
        const Tracer tracer(s);
        const GridSpec g = betweenTheBlocks(quick);
        TransportOptions t;
        t.maxBounces = 2;
        const std::vector<double> truth = convergedEbar(s, tracer, g, quick ? 8192 : 65536, t);
        double err[2] = {0, 0}, secs[2] = {0, 0};
        for (int mode : {0, 1}) {  // 0: global power CDF (before), 1: oriented tree (now)
            AdaptiveOptions o;  // fixed budget: every node takes `rays`; its estimated error is measured
            o.targetError = 1e-9;
            o.minRays = o.maxRays = rays;
            o.transport = t;
            o.transport.orientedLightTree = mode == 1;
            AdaptiveStats st;
            const Volume v = bakeShGatherAdaptive(s, tracer, g, o, nullptr, &st);
            const Measured m = measure(v, truth);
            err[mode] = st.errorQuantile(0.5);
            secs[mode] = st.seconds;
            std::printf("%-8d %-7s %8.3f %14.4f %14.4f %12.4f\n", count, mode ? "tree" : "cdf", st.seconds,
                        st.errorQuantile(0.5), st.errorQuantile(0.95), m.rms);
        }
        const double rayRatio = (err[1] / err[0]) * (err[1] / err[0]);
        std::printf("        tree vs CDF: rays at equal (median estimated) error x%.2f, time at equal error x%.2f\n",
                    rayRatio, rayRatio * secs[1] / secs[0]);
    }
}
}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_converge", {});
    if (!args.parse(argc, argv)) return 2;
    const bool quick = args.quick();
    std::printf("vdblight_bench_converge%s\n", quick ? " --quick (small workloads, noisy figures)" : "");
    partAdaptive(quick);
    partManyLights(quick);
    partManyEmitters(quick);
    return 0;
}
