// vdblight_bench_accuracy: every method and mode against converged ground truth (issue 15).
//
// Scenes (accuracy_scenes.h): an office with hanging luminaires, the Cornell box, two rooms
// joined by a door in a wall thinner than the node spacing (one lit), an outdoor scene with
// sun and sky. Points: 200 per scene, uniformly random in the scene's box, kept if in free
// space (no axis ray from them meets a back face first: not inside a solid) and at least 1 %
// of the box diagonal from any surface (not in crevices), each with a uniformly random unit
// normal; deterministic (fixed seed).
// Ground truth: `reference` (reference.h) with 256 bounces and --ref-samples samples per
// point, luminance; cached in the build directory (or --cache DIR) by scene content hash,
// point-set hash, samples, bounces and seed. Its relative standard error is printed.
// Error of a method at a point: (E - E_ref) / E_ref (luminance; E_ref guarded below by 1 % of
// the scene's mean). Per configuration: RMS, p95 and max of |error|, signed bias (mean
// error), bake seconds (wall, --threads, 2 by default) and the process's CPU seconds during
// the bake (on a shared machine the wall time includes waiting for a core), nodes and file
// bytes per node.
// Decomposition per scene (as issue 5 did it, docs/methods.md "Where the error comes from"):
//  - floor: the representation at each point itself (a node exactly there, projected with
//    many rays: no interpolation, little noise), for SH order 2 and for the six irradiance
//    vectors of the photon volumes; noise extrapolated out from N/4 and N rays (1/N law);
//  - spatial: a nearly noise-free uniform bake (many rays / photons) against the floor's
//    values at the points, i.e. what interpolation between nodes adds;
//  - noise: configurations marked so are baked again with seed 2 (not with --no-noise); the
//    per-bake noise is RMS((E1 - E2) / sqrt 2 / E_ref);
//  - bias: the mean signed error (every row).
// Regions (accuracy_scenes.h: the two rooms' lit and unlit room, the office's band around
// the luminaires) are reported on their own as well (CSV scene "SCENE:REGION").
// A new method or mode is one entry in configurations() (accuracy_configs.cpp): a name and a function that bakes
// (or otherwise builds) something that answers E(x, n).
// Output: tables on stdout, a CSV (--csv FILE; docs/accuracy.csv for the full run), which
// bench/plot_accuracy.sh turns into docs/images/accuracy_*.png.
// The parts: accuracy.h.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "accuracy.h"
#include "bench_args.h"

using namespace vdblight;

namespace {
/// --config: a comma-separated list; an entry selects the configuration of exactly that name
/// if there is one, else every configuration it is a prefix of (--config direct_).
bool configSelected(const std::string& list, const std::string& name, const std::vector<accuracy::Config>& all) {
    if (list.empty()) return true;
    std::size_t pos = 0;
    while (pos <= list.size()) {
        std::size_t end = list.find(',', pos);
        if (end == std::string::npos) end = list.size();
        const std::string entry = list.substr(pos, end - pos);
        pos = end + 1;
        if (entry.empty()) continue;
        const bool exact = std::any_of(all.begin(), all.end(), [&](const accuracy::Config& c) { return c.name == entry; });
        if (exact ? name == entry : name.rfind(entry, 0) == 0) return true;
    }
    return false;
}
}  // namespace

int main(int argc, char** argv) {
    using namespace vdblight::accuracy;
    bench::BenchArgs args("vdblight_bench_accuracy", {{"--csv", "FILE"},
                                                      {"--scene", "NAME"},
                                                      {"--config", "NAME"},
                                                      {"--threads", "N"},
                                                      {"--points", "N"},
                                                      {"--ref-samples", "N"},
                                                      {"--cache", "DIR"},
                                                      {"--worst", "N"},
                                                      {"--guard", "F"},
                                                      {"--try", "SPECS"},
                                                      {"--no-decompose", ""},
                                                      {"--no-noise", ""},
                                                      {"--seed", "N"},
                                                      {"--study", "R"},
                                                      {"--study-floor", "F"},
                                                      {"--time-to", "E"},
                                                      {"--probe-study", "R0"},
                                                      {"--probe-rays", "K"},
                                                      {"--probe-paths", "M"}});
    if (!args.parse(argc, argv)) return 1;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress visible when redirected to a file
    Settings st;
    st.quick = args.quick();
    st.threads = args.integer("--threads", 2);
    st.points = args.integer("--points", st.quick ? 60 : 200);
    st.refSamples = uint32_t(args.integer("--ref-samples", st.quick ? 2048 : 65536));
    st.floorRays = st.quick ? 512 : 8192;
    st.spatialRays = st.quick ? 128 : 1024;
    st.spatialPhotons = st.quick ? 1'000'000 : 4'000'000;
    st.cache = args.given("--cache") ? fs::path(args.text("--cache")) : defaultCache(argv[0]);
    const std::string onlyScene = args.text("--scene"), onlyConfig = args.text("--config");
    const bool decompose = !args.given("--no-decompose");
    FILE* csv = nullptr;
    if (args.given("--csv") && !(csv = std::fopen(args.text("--csv").c_str(), "w"))) {
        std::fprintf(stderr, "vdblight_bench_accuracy: cannot write %s\n", args.text("--csv").c_str());
        return 1;
    }
    if (csv) std::fprintf(csv, "scene,config,rms,p95,max,bias,bake_seconds,cpu_seconds,nodes,bytes_per_node,noise_rms,note\n");
    // Reference, floor and spatial runs use this many threads too (the bakes take --threads).
    tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(std::max(1, st.threads)));

    std::vector<Config> configs = configurations();
    // --try SPEC (repeatable as SPEC;SPEC): candidate defaults, named try_<spec>, measured with noise.
    if (args.given("--try")) {
        const std::string all = args.text("--try");
        std::size_t pos = 0;
        while (pos <= all.size()) {
            std::size_t end = all.find(';', pos);
            if (end == std::string::npos) end = all.size();
            const std::string spec = all.substr(pos, end - pos);
            pos = end + 1;
            if (spec.empty()) continue;
            const TrySpec t = parseTry(spec);
            std::string name = "try:" + spec;  // no commas in the CSV's config column
            std::replace(name.begin(), name.end(), ',', '/');
            configs.push_back({name, "--try " + spec, [t](const Ctx& c) { return tryBake(c, t); }, true});
        }
    }
    std::printf("vdblight_bench_accuracy%s: %d points per scene, ground truth %u samples x %d bounces, %d threads\n",
                st.quick ? " --quick (small workloads)" : "", st.points, st.refSamples, st.refBounces, st.threads);
    std::vector<Row> summary;
    for (bench::AccuracyScene& as : bench::accuracyScenes()) {
        if (!onlyScene.empty() && as.name != onlyScene) continue;
        const Scene& s = as.scene;
        const Tracer tracer(s);
        const Points pts = freeSpacePoints(s, tracer, st.points);
        std::printf("\n%s: %zu triangles, box %.2f x %.2f x %.2f, %zu free-space points\n", as.name.c_str(),
                    s.triangleCount(), s.bounds().size().x, s.bounds().size().y, s.bounds().size().z, pts.x.size());
        Truth truth = groundTruth(s, tracer, pts, st, st.refSamples * uint32_t(as.referenceScale));
        truth.guard = args.real("--guard", truth.guard);
        {
            std::vector<double> rse(truth.e.size());
            for (std::size_t i = 0; i < rse.size(); ++i) rse[i] = truth.se[i] / truth.denominator(i);
            const Errors e = summarise(rse);
            std::printf("  ground truth relative standard error: RMS %.2f %%, p95 %.2f %%, max %.2f %% (mean E %.4g)\n",
                        100 * e.rms, 100 * e.p95, 100 * e.max, truth.mean);
            Row r{as.name, "reference_se", e};
            writeCsvRow(csv, r);
        }
        std::printf("  %-18s %9s %9s %10s %9s %10s %9s %8s %9s %8s\n", "config", "RMS", "p95", "max", "bias", "bake", "CPU",
                    "nodes", "B/node", "noise");
        for (const Config& c : configs) {
            if (!configSelected(onlyConfig, c.name, configs)) continue;
            Row r{as.name, c.name};
            std::vector<double> rel, noiseRel;  // per point: error, and (E1 - E2) / sqrt 2 / E_ref
            try {
                const double cpu0 = cpuSeconds();
                // --seed N: the bakes' seed (default 1; the noise bake takes N + 1), to see a
                // row's spread over seeds.
                const uint64_t seed = uint64_t(args.integer("--seed", 1));
                const Baked b = c.bake(Ctx{s, tracer, st, seed});
                r.cpu = cpuSeconds() - cpu0;
                const std::vector<double> got = values(b.irradiance, pts);
                rel = relative(got, truth.e, truth);
                r.e = summarise(rel);
                printWorst(rel, got, truth, pts, args.integer("--worst", 0));
                r.seconds = b.seconds;
                r.nodes = b.nodes;
                r.bytesPerNode = b.nodes ? double(b.bytes) / double(b.nodes) : 0;
                r.note = b.note;
                if (c.noise && !args.given("--no-noise")) {  // --no-noise: one bake per row (time curves)
                    const Baked b2 = c.bake(Ctx{s, tracer, st, seed + 1});
                    const std::vector<double> got2 = values(b2.irradiance, pts);
                    double s2 = 0;
                    for (std::size_t i = 0; i < got.size(); ++i) {
                        const double d = (got[i] - got2[i]) / std::sqrt(2.0) / truth.denominator(i);
                        noiseRel.push_back(d);
                        s2 += d * d;
                    }
                    r.noise = std::sqrt(s2 / double(got.size()));
                }
            } catch (const Error& e) {
                std::printf("  %-18s failed: %s\n", c.name.c_str(), e.what());
                continue;
            }
            printRow(r);
            writeCsvRow(csv, r);
            summary.push_back(r);
            for (const bench::AccuracyRegion& region : as.regions) {
                std::vector<double> part;
                double n2 = 0;
                for (std::size_t i = 0; i < pts.x.size(); ++i)
                    if (region.contains(pts.x[i])) {
                        part.push_back(rel[i]);
                        if (!noiseRel.empty()) n2 += noiseRel[i] * noiseRel[i];
                    }
                if (part.empty()) continue;
                Row rr{as.name + ":" + region.name, c.name, summarise(part)};
                rr.note = std::to_string(part.size()) + " points";
                if (!noiseRel.empty()) rr.noise = std::sqrt(n2 / double(part.size()));
                char noise[32] = "";
                if (rr.noise >= 0) std::snprintf(noise, sizeof noise, ", noise %.1f %%", 100 * rr.noise);
                std::printf("    %-16s %7.1f %% %7.1f %% %8.1f %% %+7.1f %%  (%zu points%s)\n", region.name.c_str(), 100 * rr.e.rms,
                            100 * rr.e.p95, 100 * rr.e.max, 100 * rr.e.bias, part.size(), noise);
                writeCsvRow(csv, rr);
            }
        }
        if (args.given("--time-to")) timeToAccuracy(as, tracer, pts, truth, st, args.real("--time-to", 0.09), csv);
        if (args.given("--study")) studyDefault(as, tracer, pts, truth, st, uint32_t(args.integer("--study", 512)),
                                                  uint32_t(args.integer("--study-floor", 32768)), csv);
        if (args.given("--probe-study"))
            probeCacheStudy(as, tracer, pts, truth, st, uint32_t(args.integer("--probe-study", 2048)),
                            uint32_t(args.integer("--probe-rays", 2048)), args.integer("--probe-paths", 4));
        if (decompose) accuracy::decompose(as, tracer, pts, truth, st, csv);
    }

    printSummary(configs, summary);
    if (csv) std::fclose(csv);
    return 0;
}
