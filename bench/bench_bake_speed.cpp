// Benchmark of the point-gather bake's speed (issue 4, "paper configuration under 1 s"):
// the paper's configuration (7^3 first level, 3^3 refinement, 578 directions per node, full
// global illumination, maxBounces 8) on the default scene, with a checksum of the baked
// coefficients so that a faster path can be shown to give the same bits.
//
// `--quick` shrinks the workload for a CI smoke run.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <cstring>

#include <sys/resource.h>

#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {

uint64_t checksum(const Volume& v) {
    uint64_t h = 1469598103934665603ull;  // FNV-1a over the coefficient bits
    for (const VolumeLevel& l : v.levels)
        for (float f : l.data) {
            uint32_t bits;
            std::memcpy(&bits, &f, 4);
            for (int b = 0; b < 4; ++b) h = (h ^ ((bits >> (8 * b)) & 0xffu)) * 1099511628211ull;
        }
    return h;
}

double cpuSeconds() {
    rusage u;
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int threads = 2;
    uint32_t rays = 578;
    int repeat = 3;
    int only = -1;  // --only packets|reference: one path (for profiling)
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) quick = true;
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--rays") && i + 1 < argc) rays = uint32_t(std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
            ++i;
            only = !std::strcmp(argv[i], "packets") ? 1 : !std::strcmp(argv[i], "reference") ? 0 : -2;
            if (only == -2) {
                std::fprintf(stderr, "vdblight_bench_bake_speed: --only must be packets or reference\n");
                return 2;
            }
        } else {
            std::fprintf(stderr, "usage: vdblight_bench_bake_speed [--quick] [--threads N] [--rays N] [--repeat R] "
                                 "[--only packets|reference]\n");
            return 2;
        }
    }
    if (quick) {
        rays = 32;
        repeat = 1;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    try {
        const Scene scene = loadScene(defaultScenePath());
        const Tracer tracer(scene);
        GridPlacement p;
        p.resolution = 7;
        const GridSpec g0 = placeUniformGrid(scene.bounds(), p, 1);
        LevelsPlacement lp;
        lp.kind = LayoutKind::Bilevel;
        lp.refine = 3;
        lp.levels = 2;
        const LevelLayout layout = placeLevels(g0, scene.positions, scene.indices, lp, 1);
        // Same-run A/B: the one-ray-at-a-time reference (packetRays = false) and the packet
        // path, alternating, best of `repeat` each. Wall time and process CPU time (user +
        // system over all threads; steadier than wall time on a shared machine).
        double bestWall[2] = {1e30, 1e30}, bestCpu[2] = {1e30, 1e30};
        uint64_t sums[2] = {0, 0};
        for (int r = 0; r < repeat; ++r)
            for (int packet = 0; packet < 2; ++packet) {
                if (only >= 0 && packet != only) continue;
                GatherOptions options;
                options.raysPerNode = rays;
                options.threads = threads;
                options.transport.packetRays = packet == 1;
                options.transport.maxBounces = 8;  // the paper configuration's figures (issue 4), not the default cap
                LevelsBakeStats stats;
                const double cpu0 = cpuSeconds();
                const Volume v = bakeShGatherLevels(scene, tracer, layout, options, nullptr, &stats);
                const double cpu = cpuSeconds() - cpu0;
                sums[packet] = checksum(v);
                bestWall[packet] = std::min(bestWall[packet], stats.seconds);
                bestCpu[packet] = std::min(bestCpu[packet], cpu);
                std::printf("paper configuration (7^3 first level, 3^3 refinement, %u directions, %d bounces), %s: %llu "
                            "nodes, bake %.3f s wall (%.3f s CPU) on %d threads, %.2f M rays (%.2f M shadow)  "
                            "[checksum %016llx]\n",
                            rays, options.transport.maxBounces, packet ? "packets   " : "one by one",
                            (unsigned long long)stats.nodes, stats.seconds, cpu, threads,
                            double(stats.rays.total()) / 1e6, double(stats.rays.occluded) / 1e6,
                            (unsigned long long)sums[packet]);
            }
        if (only >= 0) return 0;
        std::printf("packets vs one by one (best of %d, same run): wall %.3f s vs %.3f s (%.2fx faster), CPU %.3f s vs "
                    "%.3f s (%.2fx); same bits: %s (target < 1 s wall on 2 idle cores)\n",
                    repeat, bestWall[1], bestWall[0], bestWall[0] / bestWall[1], bestCpu[1], bestCpu[0],
                    bestCpu[0] / bestCpu[1], sums[0] == sums[1] ? "yes" : "NO");
        if (sums[0] != sums[1]) return 1;

        // An option that changes the bits (not the default): Embree's non-robust mode.
        TracerOptions fast;
        fast.robust = false;
        const Tracer fastTracer(scene, fast);
        GatherOptions options;
        options.raysPerNode = rays;
        options.threads = threads;
        options.transport.maxBounces = 8;
        double fastWall = 1e30, fastCpu = 1e30;
        Volume fastVolume, robustVolume = bakeShGatherLevels(scene, tracer, layout, options);
        for (int r = 0; r < repeat; ++r) {
            LevelsBakeStats stats;
            const double cpu0 = cpuSeconds();
            fastVolume = bakeShGatherLevels(scene, fastTracer, layout, options, nullptr, &stats);
            fastCpu = std::min(fastCpu, cpuSeconds() - cpu0);
            fastWall = std::min(fastWall, stats.seconds);
        }
        // How many nodes changed, and by how much (relative to the node's DC magnitude).
        std::size_t nodes = 0, changed = 0;
        double worst = 0;
        for (std::size_t l = 0; l < robustVolume.levels.size(); ++l) {
            const std::vector<float>& a = robustVolume.levels[l].data;
            const std::vector<float>& b = fastVolume.levels[l].data;
            for (std::size_t n = 0; n + 27 <= a.size(); n += 27) {
                ++nodes;
                if (std::memcmp(&a[n], &b[n], 27 * sizeof(float)) == 0) continue;
                ++changed;
                const double dc = std::max(1e-12, double(std::abs(a[n]) + std::abs(a[n + 1]) + std::abs(a[n + 2])));
                for (int k = 0; k < 27; ++k) worst = std::max(worst, std::abs(double(a[n + k]) - b[n + k]) / dc);
            }
        }
        std::printf("option TracerOptions::robust = false (Embree's non-robust mode; other bits): packets %.3f s wall "
                    "(%.3f s CPU), %.2fx the robust packet path's CPU time; %zu of %zu nodes differ, largest "
                    "difference %.3g of the node's DC magnitude\n",
                    fastWall, fastCpu, fastCpu / bestCpu[1], changed, nodes, worst);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vdblight_bench_bake_speed: %s\n", e.what());
        return 1;
    }
    return 0;
}
