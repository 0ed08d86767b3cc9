// vdblight_bench_antialiased: does the Kontkanen-Laine bake remove the leak? (issue 5)
//
// On three generated leak scenes (a room split by a thin wall with a door; a small town of
// closed blocks under a sky and a sun; a room with a bed of thin bars), at an equal ray
// budget, the error of four bakes against `reference` at random points in the domain of
// interest within one cell of a surface:
//   point, point + back-face invalidation/dilation, antialiased/all, antialiased/interior,
//   antialiased/interior with the experimental visible support (AntialiasedOptions), and
//   antialiased/all and /interior with the least-squares node fit (NodeFit::LeastSquares), and
//   antialiased/interior classified by Algorithm 2 alone (no DomainFallback: its cost).
// `--fine` adds the thin wall and the bed at half the spacing and the thin wall on a grid
// shifted by half a spacing (same evaluation points); `--write-volumes DIR` writes every bake
// as DIR/<scene>[_<variant>]_<method>.vdb (scripts/leak_pictures.sh slices them); `--scene NAME`
// runs only the cases of that scene (thin_wall_door, small_town, bed_bars); `--tikhonov T`
// sets the least-squares fit's AntialiasedOptions::tikhonov.
// Printed per method: relative RMS error sqrt(sum (E - Eref)^2 / sum Eref^2), the RMS and the
// maximum of the per-point relative error |E - Eref| / Eref, the bake time (the fastest of
// three identical bakes, one with --quick) and its ratio to point sampling (same run, same
// threads), the same ratio for the CPU time of the process (all threads; not inflated by
// waiting for a core on a loaded machine), and the ratio of traced rays to point sampling's.
// `--quick` shrinks the workloads for CI.
#include <sys/resource.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "vdblight/bake_antialiased.h"
#include "vdblight/leak_scenes.h"
#include "vdblight/query.h"
#include "vdblight/reference.h"
#include "vdblight/trace.h"
#include "vdblight/vdb_io.h"

using namespace vdblight;

namespace {
struct Case {
    LeakScene scene;
    GridSpec grid;
    double evalDistance = 0;  ///< evaluation points within this of a surface (0: one grid spacing)
    std::string label;        ///< printed after the scene name
    Bounds evalBox;           ///< evaluation points drawn in this box (empty: the grid's node bounds)
};

GridSpec makeGrid(Vec3d origin, double spacing, int nx, int ny, int nz) {
    GridSpec g;
    g.origin = origin;
    g.spacing = spacing;
    g.nx = nx, g.ny = ny, g.nz = nz;
    return g;
}

/// CPU seconds used by the process so far (all threads): a cost that waiting for a core on a
/// loaded machine does not inflate, unlike the wall-clock bake time.
double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Errors {
    double normalisedRms = 0, rmsRelative = 0, maxRelative = 0;
};

Errors measure(const Volume& v, const std::vector<EvalPoint>& pts, const std::vector<ReferenceResult>& ref) {
    const IrradianceQuery q(v);
    double num = 0, den = 0, rel2 = 0;
    Errors e;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double got = luminance(q.irradiance(pts[i].position, pts[i].normal));
        const double r = luminance(Rgb(ref[i].irradiance));
        num += (got - r) * (got - r);
        den += r * r;
        const double rel = std::abs(got - r) / std::max(r, 1e-6);
        rel2 += rel * rel;
        e.maxRelative = std::max(e.maxRelative, rel);
    }
    e.normalisedRms = std::sqrt(num / den);
    e.rmsRelative = std::sqrt(rel2 / double(pts.size()));
    return e;
}

void runCase(const Case& c, uint32_t raysPerNode, int points, uint32_t refSamples, int threads, int repeats,
             double tikhonov, const std::string& writeDir) {
    const Scene& s = c.scene.scene;
    const GridSpec& g = c.grid;
    const Tracer tracer(s);
    TransportOptions transport;
    transport.maxBounces = 3;
    const std::vector<EvalPoint> pts = leakEvalPoints(c.scene, c.evalBox.empty() ? g.nodeBounds() : c.evalBox, c.evalDistance > 0 ? c.evalDistance : g.spacing, points, 11);
    std::vector<ReferencePoint> rp;
    for (const EvalPoint& p : pts) rp.push_back({p.position, p.normal});
    ReferenceOptions ro;
    ro.samples = refSamples;
    ro.transport = transport;
    ro.threads = threads;
    const std::vector<ReferenceResult> ref = referenceIrradiance(s, tracer, rp, ro);
    double refErr = 0;
    for (const ReferenceResult& r : ref)
        refErr = std::max(refErr, double(luminance(Rgb(r.standardError)) / std::max(1e-6f, luminance(Rgb(r.irradiance)))));

    GatherOptions po;
    po.raysPerNode = raysPerNode;
    po.transport = transport;
    po.threads = threads;
    AntialiasedOptions ao;
    ao.raysPerCell = uint32_t(std::lround(double(raysPerNode) * double(g.nodeCount()) / double(cellCount(g))));
    ao.transport = transport;
    ao.threads = threads;
    ao.tikhonov = tikhonov;

    std::printf("\n%s%s: %d x %d x %d nodes, spacing %.3g, %u rays/node (anti-aliased: %u rays/cell), %d points "
                "within %.3g of a surface, reference %u samples (max rel. std. error %.1f %%)\n",
                s.name.c_str(), c.label.c_str(), g.nx, g.ny, g.nz, g.spacing, raysPerNode, ao.raysPerCell,
                int(pts.size()), c.evalDistance > 0 ? c.evalDistance : g.spacing, refSamples, 100 * refErr);
    std::printf("  %-28s %10s %10s %10s %9s %8s %9s %9s %8s\n", "method", "rel.RMS", "RMS(rel)", "max(rel)", "bake s",
                "x point", "cpu x pt", "rays x pt", "dilated");
    double pointSeconds = 0, pointCpu = 0, pointRays = 0;
    for (int m = 0; m < 8; ++m) {
        BakeStats st;
        Volume v;
        const char* name = "";
        double seconds = std::numeric_limits<double>::max(), cpu = seconds;
        for (int rep = 0; rep < repeats; ++rep) {  // the fastest of `repeats` identical bakes
            const double cpuStart = processCpuSeconds();
            if (m == 0) v = bakeShGather(s, tracer, g, po, nullptr, &st), name = "point";
            if (m == 1) v = bakeShGatherInvalidated(s, tracer, g, po, 0.25, nullptr, &st), name = "point + invalidation (0.25)";
            if (m >= 2) {
                ao.domain = m == 2 || m == 5 ? DomainMode::All : DomainMode::Interior;
                ao.visibleSupport = m == 4;
                ao.fit = m == 5 || m == 6 ? NodeFit::LeastSquares : NodeFit::Projection;
                ao.fallback = m == 7 ? DomainFallback{0, 0} : DomainFallback{};
                v = bakeShAntialiased(s, tracer, g, ao, nullptr, &st);
                static const char* const kName[6] = {"antialiased/all", "antialiased/interior",
                                                     "aa/interior, visible support", "aa/all, least-squares",
                                                     "aa/interior, least-squares", "aa/interior, Algorithm 2 only"};
                name = kName[m - 2];
            }
            seconds = std::min(seconds, st.seconds);
            cpu = std::min(cpu, processCpuSeconds() - cpuStart);
        }
        st.seconds = seconds;
        if (m == 0) pointSeconds = st.seconds, pointCpu = cpu, pointRays = double(st.rays.total());
        if (!writeDir.empty()) {
            static const char* const kFile[8] = {"point", "point_invalidated", "antialiased_all", "antialiased_interior",
                                                 "antialiased_visible", "antialiased_all_lsq", "antialiased_interior_lsq",
                                                 "antialiased_interior_no_fallback"};
            std::string tag = s.name;
            for (char ch : c.label)  // " (2x finer)" -> "_2x_finer"
                if (std::isalnum(static_cast<unsigned char>(ch))) tag += ch;
                else if (tag.back() != '_') tag += '_';
            if (tag.back() == '_') tag.pop_back();
            writeVolume(v, writeDir + "/" + tag + "_" + kFile[m] + ".vdb");
        }
        const Errors e = measure(v, pts, ref);
        std::printf("  %-28s %9.1f%% %9.1f%% %9.1f%% %9.3f %8.2f %9.2f %9.2f %8s\n", name, 100 * e.normalisedRms,
                    100 * e.rmsRelative, 100 * e.maxRelative, st.seconds, st.seconds / pointSeconds, cpu / pointCpu,
                    double(st.rays.total()) / pointRays, metaString(v.meta, "nodes_dilated", "-").c_str());
    }
}
}  // namespace

int main(int argc, char** argv) {
    bool quick = false, fine = false;
    std::string writeDir, only;
    double tikhonov = AntialiasedOptions{}.tikhonov;
    for (int a = 1; a < argc; ++a) {
        if (std::strcmp(argv[a], "--quick") == 0) quick = true;
        else if (std::strcmp(argv[a], "--fine") == 0) fine = true;
        else if (std::strcmp(argv[a], "--write-volumes") == 0 && a + 1 < argc) writeDir = argv[++a];
        else if (std::strcmp(argv[a], "--scene") == 0 && a + 1 < argc) only = argv[++a];
        else if (std::strcmp(argv[a], "--tikhonov") == 0 && a + 1 < argc) tikhonov = std::atof(argv[++a]);
        else {
            std::fprintf(stderr, "usage: vdblight_bench_antialiased [--quick] [--fine] [--write-volumes DIR] "
                                 "[--scene NAME] [--tikhonov T]\n");
            return 2;
        }
    }
    const uint32_t rays = quick ? 64 : 512;
    const int points = quick ? 200 : 1000;
    const uint32_t refSamples = quick ? 1024 : 16384;
    std::printf("vdblight_bench_antialiased%s: error near surfaces against reference, equal ray budget\n",
                quick ? " --quick (small workloads, noisy figures)" : "");
    std::vector<Case> cases = {
        {makeThinWallScene(), makeGrid({0.25, 0.1, 0.1}, 0.25, 15, 8, 8), 0, "", Bounds{}},
        {makeTownScene(), makeGrid({0.2, 0.2, 0.2}, 0.4, 20, 7, 20), 0, "", Bounds{}},
        {makeBarsScene(), makeGrid({0.15, 0.1, 0.15}, 0.2, 14, 10, 14), 0, "", Bounds{}},
    };
    if (fine) {
        // The same scenes at half the spacing (same evaluation points: within the coarse
        // spacing of a surface), same rays per node: does a finer grid remove the thin-wall
        // "lack of resolution" (K&L section 7)?
        cases.push_back({makeThinWallScene(), makeGrid({0.25, 0.1, 0.1}, 0.125, 29, 15, 15), 0.25, " (2x finer)", Bounds{}});
        cases.push_back({makeBarsScene(), makeGrid({0.15, 0.1, 0.15}, 0.1, 27, 19, 27), 0.2, " (2x finer)", Bounds{}});
        // Grid placement instead of resolution: the coarse grid shifted by half a spacing in x,
        // so that the wall (x in [1.95, 2.05]) lies between the node planes 1.875 and 2.125.
        cases.push_back({makeThinWallScene(), makeGrid({0.125, 0.1, 0.1}, 0.25, 16, 8, 8), 0.25, " (shifted)",
                         makeGrid({0.25, 0.1, 0.1}, 0.25, 15, 8, 8).nodeBounds()});
    }
    for (const Case& c : cases)
        if (only.empty() || c.scene.scene.name == only)
            runCase(c, rays, points, refSamples, 0, quick ? 1 : 3, tikhonov, writeDir);
    return 0;
}
