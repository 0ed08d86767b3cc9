// vdblight_bench_layouts (layouts.h): the node-budget sweep (`--sweep R1,R2,...`). The table
// of bench_layouts.cpp compares the layouts at one budget; whether refinement pays can depend
// on the budget, so this repeats the comparison over several, with a bootstrap range of each
// ratio (a few points near walls carry most of the RMS).
#include "layouts.h"

#include <cstdio>

#include "vdblight/core/errors.h"

namespace vdblight::bench_layouts {

void benchSweep(const Probe& probe, const LayoutBenchOptions& lo, uint32_t rays, int threads, bool quick) {
    const Scene& scene = probe.scene;
    std::vector<BasisChoice> bases = {shBasis()};
    if (lo.binsResolution > 0) bases.push_back(binsBasis(lo.binsResolution));
    std::vector<std::vector<Rgb>> pointE;  // per basis: projection at the points, N rays
    for (const BasisChoice& b : bases) pointE.push_back(projectAtPoints(probe, b, rays));
    std::printf("  node-budget sweep (%s, %u rays per node in sh2%s; best of the refined layouts vs uniform, near "
                "geometry; target <= 0.70x; [5%%-95%%] of the ratio by bootstrap over the near points):\n",
                scene.name.c_str(), rays,
                lo.binsResolution > 0
                    ? (", " + std::to_string(bases[1].raysPerNode(rays)) + " in " + bases[1].name).c_str()
                    : "");
    for (const int r : lo.sweep) {
        LevelLayout bilevel;
        try {
            bilevel = makeLayout(scene, LayoutKind::Bilevel, r, 3, 2);
        } catch (const ValueError& e) {
            std::printf("    first level %d: skipped (%s)\n", r, e.what());
            continue;
        }
        const uint64_t target = bilevel.totalNodes();
        std::vector<Config> configs = {{"uniform", closestLayout(scene, LayoutKind::Uniform, 2, 1, target)},
                                       {"bilevel K=3", bilevel}};
        if (!quick) {
            configs.push_back({"bilevel K=2", closestLayout(scene, LayoutKind::Bilevel, 2, 2, target)});
            configs.push_back({"adaptive K=2 L=3", closestLayout(scene, LayoutKind::Adaptive, 2, 3, target)});
            configs.push_back({"adaptive K=2 L=3 D", closestLayout([&](int q) {
                                   return makeLayout(scene, LayoutKind::Adaptive, q, 2, 3, 0.5);
                               }, target)});
        }
        const std::vector<char> near = nearPoints(probe, bilevel);
        int nearCount = 0;
        for (const char n : near) nearCount += n;
        for (std::size_t bi = 0; bi < bases.size(); ++bi) {
            const BasisChoice& b = bases[bi];
            std::vector<double> rms;
            std::vector<std::vector<Rgb>> e;
            for (const Config& c : configs) {
                e.push_back(bakeAndQuery(probe, c.layout, b, rays, threads, nullptr));
                rms.push_back(rmsNearOf(probe, e.back(), near));
            }
            std::size_t best = 1;
            for (std::size_t c = 1; c < configs.size(); ++c)
                if (rms[c] < rms[best]) best = c;
            const double floor = rmsNearOf(probe, pointE[bi], near);
            const std::pair<double, double> ci = bootstrapRatio(probe, e[0], e[best], near);
            std::printf("    first level %2d, %6llu nodes, %4d near  %-7s uniform %6llu nodes %6.2f%%; best %-18s "
                        "%6llu nodes %6.2f%% = %.2fx [%.2f-%.2f]  %-7s (point floor %6.2f%% = %.2fx uniform)\n",
                        r, (unsigned long long)target, nearCount, b.name.c_str(),
                        (unsigned long long)configs[0].layout.totalNodes(), 100 * rms[0], configs[best].name,
                        (unsigned long long)configs[best].layout.totalNodes(), 100 * rms[best], rms[best] / rms[0],
                        ci.first, ci.second, rms[best] <= 0.70 * rms[0] ? "MET" : "NOT met", 100 * floor,
                        floor / rms[0]);
            if (configs.size() > 2) {  // every refined layout, not only the best (the best of several is optimistic)
                std::printf("      %-7s all vs uniform:", b.name.c_str());
                for (std::size_t c = 1; c < configs.size(); ++c)
                    std::printf("%s %s (%llu) %.2fx", c > 1 ? "," : "", configs[c].name,
                                (unsigned long long)configs[c].layout.totalNodes(), rms[c] / rms[0]);
                std::printf("\n");
            }
        }
    }
}

}  // namespace vdblight::bench_layouts
