// vdblight_bench_photons: speed and error of the photon pass (Pacanowski et al.), in one run.
//
//  1. Throughput on a ~26 k-triangle scene (Cornell box + two spheres) with the paper's
//     20 x 22 x 20 grid: photons/s, segments/s, face crossings/s, and the pass's Embree
//     rays/s against raw Embree rays/s (random rays in the scene, same threads). The paper:
//     8 M photons in 58 s (24 k triangles, 2009 CPU); our target: 8 M photons in under 4 s.
//  2. Error against time on the default scene: RMS error against `reference` at random
//     free-space points for the photon vector grid and the SH gather volume at the same grid
//     resolution, at about equal bake times (several budgets).
//  3. The compact colour + direction form (section 4.2): file size saved and error added.
// `--quick` shrinks every workload for a CI smoke run; the figures are then noisy.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include <filesystem>
#include <unistd.h>

#include "vdblight/bake/each_pass.h"
#include "basis/irradiance_vectors_compact.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/query/query.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "volume/volume_compact.h"
#include "../libvdblight/src/trace/random_rays.h"  // internal: traceRandomRays, the raw Embree probe
#include "bench_args.h"
#include "bench_scenes.h"
#include "bench_util.h"

#include "support/scene_generators.h"

using namespace vdblight;
using bench::now;

namespace {
/// CPU seconds used by the whole process (all threads): on a loaded machine wall time
/// counts the time other processes held the cores, CPU time does not.
double cpuNow() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Rate {
    double wall = 0, cpu = 0;  ///< per wall second, per CPU second
};

Rate rawRaysPerSecond(const Tracer& tracer, const Bounds& box, std::size_t total, int threads) {
    tbb::task_arena arena(threads);
    std::atomic<std::size_t> hits{0};
    const double t0 = now(), c0 = cpuNow();
    arena.execute([&] {
        tbb::parallel_for(0, threads, [&](int w) { hits += traceRandomRays(tracer, box, total / threads, uint64_t(w) + 1); });
    });
    const double dt = now() - t0, dc = cpuNow() - c0;
    if (hits == std::size_t(-1)) std::puts("");
    const double n = double(total / threads * threads);
    return {n / dt, n / dc};
}

void benchThroughput(int threads, bool quick) {
    const Scene scene = bench::cornellWithSpheres(5, 4);  // 20 480 + 5 120 triangles
    const Tracer tracer(scene);
    const Bounds b = scene.bounds();
    GridSpec g;
    g.nx = 20, g.ny = 22, g.nz = 20;
    g.spacing = b.size().y / 22.0;
    g.origin = b.lo + Vec3d(1, 1, 1) * (0.5 * g.spacing);
    PhotonOptions o;
    o.photons = quick ? 400'000 : 8'000'000;
    o.threads = threads;
    PhotonStats st;
    const double c0 = cpuNow();
    bakePhotons(scene, tracer, g, o, nullptr, &st);
    const double cpu = cpuNow() - c0;
    const Rate raw = rawRaysPerSecond(tracer, b, quick ? 400'000 : 4'000'000, threads);
    std::printf("\n[throughput] scene %s, %zu triangles, grid %dx%dx%d, %d threads\n", scene.name.c_str(),
                scene.triangleCount(), g.nx, g.ny, g.nz, threads);
    std::printf("  %.2f M photons in %.2f s wall, %.2f s CPU: %.2f M photons/s, %.2f M segments/s, %.1f M face "
                "crossings/s (%.1f crossings per segment)\n",
                st.photons / 1e6, st.seconds, cpu, st.photons / st.seconds / 1e6, st.segments / st.seconds / 1e6,
                st.crossings / st.seconds / 1e6, double(st.crossings) / double(st.segments));
    const double passRays = double(st.rays.total()) / st.seconds, passRaysCpu = double(st.rays.total()) / cpu;
    std::printf("  photon pass %.2f M rays/s vs raw Embree %.2f M rays/s (wall; ratio %.2f)\n", passRays / 1e6,
                raw.wall / 1e6, passRays / raw.wall);
    std::printf("  per CPU second: photon pass %.2f M rays, raw Embree %.2f M rays (ratio %.2f; the rest is emission "
                "and the grid walk)\n",
                passRaysCpu / 1e6, raw.cpu / 1e6, passRaysCpu / raw.cpu);
    const double eightM = 8e6 / (st.photons / st.seconds);
    const double eightMCpu = 8e6 / (st.photons / cpu) / threads;
    std::printf("  8 M photons: %.2f s wall %s, %.2f s on %d dedicated cores (CPU time / threads); paper: 58 s on a "
                "2009 CPU; target < 4 s: %s\n",
                eightM, quick ? "extrapolated" : "measured", eightMCpu, threads,
                eightM < 4.0 ? "met" : eightMCpu < 4.0 ? "met in CPU time (wall time includes other processes' load)" : "NOT met");
}

struct ErrorSet {
    std::vector<ReferencePoint> points;
    std::vector<ReferenceResult> ref;
};

ErrorSet freeSpacePoints(const Scene& scene, const Tracer& tracer, const Bounds& box, int count, uint32_t samples,
                         int threads) {
    // Random points and normals in the node box; points inside solids (reference E = 0 for
    // every normal there: no light enters a closed block) are dropped.
    Rng rng(2024);
    ErrorSet out;
    std::vector<ReferencePoint> cand;
    for (int i = 0; i < count * 5 / 4; ++i)
        cand.push_back({Vec3f(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform())),
                        uniformSphere(rng.uniform(), rng.uniform())});
    ReferenceOptions ro;
    ro.samples = samples;
    ro.threads = threads;
    const std::vector<ReferenceResult> r = referenceIrradiance(scene, tracer, cand, ro);
    for (std::size_t i = 0; i < cand.size() && int(out.points.size()) < count; ++i)
        if (luminance(Rgb(r[i].irradiance)) > 1e-6f) out.points.push_back(cand[i]), out.ref.push_back(r[i]);
    return out;
}

// sqrt(sum |E - E_ref|^2 / sum |E_ref|^2) over luminance: relative RMS error.
template <typename F>
double relativeRms(const ErrorSet& set, F&& lookup) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < set.points.size(); ++i) {
        const double e = luminance(lookup(set.points[i].position, normalize(set.points[i].normal)));
        const double r = luminance(Rgb(set.ref[i].irradiance));
        num += (e - r) * (e - r);
        den += r * r;
    }
    return std::sqrt(num / den);
}

void benchErrorVsTime(int threads, bool quick) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const GridSpec g = bench::uniformGrid(scene.bounds(), quick ? 8 : 16);
    const int points = quick ? 100 : 1000;
    const double t0 = now();
    const ErrorSet set = freeSpacePoints(scene, tracer, g.nodeBounds(), points, quick ? 2048 : 32768, threads);
    std::printf("\n[error vs time] default scene, grid %dx%dx%d, %zu random free-space points, reference %u samples "
                "(%.1f s), %d threads; relative RMS error of luminance\n",
                g.nx, g.ny, g.nz, set.points.size(), quick ? 2048u : 32768u, now() - t0, threads);
    std::printf("  %-10s %-9s %-10s | %-11s %-9s %-10s %-10s\n", "SH rays", "SH time", "SH error", "photons", "time",
                "trilinear", "tricubic");
    const std::vector<uint32_t> budgets = quick ? std::vector<uint32_t>{32, 128} : std::vector<uint32_t>{32, 128, 512, 2048};
    double photonRate = 0;
    for (uint32_t rays : budgets) {
        GatherOptions go;
        go.raysPerNode = rays;
        go.threads = threads;
        BakeStats bs;
        const Volume sh = bakeShGather(scene, tracer, g, go, nullptr, &bs);
        const IrradianceQuery shq(sh);
        const double shErr = relativeRms(set, [&](const Vec3f& x, const Vec3f& n) { return shq.irradiance(x, n); });

        // Photons for about the same time (rate from the previous run; first a calibration).
        if (photonRate == 0) {
            PhotonOptions po;
            po.photons = 100'000;
            po.threads = threads;
            PhotonStats ps;
            bakePhotons(scene, tracer, g, po, nullptr, &ps);
            photonRate = ps.photons / ps.seconds;
        }
        PhotonOptions po;
        po.photons = std::max<uint64_t>(10'000, uint64_t(photonRate * bs.seconds));
        po.threads = threads;
        PhotonStats ps;
        const Volume iv = bakePhotons(scene, tracer, g, po, nullptr, &ps);
        photonRate = ps.photons / ps.seconds;
        const VectorGridLookup lin(iv, OutsidePolicy::Clamp, Interpolation::Trilinear);
        const VectorGridLookup cub(iv, OutsidePolicy::Clamp, Interpolation::Tricubic);
        const double linErr = relativeRms(set, [&](const Vec3f& x, const Vec3f& n) { return lin.irradiance(x, n); });
        const double cubErr = relativeRms(set, [&](const Vec3f& x, const Vec3f& n) { return cub.irradiance(x, n); });
        std::printf("  %-10u %-9.2f %-10.4f | %-11llu %-9.2f %-10.4f %-10.4f\n", rays, bs.seconds, shErr,
                    (unsigned long long)po.photons, ps.seconds, linErr, cubErr);
    }
}
// The compact colour + direction form (section 4.2): file size saved and error added, against
// the full form of the same bake, at the same free-space points as above.
void benchCompact(int threads, bool quick) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const GridSpec g = bench::uniformGrid(scene.bounds(), 16);
    const ErrorSet set = freeSpacePoints(scene, tracer, g.nodeBounds(), quick ? 100 : 1000, quick ? 2048 : 32768, threads);
    PhotonOptions po;
    po.photons = quick ? 200'000 : 4'000'000;
    po.threads = threads;
    const Volume full = bakePhotons(scene, tracer, g, po);
    const Volume compact = iv::compact(full);

    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("vdblight_bench_compact_" + std::to_string(getpid()));
    fs::create_directories(dir);
    auto sizeOf = [&](const Volume& v, bool half, const char* name) {
        WriteOptions w;
        w.halfFloat = half;
        const fs::path path = dir / name;
        writeVolume(v, path.string(), w);
        return double(fs::file_size(path));
    };
    const double fullBytes = sizeOf(full, false, "full.vdb"), halfBytes = sizeOf(full, true, "half.vdb"),
                 compactBytes = sizeOf(compact, true, "compact.vdb");
    const Volume compactRead = readVolume((dir / "compact.vdb").string());
    fs::remove_all(dir);

    std::printf("\n[compact form] default scene, grid %dx%dx%d (%zu nodes), %.1f M photons, %zu free-space points\n", g.nx,
                g.ny, g.nz, g.nodeCount(), po.photons / 1e6, set.points.size());
    std::printf("  file size: full float %.0f KiB, full half %.0f KiB, compact half %.0f KiB (%.2fx smaller than full "
                "float; data 216 -> 72 bytes per node)\n",
                fullBytes / 1024, halfBytes / 1024, compactBytes / 1024, fullBytes / compactBytes);
    std::printf("  %-10s | %-14s %-14s | %-s\n", "interp", "full error", "compact error", "compact vs full (RMS difference)");
    for (Interpolation in : {Interpolation::Trilinear, Interpolation::Tricubic}) {
        const VectorGridLookup a(full, OutsidePolicy::Clamp, in), b(compactRead, OutsidePolicy::Clamp, in);
        const double ea = relativeRms(set, [&](const Vec3f& x, const Vec3f& n) { return a.irradiance(x, n); });
        const double eb = relativeRms(set, [&](const Vec3f& x, const Vec3f& n) { return b.irradiance(x, n); });
        double num = 0, den = 0;
        for (const ReferencePoint& pt : set.points) {
            const Vec3f n = normalize(pt.normal);
            const double va = luminance(a.irradiance(pt.position, n)), vb = luminance(b.irradiance(pt.position, n));
            num += (vb - va) * (vb - va), den += va * va;
        }
        std::printf("  %-10s | %-14.4f %-14.4f | %.4f\n", in == Interpolation::Trilinear ? "trilinear" : "tricubic", ea, eb,
                    std::sqrt(num / den));
    }
}
}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_photons", {{"--threads", "N"}, {"--only", "throughput|error|compact"}});
    if (!args.parse(argc, argv)) return 2;
    const bool quick = args.quick();
    int threads = args.integer("--threads", 0);
    const std::string only = args.text("--only");
    if (threads <= 0) threads = tbb::this_task_arena::max_concurrency();
    std::printf("vdblight_bench_photons%s: %d threads\n", quick ? " (quick smoke run, noisy figures)" : "", threads);
    try {
        if (only.empty() || only == "throughput") benchThroughput(threads, quick);
        if (only.empty() || only == "error") benchErrorVsTime(threads, quick);
        if (only.empty() || only == "compact") benchCompact(threads, quick);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench_photons: %s\n", e.what());
        return 1;
    }
    return 0;
}
