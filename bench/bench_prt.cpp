// vdblight_bench_prt: the PRT bake by phase, relight time per light position on one thread,
// and a re-computation from scratch at equal error, all measured in this run.
//
//  1. Bake of the default scene (samples, visibility, direct-light basis, transfer) and the
//     storage before / after sparse 16-bit quantisation, beside the paper's figures
//     (45 k samples, 48 clusters, 4 h precomputation, 4.47 MB visibility + 21 MB transfer).
//  2. Relight (section 5: visibility -> direct -> projection -> transfer) per light position,
//     one thread, and its RMS relative error against the uncompressed one-bounce reference
//     (exact shadow rays, every sample to every sample).
//  3. Re-computing the same indirect light without PRT: exact direct light by shadow rays, then
//     one bounce gathered from m randomly chosen senders per receiver (n/m weight), m grown
//     until its error is at most the PRT error; time on one thread and the ratio.
// `--quick` shrinks the workload for a CI smoke run.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unistd.h>
#include <string>

#include "vdblight/prt.h"
#include "vdblight/prt_io.h"
#include "vdblight/sampling.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"

using namespace vdblight;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// One-bounce indirect from m random senders per receiver (single thread), plus exact direct.
std::vector<Rgb> sampledIndirect(const SurfaceSamples& s, const Tracer& tracer, const Vec3f& light, std::size_t m,
                                 uint64_t seed) {
    const std::vector<float> direct = exactDirectUnit(s, tracer, light, 1);
    const std::size_t n = s.size();
    std::vector<Rgb> out(n, Rgb{0, 0, 0});
    for (std::size_t r = 0; r < n; ++r) {
        Rng rng(seed, r);
        Rgbd acc{0, 0, 0};
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t j = std::min(n - 1, std::size_t(rng.uniform() * float(n)));
            if (j == r || direct[j] == 0.0f) continue;
            const float f = diskTransfer(s.position[r], s.normal[r], s.position[j], s.normal[j], s.area[j]);
            if (f <= 0.0f) continue;
            const Vec3f a = offsetRayOrigin(s.position[r], s.normal[r], s.position[j] - s.position[r]);
            const Vec3f b = offsetRayOrigin(s.position[j], s.normal[j], s.position[r] - s.position[j]);
            if (tracer.occluded(Ray{a, b - a, 0.0f, 0.9999f})) continue;
            acc += Rgbd(s.albedo[j]) * (double(f) * kInvPi * direct[j]);
        }
        out[r] = Rgb(acc * (double(n) / double(m)));
    }
    return out;
}
}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    PrtOptions o;
    o.samples = quick ? 600 : 4000;
    o.clusterSize = quick ? 300 : 1000;
    o.visDirs = quick ? 256 : 2048;
    o.visCoeffs = quick ? 24 : 50;
    o.trainLights = quick ? 100 : 1000;
    o.transferCoeffs = 10;
    o.volumeResolution = quick ? 6 : 16;
    std::printf("vdblight_bench_prt%s: default scene (%zu triangles), bake on all cores, relight on one thread\n",
                quick ? " --quick" : "", scene.triangleCount());

    const double t0 = now();
    const PrtData prt = bakePrt(scene, tracer, o);
    const double bakeSeconds = now() - t0;
    std::printf("bake: %zu samples, %zu clusters, %d dirs -> %d coeffs, %u lights -> %d vectors\n", prt.samples.size(),
                prt.samples.clusters(), prt.visGrid * prt.visGrid, prt.visCoeffStride, prt.trainLights,
                prt.transferStride - 1);
    std::printf("  phases: samples %.3f s, visibility %.3f s, basis %.3f s, transfer %.3f s; total %.3f s\n",
                prt.secondsSamples, prt.secondsVisibility, prt.secondsBasis, prt.secondsTransfer, bakeSeconds);
    const std::string path = "/tmp/vdblight_bench_prt_" + std::to_string(::getpid()) + ".vdb";
    writePrt(prt, path);
    const PrtFileInfo info = inspectPrt(path);
    std::remove(path.c_str());
    std::printf("  storage: %.3f MB dense float32 -> %.3f MB stored (sparse, 16-bit), file %.3f MB\n",
                info.bytesFloat32 / 1e6, info.bytesStored / 1e6, info.fileBytes / 1e6);
    std::printf("  paper: 45 k samples, 48 clusters, about 4 h (photon mapper), 4.47 MB + 21 MB\n");

    const Vec3f lights[5] = {{0.28f, 0.40f, 0.28f}, {0.12f, 0.30f, 0.45f}, {0.45f, 0.48f, 0.10f},
                             {0.30f, 0.15f, 0.05f}, {0.50f, 0.20f, 0.15f}};
    double relightSeconds = 0, prtError = 0;
    std::vector<std::vector<Rgb>> refs;
    for (const Vec3f& l : lights) {
        const int reps = quick ? 3 : 10;
        PrtLighting lit;
        const double t = now();
        for (int k = 0; k < reps; ++k) lit = relightPrt(prt, {PrtLight{l}});
        relightSeconds += (now() - t) / reps / 5;
        const std::vector<float> d = exactDirectUnit(prt.samples, tracer, l);
        refs.push_back(referenceIndirect(prt.samples, tracer, d));
        prtError += rmsRelativeError(lit.indirect, refs.back()) / 5;
    }
    std::printf("relight: %.3f ms per light position (one thread, %zu samples), indirect RMS relative error %.4f\n",
                relightSeconds * 1e3, prt.samples.size(), prtError);

    // Re-computation at equal error.
    const std::size_t n = prt.samples.size();
    for (std::size_t m = 4;; m *= 2) {
        double err = 0;
        const double t = now();
        for (int i = 0; i < 5; ++i) err += rmsRelativeError(sampledIndirect(prt.samples, tracer, lights[i], m, 7), refs[std::size_t(i)]) / 5;
        const double dt = (now() - t) / 5;
        std::printf("  from scratch, %zu senders per receiver: %.3f ms per light, error %.4f\n", m, dt * 1e3, err);
        if (err <= prtError || m >= n) {
            std::printf("re-computation at equal error: %.3f ms vs relight %.3f ms: relight %.0fx faster\n", dt * 1e3,
                        relightSeconds * 1e3, dt / relightSeconds);
            break;
        }
    }

    // Relightable volume: relight time vs recomputing it uncompressed (exact direct by rays,
    // every sample to every node), both on one thread.
    const std::size_t nodes = prt.volumeGrid.nodeCount();
    double volSeconds = 0, volError = 0, refSeconds = 0;
    for (const Vec3f& l : lights) {
        const int reps = quick ? 3 : 10;
        Volume vol;
        double t = now();
        for (int k = 0; k < reps; ++k) vol = relightVolume(prt, {PrtLight{l}});
        volSeconds += (now() - t) / reps / 5;
        t = now();
        const std::vector<float> d = exactDirectUnit(prt.samples, tracer, l, 1);
        const std::vector<Rgb> ref = referenceVolume(prt.samples, prt.volumeGrid, tracer, d, 1);
        refSeconds += (now() - t) / 5;
        std::vector<Rgb> got(ref.size());
        for (std::size_t i = 0; i < got.size(); ++i)
            got[i] = Rgb{vol.levels[0].data[i * 3], vol.levels[0].data[i * 3 + 1], vol.levels[0].data[i * 3 + 2]};
        volError += rmsRelativeError(got, ref) / 5;
    }
    std::printf("volume (%d x %d x %d = %zu nodes, SH order 2): relight %.3f ms per light (one thread), SH RMS relative "
                "error %.4f; uncompressed recomputation %.1f ms (one thread): relight %.0fx faster\n",
                prt.volumeGrid.nx, prt.volumeGrid.ny, prt.volumeGrid.nz, nodes, volSeconds * 1e3, volError,
                refSeconds * 1e3, refSeconds / volSeconds);
    return 0;
}
