// vdblight_bench_prt: the PRT bake by phase, relight time per light position on one thread,
// and a re-bake of the same volume at equal error, all measured in this run.
//
//  1. Bake of the default scene (samples, visibility, direct-light basis, multi-bounce
//     transfer) and the storage before / after sparse 16-bit quantisation, beside the paper's
//     figures (45 k samples, 48 clusters, 4 h precomputation, 4.47 MB visibility + 21 MB).
//  2. Relight at the samples (section 5) per light position, one thread, and its RMS relative
//     error against the uncompressed multi-bounce iteration (exact shadow rays, same F).
//  3. The relightable SH volume (a `--direct occlusion` volume: the baked bounces in the SH,
//     the light's visibility channel by shadow rays), one thread, against a converged re-bake: the foundation's SH gather
//     (bakeShGather, maxBounces = the PRT's bounces) of the scene with only that point light,
//     at many rays per node on all cores. Then the same gather on one thread with rays per
//     node doubled until its error against that reference is at most the relight's, and
//     bisected down to the smallest count found with that error (equal error). Finally the
//     relight and that re-bake are timed in alternating pairs, so that on a loaded machine
//     both see the same load: medians, the ratio of medians and the range of per-pair
//     ratios. The errors are of complete SH volumes: the relit SH plus the light's exact direct
//     SH at the nodes (a maxBounces = 0 gather of the point light: I / d^2 Y(w) by shadow rays,
//     the term the foundation's gather adds), which the re-bake carries too, so equal error on
//     the complete volume is equal error on its indirect part (also printed).
// `--relight-only [--prt FILE]` times only the relight phases (for profiling); with --prt it
// relights FILE if it exists, else bakes and writes it there.
// `--quick` shrinks the workload for a CI smoke run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <unistd.h>
#include <string>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "vdblight/prt/prt.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

DirectLight pointLight(const Vec3f& p) {
    DirectLight l;
    l.position = Vec3d(p);
    l.value = Rgb{1, 1, 1};
    return l;
}

/// The scene as PRT sees it: no emissive triangles, black sky, one point light of unit
/// intensity at `light`.
Scene withOnlyPointLight(const Scene& scene, const Vec3f& light) {
    Scene out = scene;
    for (Material& m : out.materials) m.emission = Rgb{0, 0, 0};
    out.pointLights = {PointLight{light, Rgb{1, 1, 1}}};
    out.spotLights.clear();
    out.directionalLights.clear();
    out.sky = Sky{};
    return out;
}

std::vector<Rgb> volumeRgb(const Volume& v) {
    std::vector<Rgb> out(v.levels[0].data.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = Rgb{v.levels[0].data[i * 3], v.levels[0].data[i * 3 + 1], v.levels[0].data[i * 3 + 2]};
    return out;
}
}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    // --relight-only: bake and time the relight phases, no references (for profiling).
    const bool relightOnly = argc > 1 && std::strcmp(argv[1], "--relight-only") == 0;
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    PrtOptions o;
    o.samples = quick ? 600 : 4000;
    o.clusterSize = quick ? 300 : 1000;
    o.visDirs = quick ? 256 : 2048;
    o.visCoeffs = quick ? 24 : 50;
    o.trainLights = quick ? 100 : 1000;
    o.transferCoeffs = 10;
    // --transfer-coeffs N (after the mode flag, or alone): the basis size to compare.
    for (int a = 1; a + 1 < argc; ++a)
        if (std::strcmp(argv[a], "--transfer-coeffs") == 0) o.transferCoeffs = uint32_t(std::atoi(argv[a + 1]));
    o.volumeResolution = quick ? 6 : 16;
    std::printf("vdblight_bench_prt%s: default scene (%zu triangles), bake on all cores, relight on one thread\n",
                quick ? " --quick" : "", scene.triangleCount());

    // --prt FILE (profiling): relight FILE if it exists, else bake and also write it there.
    std::string prtFile;
    for (int a = 1; a + 1 < argc; ++a)
        if (std::strcmp(argv[a], "--prt") == 0) prtFile = argv[a + 1];
    const double t0 = now();
    const bool loaded = relightOnly && !prtFile.empty() && ::access(prtFile.c_str(), R_OK) == 0;
    const PrtData prt = loaded ? readPrt(prtFile) : bakePrt(scene, tracer, o);
    if (relightOnly && !prtFile.empty() && !loaded) writePrt(prt, prtFile);
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
    const int reps = quick ? 3 : 10;

    {
        // Where a volume relight's time goes (one thread).
        double tDirect = 0, tTransfer = 0, tNodes = 0;
        PrtRelightOptions one;
        one.threads = 1;
        for (const Vec3f& l : lights) {
            for (int k = 0; k < reps; ++k) {
                double t = now();
                const std::vector<float> d = prtDirectLight(prt, pointLight(l));
                tDirect += (now() - t) / reps / 5;
                t = now();
                const std::vector<Rgb> v = prtVolumeTransfer(prt, d);
                tTransfer += (now() - t) / reps / 5;
                t = now();
                const Volume without = relightVolume(prt, {pointLight(l)}, nullptr, nullptr, one);
                const double t1 = now();
                const Volume with = relightVolume(prt, {pointLight(l)}, &scene, &tracer, one);
                tNodes += ((now() - t1) - (t1 - t)) / reps / 5;
            }
        }
        std::printf("volume relight phases (one thread): direct at samples (compressed visibility) %.3f ms, projection + "
                    "transfer %.3f ms, light's visibility channel at nodes (shadow rays) %.3f ms\n",
                    tDirect * 1e3, tTransfer * 1e3, tNodes * 1e3);
        if (relightOnly) return 0;
    }

    // Samples: relight vs the uncompressed iteration with the bake's form factors.
    const std::vector<float> F = sampleFormFactors(prt.samples, tracer, 0, nullptr, prt.closureNormalise);
    {
        double seconds = 0, error = 0;
        for (const Vec3f& l : lights) {
            PrtLighting lit;
            const double t = now();
            for (int k = 0; k < reps; ++k) lit = relightPrt(prt, {pointLight(l)});
            seconds += (now() - t) / reps / 5;
            const std::vector<float> d = exactDirectUnit(prt.samples, scene, tracer, l);
            std::vector<Rgb> direct(d.size());
            for (std::size_t i = 0; i < d.size(); ++i) direct[i] = Rgb{d[i], d[i], d[i]};
            error += rmsRelativeError(lit.indirect, bounceIndirect(prt.samples, F, direct, prt.bounces)) / 5;
        }
        std::printf("relight at samples: %.3f ms per light position (one thread, %zu samples, %d bounces), indirect RMS "
                    "relative error %.4f vs the uncompressed iteration\n",
                    seconds * 1e3, prt.samples.size(), prt.bounces, error);
    }

    // One-sided (cosine) area lights against point lights, with the default basis (point-light
    // vectors + vectors from one-sided examples, PrtOptions::orientedTraining / orientedCoeffs)
    // and a basis of point lights only (the paper's examples). The second bake differs only in its basis and transfer (same samples and F),
    // so it skips the volume and uses a cheap visibility; both are fed the exact direct light
    // (shadow rays), so the errors are those of projection + transfer alone.
    {
        PrtOptions po = o;
        po.orientedTraining = 0;
        po.volumeResolution = 0;
        po.visDirs = 16;
        po.visCoeffs = 4;
        const PrtData points = bakePrt(scene, tracer, po);
        const DirectLight oneSided[5] = {
            squareLight(Vec3d(Vec3f{0.28f, 0.40f, 0.28f}), {0, -1, 0}, 0.1, Rgb{1, 1, 1}),
            squareLight(Vec3d(Vec3f{0.12f, 0.50f, 0.40f}), {0, -1, 0}, 0.1, Rgb{1, 1, 1}),
            squareLight(Vec3d(Vec3f{0.05f, 0.30f, 0.30f}), {1, 0, 0}, 0.1, Rgb{1, 1, 1}),
            squareLight(Vec3d(Vec3f{0.45f, 0.40f, 0.12f}), Vec3d(Vec3f{-0.5f, -0.5f, 0.7f}), 0.1, Rgb{1, 1, 1}),
            squareLight(Vec3d(Vec3f{0.08f, 0.06f, 0.50f}), Vec3d(Vec3f{0.3f, 1, -0.3f}), 0.1, Rgb{1, 1, 1}),
        };
        // The same square as 4 x 4 isotropic points in the XZ plane (`prt relight --area-size`).
        auto isotropicSquare = [&](const DirectLight& square) {
            std::vector<float> sum(prt.samples.size(), 0.0f);
            for (int a = 0; a < 16; ++a) {
                const Vec3f p = Vec3f(square.position) + Vec3f{0.1f * ((float(a % 4) + 0.5f) / 4 - 0.5f), 0,
                                                               0.1f * ((float(a / 4) + 0.5f) / 4 - 0.5f)};
                const std::vector<float> d = exactDirectUnit(prt.samples, scene, tracer, p);
                for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += d[i] / 16;
            }
            return sum;
        };
        auto grey = [](const std::vector<float>& d) {
            std::vector<Rgb> out(d.size());
            for (std::size_t i = 0; i < d.size(); ++i) out[i] = Rgb{d[i], d[i], d[i]};
            return out;
        };
        double err[2][3] = {};  // [basis][one-sided, its isotropic square, point]
        double compressed = 0;  // default basis, one-sided, through the compressed visibility
        for (int i = 0; i < 5; ++i) {
            const std::vector<float> d[3] = {exactDirectLight(prt.samples, scene, tracer, oneSided[i]),
                                             isotropicSquare(oneSided[i]),
                                             exactDirectUnit(prt.samples, scene, tracer, lights[i])};
            for (int k = 0; k < 3; ++k) {
                const std::vector<Rgb> ref = bounceIndirect(prt.samples, F, grey(d[k]), prt.bounces);
                err[0][k] += rmsRelativeError(prtTransfer(prt, d[k]), ref) / 5;
                err[1][k] += rmsRelativeError(prtTransfer(points, d[k]), ref) / 5;
                if (k == 0) compressed += rmsRelativeError(prtTransfer(prt, prtDirectLight(prt, oneSided[i], 4)), ref) / 5;
            }
        }
        std::printf("one-sided area lights (5 squares of 10 cm, %d bounces, exact direct light in): indirect RMS relative "
                    "error %.4f with one-sided examples in the basis (%d + %d vectors) vs %.4f with point lights "
                    "only (%d vectors; %.2fx); held-out point lights %.4f vs %.4f (%.2fx); the same squares isotropic %.4f vs %.4f; "
                    "one-sided through the compressed visibility %.4f\n",
                    prt.bounces, err[0][0], prt.transferStride - 1 - prt.orientedCoeffs, prt.orientedCoeffs, err[1][0],
                    points.transferStride - 1, err[0][0] / err[1][0], err[0][2],
                    err[1][2], err[0][2] / err[1][2], err[0][1], err[1][1], compressed);
    }

    // The complete relit volume (one thread) and the converged gather reference (all cores).
    const std::size_t nodes = prt.volumeGrid.nodeCount();
    std::vector<Scene> lit;
    std::vector<std::unique_ptr<Tracer>> litTracers;
    for (const Vec3f& l : lights) lit.push_back(withOnlyPointLight(scene, l));
    for (const Scene& sc : lit) litTracers.push_back(std::make_unique<Tracer>(sc));
    const uint32_t refRays = quick ? 256 : 2048;
    std::vector<std::vector<Rgb>> refs, directs;
    double refSeconds = 0;
    for (int i = 0; i < 5; ++i) {
        GatherOptions g;
        g.raysPerNode = refRays;
        g.threads = 0;
        g.seed = 99;
        g.transport.maxBounces = prt.bounces;
        const double t = now();
        refs.push_back(volumeRgb(bakeShGather(lit[std::size_t(i)], *litTracers[std::size_t(i)], prt.volumeGrid, g)));
        refSeconds += now() - t;
        g.raysPerNode = 4;  // the point light's direct SH alone: exact (one shadow ray per node)
        g.transport.maxBounces = 0;
        directs.push_back(volumeRgb(bakeShGather(lit[std::size_t(i)], *litTracers[std::size_t(i)], prt.volumeGrid, g)));
    }
    auto indirectError = [&](const std::vector<Rgb>& got, int i) {
        std::vector<Rgb> a(got.size()), b(got.size());
        for (std::size_t k = 0; k < got.size(); ++k) {
            a[k] = got[k] - directs[std::size_t(i)][k];
            b[k] = refs[std::size_t(i)][k] - directs[std::size_t(i)][k];
        }
        return rmsRelativeError(a, b);
    };
    std::printf("reference: SH gather, %u rays per node, %d bounces, all cores: %.1f s for 5 lights\n", refRays,
                prt.bounces, refSeconds);
    double volSeconds = 0, volError = 0, volIndirectError = 0, directSeconds = 0;
    PrtRelightOptions oneThread;
    oneThread.threads = 1;
    for (int i = 0; i < 5; ++i) {
        Volume vol;
        double t = now();
        for (int k = 0; k < reps; ++k) vol = relightVolume(prt, {pointLight(lights[i])}, &scene, &tracer, oneThread);
        const double with = (now() - t) / reps;
        t = now();
        for (int k = 0; k < reps; ++k) relightVolume(prt, {pointLight(lights[i])}, nullptr, nullptr, oneThread);
        volSeconds += with / 5;
        directSeconds += (with - (now() - t) / reps) / 5;  // the visibility channel's share
        std::vector<Rgb> got = volumeRgb(vol);  // the reflected light; the light's direct SH added:
        for (std::size_t k = 0; k < got.size(); ++k) got[k] += directs[std::size_t(i)][k];
        volError += rmsRelativeError(got, refs[std::size_t(i)]) / 5;
        volIndirectError += indirectError(got, i) / 5;
    }
    std::printf("volume relight (%d x %d x %d = %zu nodes, SH order 2 of %d bounces + the light's visibility): %.3f ms "
                "per light (one thread; of which visibility by shadow rays %.3f ms), RMS relative error with the exact "
                "direct SH added %.4f (indirect part %.4f)\n",
                prt.volumeGrid.nx, prt.volumeGrid.ny, prt.volumeGrid.nz, nodes, prt.bounces, volSeconds * 1e3,
                directSeconds * 1e3, volError, volIndirectError);

    // Re-baking the same volume at equal error: the gather on one thread. Rays per node are
    // doubled until its error is at most the relight's, then bisected between the last two
    // counts for the smallest count found whose error is at most the relight's.
    auto rebake = [&](uint32_t rays, double* error, double* indirect) {
        double err = 0, indErr = 0;
        for (int i = 0; i < 5; ++i) {
            GatherOptions g;
            g.raysPerNode = rays;
            g.threads = 1;
            g.seed = 7;
            g.transport.maxBounces = prt.bounces;
            const Volume v = bakeShGather(lit[std::size_t(i)], *litTracers[std::size_t(i)], prt.volumeGrid, g);
            if (!error) continue;
            const std::vector<Rgb> got = volumeRgb(v);
            err += rmsRelativeError(got, refs[std::size_t(i)]) / 5;
            indErr += indirectError(got, i) / 5;
        }
        if (error) *error = err, *indirect = indErr;
    };
    const uint32_t maxRays = quick ? 64 : 4096;
    uint32_t lo = 0, hi = quick ? 4 : 16;
    double hiError = 0, hiIndirect = 0;
    for (;; lo = hi, hi *= 2) {
        const double t = now();
        rebake(hi, &hiError, &hiIndirect);
        std::printf("  SH gather re-bake, %u rays per node: %.3f ms per light, RMS relative error %.4f (indirect part "
                    "%.4f)\n", hi, (now() - t) / 5 * 1e3, hiError, hiIndirect);
        if (hiError <= volError || hi >= maxRays) break;
    }
    const bool reached = hiError <= volError;
    while (reached && hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        double e = 0, ie = 0;
        rebake(mid, &e, &ie);
        std::printf("  bisect: %u rays per node, error %.4f (indirect %.4f)\n", mid, e, ie);
        if (e <= volError) hi = mid, hiError = e, hiIndirect = ie;
        else lo = mid;
    }
    // Relight and re-bake timed in alternating pairs (which goes first alternates too), so a
    // change of load hits both: medians of each, the ratio of the medians and the range of the
    // per-pair ratios.
    const int pairs = quick ? 3 : 9;
    std::vector<double> relightMs, rebakeMs, ratio;
    for (int p = 0; p < pairs; ++p) {
        double tr = 0, tb = 0;
        for (int half = 0; half < 2; ++half) {
            if ((half == 0) == (p % 2 == 0)) {
                const double t = now();
                for (int i = 0; i < 5; ++i)
                    for (int k = 0; k < reps; ++k)
                        relightVolume(prt, {pointLight(lights[i])}, &scene, &tracer, oneThread);
                tr = (now() - t) / reps / 5 * 1e3;
            } else {
                const double t = now();
                rebake(hi, nullptr, nullptr);
                tb = (now() - t) / 5 * 1e3;
            }
        }
        relightMs.push_back(tr);
        rebakeMs.push_back(tb);
        ratio.push_back(tb / tr);
    }
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        const std::size_t n = v.size();
        return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    };
    const double mr = median(relightMs), mb = median(rebakeMs);
    std::printf("volume re-bake (SH gather, %d bounces, one thread) at equal error: %u rays per node, error %.4f "
                "(indirect %.4f) vs the relight's %.4f (indirect %.4f)%s\n",
                prt.bounces, hi, hiError, hiIndirect, volError, volIndirectError,
                reached ? "" : " (error NOT reached)");
    std::printf("  %d interleaved pairs: relight median %.3f ms, re-bake median %.3f ms per light: relight %.0fx faster "
                "(ratio of medians; per-pair ratios %.0fx to %.0fx)\n",
                pairs, mr, mb, mb / mr, *std::min_element(ratio.begin(), ratio.end()),
                *std::max_element(ratio.begin(), ratio.end()));
    return 0;
}
