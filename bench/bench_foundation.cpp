// vdblight_bench: the foundation's speed figures, measured in one run on one machine.
//
// For each scene (the default Cornell box, and the box with >= 100 000 extra triangles):
//  - raw Embree throughput: random rays inside the scene, plain rtcIntersect1 (and
//    rtcOccluded1), on the same number of threads as the bake;
//  - the bake's own rays/s (closest-hit + shadow rays) and the ratios to the raw figures;
// and, once, the query throughput per thread (random points and normals), for SH order 2 and
// the default's SH order 4, each without and with depth moments, and the default volume (SH
// order 4, depth moments, per-light visibility); beside each, the memory-bandwidth bound of the
// same access pattern (lookup_bound.h), measured in the same run (for the default volume also
// at points whose nodes stay in the cache: its arithmetic alone); and beside each, the lookup
// an engine runs on the same volume exported to NanoVDB (shaders/vdblight_nanovdb.h compiled as
// C, tests/nanovdb_lookup_c.c) on the same inputs, with its worst difference to query.
// `--quick` shrinks every workload for a CI smoke run; the figures are then noisy.
// `--only query` runs the query rows alone (`--only bake`: the scenes alone).
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "basis/shadow_edges.h"
#include "query/channel_lookup.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/query/query.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/query/sh4_uniform_lookup.h"  // internal: the lookups' layouts, for the bound
#include "../libvdblight/src/query/sh_trilinear.h"
#include "../libvdblight/src/query/sh_uniform_lookup.h"
#include "query/query_direct.h"
#include "../libvdblight/src/trace/random_rays.h"  // internal: traceRandomRays, the raw Embree probe
#include "bench_args.h"
#include "bench_scenes.h"
#include "bench_util.h"
#include "lookup_bound.h"
#include "nanovdb_grid_words.h"
#include "nanovdb_lookup_c.h"

#include "support/scene_generators.h"

using namespace vdblight;
using bench::now;

namespace {
// Rays/s of `total` random rays split over `threads` workers; best of `repeats`.
double rawRaysPerSecond(const Tracer& tracer, const Bounds& box, std::size_t total, int threads, bool occlusion,
                        int repeats) {
    double best = 0;
    tbb::task_arena arena(threads);
    for (int r = 0; r < repeats; ++r) {
        std::atomic<std::size_t> hits{0};
        const double t0 = now();
        arena.execute([&] {
            tbb::parallel_for(0, threads, [&](int w) {
                hits += traceRandomRays(tracer, box, total / threads, uint64_t(r) * 1000 + w, occlusion);
            });
        });
        const double dt = now() - t0;
        best = std::max(best, double(total / threads * threads) / dt);
        if (hits == std::size_t(-1)) std::puts("");  // keep the result alive
    }
    return best;
}

/// `basis`: what the gather stores (null: SH order 2; "sh:4": the default bake's basis).
void benchScene(const Scene& scene, int threads, bool quick, const char* basis = nullptr) {
    const Tracer tracer(scene);
    Bounds box = scene.bounds();
    // Origins strictly inside the scene bounds (the room), as a bake's nodes are.
    const Vec3d inset = box.size() * 0.01;
    box.lo += inset;
    box.hi -= inset;

    const std::size_t rawRays = quick ? 400'000 : 4'000'000;
    const GridSpec grid = bench::uniformGrid(scene.bounds(), quick ? 8 : 16);
    GatherOptions options;
    options.raysPerNode = quick ? 64 : 512;
    options.threads = threads;
    if (basis) options.basis = makeBasis(basis);

    // Raw and bake measurements are interleaved and the best of each kept, so that a
    // transient load on the machine does not distort the ratio.
    double rawIntersect = 0, rawOccluded = 0, bake = 0;
    BakeStats stats;
    for (int r = 0; r < (quick ? 1 : 3); ++r) {
        rawIntersect = std::max(rawIntersect, rawRaysPerSecond(tracer, box, rawRays, threads, false, 1));
        rawOccluded = std::max(rawOccluded, rawRaysPerSecond(tracer, box, rawRays, threads, true, 1));
        BakeStats run;
        bakeShGather(scene, tracer, grid, options, nullptr, &run);
        if (run.raysPerSecond() > bake) {
            bake = run.raysPerSecond();
            stats = run;
        }
    }
    // The bake mixes closest-hit and (cheaper) shadow rays: the raw rate of the same mix.
    const double mixTime = double(stats.rays.intersect) / rawIntersect + double(stats.rays.occluded) / rawOccluded;
    const double rawMix = double(stats.rays.total()) / mixTime;

    std::printf("%-22s %-4s %9zu tris %2d thr | raw rtcIntersect1 %7.2f M/s  rtcOccluded1 %7.2f M/s | bake %7.2f M/s "
                "(%zu nodes x %u rays, %.1f%% shadow rays, %.2f s) | bake/raw intersect %.2f  bake/raw same mix %.2f\n",
                scene.name.c_str(), basis ? basis : "sh2", scene.triangleCount(), threads, rawIntersect / 1e6,
                rawOccluded / 1e6, bake / 1e6,
                grid.nodeCount(), options.raysPerNode, 100.0 * double(stats.rays.occluded) / double(stats.rays.total()),
                stats.seconds, bake / rawIntersect, bake / rawMix);
}

/// The node arrays (floats per node of each) that the lookup `kind` reads at each corner, in its
/// own layout: sh2 its coefficients and the depth moments apart (query/sh_uniform_lookup.h);
/// sh:4 one record per node, the depth values inside it (query/sh4_uniform_lookup.h).
std::vector<int> nodeArraysRead(const std::string& kind, bool depth) {
    if (kind == "sh2-uniform") {
        if (depth) return {query_detail::kShFloats, depth::kFloatsPerNode};
        return {query_detail::kShFloats};
    }
    if (kind == "sh4-uniform")
        return {ShFourUniformLookup::kLitStride + (depth ? query_detail::kPreparedDepthFloats : 0)};
    throw ValueError("vdblight_bench: no bound for lookup kind " + kind);
}

/// The sh2 / sh:4 lookup of `kind` in its portable (SSE2) or its AVX2 build (`wide`; the same
/// bits, query/wide_vectors.h), or null for other kinds.
std::unique_ptr<VolumeLookup> buildOf(const Volume& volume, const std::string& kind, bool wide) {
    if (kind == "sh2-uniform") {
        auto sh2 = std::make_unique<ShUniformLookup>(volume, OutsidePolicy::Clamp);
        sh2->setWideVectors(wide);
        return sh2;
    }
    if (kind == "sh4-uniform") {
        auto sh4 = std::make_unique<ShFourUniformLookup>(volume, OutsidePolicy::Clamp);
        sh4->setWideVectors(wide);
        return sh4;
    }
    return nullptr;
}

/// The default volume's lookup as it ran before issue 33's fourth session: the portable blend,
/// the visibility located again in double, the lights in double (setShareBaseCell(false)).
std::unique_ptr<VolumeLookup> previousOcclusionLookup(const Volume& volume, const std::string& kind) {
    std::unique_ptr<VolumeLookup> base = buildOf(volume, kind, false);
    if (!base) return nullptr;
    auto occlusion = std::make_unique<OcclusionLookup>(std::move(base), volume);
    occlusion->setShareBaseCell(false);
    return occlusion;
}

/// The PNanoVDB lookup compiled as C (vdblightNanoIrradiance) on `volume` exported by
/// exportNanoVdb, with a lookup's irradiance(x, n), so that bench::lookupRate times it as it
/// times query. The export goes through a temporary file (removed at once) and is held as a
/// renderer uploads it: the grid buffers back to back, in 64-bit words (PNanoVDB reads 64-bit
/// values at 8-byte aligned offsets). Each call opens the volume (vdblight_nano_open reads the
/// metadata grid), as the C entry point does.
class NanoLookup {
public:
    explicit NanoLookup(const Volume& volume) {
        const std::filesystem::path file =
            std::filesystem::temp_directory_path() / ("vdblight_bench_" + std::to_string(::getpid()) + ".nvdb");
        struct Remove {
            const std::filesystem::path& path;
            ~Remove() {
                std::error_code ignored;
                std::filesystem::remove(path, ignored);
            }
        } remove{file};
        fileBytes_ = exportNanoVdb(volume, file.string()).bytes;
        words_ = test::nanoGridWords(file.string());
        float e[3];
        const float x[3] = {0, 0, 0}, n[3] = {0, 0, 1};
        if (!vdblightNanoIrradiance(buffer(), x, n, e)) throw ValueError("vdblight_bench: the NanoVDB lookup does not read this volume");
    }
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const {
        const float xs[3] = {x.x, x.y, x.z}, ns[3] = {n.x, n.y, n.z};
        float e[3];
        vdblightNanoIrradiance(buffer(), xs, ns, e);
        return Rgb{e[0], e[1], e[2]};
    }
    uint64_t fileBytes() const { return fileBytes_; }

private:
    const uint32_t* buffer() const { return reinterpret_cast<const uint32_t*>(words_.data()); }
    std::vector<uint64_t> words_;
    uint64_t fileBytes_ = 0;
};

/// The worst relative difference of `b` to `a` over the inputs, per colour, relative to
/// max(|a|, 1 % of a's RMS) as nanovdb_export_test measures it (irradiance passes through 0).
template <class A, class B>
double worstRelativeDifference(const A& a, const B& b, const bench::LookupInputs& in) {
    std::vector<Rgb> expected(in.points.size());
    double squares = 0;
    for (std::size_t i = 0; i < in.points.size(); ++i) {
        expected[i] = a.irradiance(in.points[i], in.normals[i]);
        for (int c = 0; c < 3; ++c) squares += double(expected[i][c]) * expected[i][c];
    }
    const double floor = 0.01 * std::sqrt(squares / (3.0 * double(in.points.size())));
    double worst = 0;
    for (std::size_t i = 0; i < in.points.size(); ++i) {
        const Rgb e = b.irradiance(in.points[i], in.normals[i]);
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::fabs(double(e[c]) - expected[i][c]) / std::max(std::fabs(double(expected[i][c])), floor));
    }
    return worst;
}

/// `basis` as in benchScene; `depth`: the volume carries depth moments (GatherOptions::
/// depthMoments), which the lookup then weights its corners by, as the default bake's;
/// `visibility`: also `--direct occlusion`'s per-light visibility (the default bake's: the
/// lookup adds each light's exact direct light times its interpolated visibility). `target`:
/// the goal for the row in M lookups/s (0: none).
void benchQuery(bool quick, const char* basis, bool depth, bool visibility, double target) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const GridSpec grid = bench::uniformGrid(scene.bounds(), 32);
    GatherOptions options;
    options.raysPerNode = 1;  // values do not matter for lookup speed
    if (basis) options.basis = makeBasis(basis);
    options.depthMoments = depth;
    Volume volume = bakeShGather(scene, tracer, grid, options);
    if (visibility) {
        DirectOptions direct;
        direct.mode = DirectMode::Occlusion;
        direct.visibilitySamples = 4;  // values do not matter here either
        bakeLightVisibility(scene, tracer, planDirectLight(scene, tracer, grid, direct), direct, volume);
    }
    const IrradianceQuery query(volume);

    // The bound reads the same bytes per corner: the lookup's coefficients and depth moments,
    // the lights' visibility and, where the volume has them (the default's), their shadow edges
    // (shadow_edges.h: kFloatsPerLight floats per node and light, of which a lookup reads three
    // in one run of 24 bytes).
    std::vector<int> floatsPerNode = nodeArraysRead(query.kind(), depth);
    if (visibility) floatsPerNode.push_back(int(volume.direct.lights.size()));
    if (visibility && !volume.levels[0].lightShadowEdges.empty())
        floatsPerNode.push_back(int(volume.direct.lights.size()) * shadow_edge::kFloatsPerLight);
    int bytes = 0;
    for (const int f : floatsPerNode) bytes += 4 * f;
    const std::vector<bench::GatheredArray> arrays = bench::gatheredArrays(grid, floatsPerNode);

    // Pre-generate inputs so that only lookups are timed; lookup and bound runs alternate and
    // the best of each is kept, so that a transient load on the machine hits both alike.
    const bench::LookupInputs in = bench::randomLookups(grid.nodeBounds(), quick ? 200'000 : 2'000'000);
    // The NanoVDB lookup is 4-10x slower: in the smoke run it takes the first 20 000 inputs alone.
    const NanoLookup nano(volume);
    const bench::LookupInputs nanoIn =
        quick ? bench::LookupInputs{{in.points.begin(), in.points.begin() + 20'000}, {in.normals.begin(), in.normals.begin() + 20'000}}
              : in;
    Rgb sink{0, 0, 0}, nanoSink{0, 0, 0};
    float boundSink = 0;
    double best = 0, bound = 0, nanoBest = 0;
    for (int r = 0; r < (quick ? 1 : 5); ++r) {
        best = std::max(best, bench::lookupRate(query, in, 1, sink));
        bound = std::max(bound, bench::gatherBoundRate(grid, arrays, in, 1, boundSink));
        nanoBest = std::max(nanoBest, bench::lookupRate(nano, nanoIn, 1, nanoSink));
    }
    char goal[32] = "";
    if (target > 0) std::snprintf(goal, sizeof goal, " (target >= %g)", target);
    const std::string name = std::string(basis ? basis : "sh2") + (depth ? " +depth" : "") + (visibility ? " +vis" : "");
    std::printf("query %-16s (32^3 nodes, 1 thread, lookup %s%s): %.2f M lookups/s per thread%s | bound %.1f M/s "
                "(gather and sum of the same %d B per corner) | lookup/bound %.2f  [checksum %.9g, %g]\n",
                name.c_str(), query.kind(), visibility ? " + occlusion" : "", best / 1e6, goal, bound / 1e6, bytes,
                best / bound, double(sink.x), double(boundSink));
    // nanovdb_export_test's limits: 1e-5 for the SH part, 2e-5 with listed lights (query's
    // point, spot, directional and mesh lights in double, the shader's in float; its polygon
    // lights take the shader's float operations, fast_exact_lights.h).
    const double worst = worstRelativeDifference(query, nano, nanoIn), limit = visibility ? 2e-5 : 1e-5;
    std::printf("query %-16s (NanoVDB: the PNanoVDB lookup as C, %.1f MB .nvdb): %.2f M lookups/s per thread | nano/query %.2f | "
                "worst relative difference to query %.2g over %zu points (tests: <= %g)%s  [checksum %.9g]\n",
                name.c_str(), double(nano.fileBytes()) / 1e6, nanoBest / 1e6, nanoBest / best, worst, nanoIn.points.size(), limit,
                worst > limit ? " ABOVE THE TESTS' LIMIT" : "", double(nanoSink.x));
    // On the same volume and inputs, timed alternately so that one run gives the ratios: the
    // portable and the AVX2 builds of the blend (the same checksum: the same sums; the lookup
    // picks one of them, sh_uniform_lookup.h, sh4_uniform_lookup.cpp), and for the default
    // volume its previous path (its checksum differs in the direct light, float against double).
    if (!visibility) {
        const std::unique_ptr<VolumeLookup> portable = buildOf(volume, query.kind(), false), wide = buildOf(volume, query.kind(), true);
        if (portable && wide) {
            Rgb portableSink{0, 0, 0}, wideSink{0, 0, 0};
            double p = 0, w = 0;
            for (int r = 0; r < (quick ? 1 : 5); ++r) {
                p = std::max(p, bench::lookupRate(*portable, in, 1, portableSink));
                w = std::max(w, bench::lookupRate(*wide, in, 1, wideSink));
            }
            std::printf("query %-16s (the blend's builds): portable %.2f M lookups/s | AVX2 %.2f M/s, %.2fx  [checksums %.9g, %.9g]\n",
                        name.c_str(), p / 1e6, w / 1e6, w / p, double(portableSink.x), double(wideSink.x));
        }
    } else if (std::unique_ptr<VolumeLookup> before = previousOcclusionLookup(volume, query.kind())) {
        // What the arithmetic alone costs: the same lookups at points of the 3 x 3 x 3 cells at
        // the grid's first corner, whose nodes stay in the cache (and the bound there), so that
        // one run shows how much of the row's time is memory.
        Bounds corner = grid.nodeBounds();
        corner.hi = corner.lo + Vec3d(3, 3, 3) * grid.spacing;
        const bench::LookupInputs cached = bench::randomLookups(corner, quick ? 200'000 : 2'000'000);
        Rgb cachedSink{0, 0, 0};
        double cachedRate = 0, cachedBound = 0;
        for (int r = 0; r < (quick ? 1 : 5); ++r) {
            cachedRate = std::max(cachedRate, bench::lookupRate(query, cached, 1, cachedSink));
            cachedBound = std::max(cachedBound, bench::gatherBoundRate(grid, arrays, cached, 1, boundSink));
        }
        std::printf("query %-16s (points in 3^3 cells, their nodes in cache: the arithmetic): %.2f M lookups/s (%.0f ns) | "
                    "bound %.1f M/s | at random points %.0f ns: %.0f ns more  [checksum %.9g]\n",
                    name.c_str(), cachedRate / 1e6, 1e9 / cachedRate, cachedBound / 1e6, 1e9 / best, 1e9 / best - 1e9 / cachedRate,
                    double(cachedSink.x));
        Rgb beforeSink{0, 0, 0}, again{0, 0, 0};
        double rate = 0, now = 0;
        for (int r = 0; r < (quick ? 1 : 5); ++r) {
            rate = std::max(rate, bench::lookupRate(*before, in, 1, beforeSink));
            now = std::max(now, bench::lookupRate(query, in, 1, again));
        }
        std::printf("query %-16s (the previous path: portable blend, visibility located again, lights in double): %.2f M lookups/s | "
                    "now %.2f M/s, %.2fx  [checksum %.9g]\n",
                    name.c_str(), rate / 1e6, now / 1e6, now / rate, double(beforeSink.x));
    }
    // The generic lookup on the same volume and inputs (what sh:4 volumes were read by before
    // their own lookup), so that one run shows the ratio; the same checksum means the same sums.
    if (basis && !visibility && std::string(query.kind()) != "basis") {
        const ChannelLookup generic(volume, OutsidePolicy::Clamp);
        Rgb genericSink{0, 0, 0};
        const double rate = bench::lookupRate(generic, in, quick ? 1 : 5, genericSink);
        std::printf("query %-16s (32^3 nodes, 1 thread, lookup basis, for comparison): %.2f M lookups/s  [checksum %.9g]\n",
                    name.c_str(), rate / 1e6, double(genericSink.x));
    }
}
}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench", {{"--threads", "N"}, {"--only", "query|bake"}});
    if (!args.parse(argc, argv)) return 2;
    const std::string only = args.text("--only");
    if (!only.empty() && only != "query" && only != "bake") {
        std::fprintf(stderr, "vdblight_bench: --only takes query or bake, not '%s'\n", only.c_str());
        return 2;
    }
    const bool quick = args.quick();
    const int threads = args.integer("--threads", tbb::this_task_arena::max_concurrency());
    std::printf("vdblight_bench%s: %d threads\n", quick ? " (quick smoke run, noisy figures)" : "", threads);
    try {
        if (only != "query") {
            benchScene(loadScene(defaultScenePath()), threads, quick);
            benchScene(bench::cornellWithSpheres(6, 6), threads, quick);
            // The default bake stores SH order 4: the same gather projecting into 25 coefficients.
            benchScene(loadScene(defaultScenePath()), threads, quick, "sh:4");
            benchScene(bench::cornellWithSpheres(6, 6), threads, quick, "sh:4");
        }
        if (only != "bake")
        {
            std::printf("query rows: lookups per second of the timing thread's CPU time (bench_util.h)\n");
            benchQuery(quick, nullptr, false, false, 20);
            benchQuery(quick, "sh:4", false, false, 0);
            benchQuery(quick, nullptr, true, false, 0);
            benchQuery(quick, "sh:4", true, false, 0);
            // What `vdblight bake` writes by default and `query` reads.
            benchQuery(quick, "sh:4", true, true, 10);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
