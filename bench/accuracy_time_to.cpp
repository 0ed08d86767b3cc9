// vdblight_bench_accuracy --time-to E: time to accuracy.
#include "accuracy.h"

namespace vdblight::accuracy {

// ---------------------------------------------------------------------------------------
// --time-to E: time to accuracy (issue 15 item 2's target: in two_rooms, reach 9 % RMS at least
// 5x faster than plain gathering, which took 8192 rays per node at 32 nodes, 21 s). Each ladder
// doubles the rays per node on one grid until the RMS is at most E; the time to E of a ladder
// is the bake time of its first step that reaches it (wall and CPU / threads; the machine may be
// shared, so CPU / threads is the better estimate of two free cores).

namespace {
struct Rung {
    uint32_t rays = 0;
    Errors e;
    double wall = 0, cpu = 0;
};
}  // namespace

void timeToAccuracy(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
                    const Settings& st, double target, FILE* csv) {
    struct Ladder {
        const char* name;
        const char* spec;  ///< TrySpec without rays
        std::vector<uint32_t> rays;
    };
    const std::vector<Ladder> ladders = {
        {"plain, the issue's baseline (32 nodes, --direct baked, no depth)", "res=32,passes=0,direct=baked", {1024, 2048, 4096, 8192}},
        {"plain on the default's grid and options (no probe pass)", "nodes=16384,passes=0,depth=1", {512, 1024, 2048, 4096}},
        {"plain, 32 nodes, default's options (no probe pass)", "res=32,passes=0,depth=1", {1024, 2048, 4096, 8192}},
        {"default variance reduction (one probe pass, default's grid)", "nodes=16384,passes=1,depth=1", {64, 128, 256, 512, 1024}},
        {"one probe pass, 32 nodes", "res=32,passes=1,depth=1", {64, 128, 256, 512, 1024}},
    };
    std::printf("  time to %.1f %% RMS (rays per node doubled until reached; wall s, CPU s / %d threads)\n", 100 * target, st.threads);
    std::vector<std::pair<std::string, const Rung*>> best;
    std::vector<std::vector<Rung>> all(ladders.size());
    for (std::size_t l = 0; l < ladders.size(); ++l) {
        std::printf("    %s:\n", ladders[l].name);
        const Rung* reached = nullptr;
        for (const uint32_t r : ladders[l].rays) {
            TrySpec t = parseTry(ladders[l].spec);
            t.rays = r;
            const double cpu0 = cpuSeconds();
            const Baked b = tryBake(Ctx{as.scene, tracer, st, 1}, t);
            Rung g;
            g.rays = st.rays(r);
            g.cpu = cpuSeconds() - cpu0;
            g.wall = b.seconds;
            g.e = summarise(relative(values(b.irradiance, pts), truth.e, truth));
            all[l].push_back(g);
            std::printf("      %5u rays: RMS %5.1f %% (bias %+.1f %%), %7.2f s wall, %7.2f s CPU / %d = %6.2f s%s\n", g.rays, 100 * g.e.rms,
                        100 * g.e.bias, g.wall, g.cpu, st.threads, g.cpu / st.threads, g.e.rms <= target ? "  <- reached" : "");
            Row row{as.name, std::string("tta:") + ladders[l].spec + "/rays=" + std::to_string(g.rays), g.e};
            std::replace(row.config.begin(), row.config.end(), ',', '/');
            row.seconds = g.wall;
            row.cpu = g.cpu;
            writeCsvRow(csv, row);
            if (g.e.rms <= target) {
                reached = &all[l].back();
                break;
            }
        }
        best.push_back({ladders[l].name, reached});
    }
    auto cpuOf = [&](std::size_t i) { return best[i].second ? best[i].second->cpu / st.threads : -1.0; };
    std::printf("  time to %.1f %% RMS, CPU s / %d threads (- = not reached on the ladder):\n", 100 * target, st.threads);
    for (std::size_t i = 0; i < best.size(); ++i)
        if (best[i].second)
            std::printf("    %-66s %7.2f s (%u rays, wall %.2f s)\n", best[i].first.c_str(), cpuOf(i), best[i].second->rays,
                        best[i].second->wall);
        else
            std::printf("    %-66s %7s\n", best[i].first.c_str(), "-");
    // Plain: the fastest plain ladder; variance reduction: the fastest probe ladder.
    double plain = -1, probe = -1;
    for (std::size_t i = 0; i < best.size(); ++i) {
        const double c = cpuOf(i);
        if (c < 0) continue;
        double& slot = std::string(ladders[i].spec).find("passes=1") != std::string::npos ? probe : plain;
        if (slot < 0 || c < slot) slot = c;
    }
    if (plain > 0 && probe > 0)
        std::printf("  ratio, fastest plain / fastest probe pass: %.1fx (target >= 5x)\n", plain / probe);
    else
        std::printf("  ratio: not measured (a ladder did not reach %.1f %%)\n", 100 * target);
    // The default bake's own variance reduction (ladder 3) against the fastest plain ladder.
    if (plain > 0 && cpuOf(3) > 0)
        std::printf("  ratio, fastest plain / the default's (one probe pass on its grid): %.1fx\n", plain / cpuOf(3));
}

}  // namespace vdblight::accuracy
