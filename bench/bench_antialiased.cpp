// vdblight_bench_antialiased: does the Kontkanen-Laine bake remove the leak? (issue 5)
//
// On three generated leak scenes (a room split by a thin wall with a door; a small town of
// closed blocks under a sky and a sun; a room with a bed of thin bars), at an equal ray
// budget, the error of four bakes against `reference` at random points in the domain of
// interest within one cell of a surface:
//   point, point + back-face invalidation/dilation, antialiased/all, antialiased/interior.
// Printed per method: relative RMS error sqrt(sum (E - Eref)^2 / sum Eref^2), the RMS and the
// maximum of the per-point relative error |E - Eref| / Eref, and the bake time and its ratio
// to point sampling (same run, same threads). `--quick` shrinks the workloads for CI.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "vdblight/bake_antialiased.h"
#include "vdblight/leak_scenes.h"
#include "vdblight/query.h"
#include "vdblight/reference.h"
#include "vdblight/trace.h"

using namespace vdblight;

namespace {
struct Case {
    LeakScene scene;
    GridSpec grid;
};

GridSpec makeGrid(Vec3d origin, double spacing, int nx, int ny, int nz) {
    GridSpec g;
    g.origin = origin;
    g.spacing = spacing;
    g.nx = nx, g.ny = ny, g.nz = nz;
    return g;
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

void runCase(const Case& c, uint32_t raysPerNode, int points, uint32_t refSamples, int threads) {
    const Scene& s = c.scene.scene;
    const GridSpec& g = c.grid;
    const Tracer tracer(s);
    TransportOptions transport;
    transport.maxBounces = 3;
    const std::vector<EvalPoint> pts = leakEvalPoints(c.scene, g.nodeBounds(), g.spacing, points, 11);
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

    std::printf("\n%s: %d x %d x %d nodes, spacing %.3g, %u rays/node (anti-aliased: %u rays/cell), %d points "
                "within one cell of a surface, reference %u samples (max rel. std. error %.1f %%)\n",
                s.name.c_str(), g.nx, g.ny, g.nz, g.spacing, raysPerNode, ao.raysPerCell, int(pts.size()), refSamples,
                100 * refErr);
    std::printf("  %-28s %10s %10s %10s %9s %8s %8s\n", "method", "rel.RMS", "RMS(rel)", "max(rel)", "bake s",
                "x point", "dilated");
    double pointSeconds = 0;
    for (int m = 0; m < 4; ++m) {
        BakeStats st;
        Volume v;
        const char* name = "";
        if (m == 0) v = bakeShGather(s, tracer, g, po, nullptr, &st), name = "point";
        if (m == 1) v = bakeShGatherInvalidated(s, tracer, g, po, 0.25, nullptr, &st), name = "point + invalidation (0.25)";
        if (m >= 2) {
            ao.domain = m == 2 ? DomainMode::All : DomainMode::Interior;
            v = bakeShAntialiased(s, tracer, g, ao, nullptr, &st);
            name = m == 2 ? "antialiased/all" : "antialiased/interior";
        }
        if (m == 0) pointSeconds = st.seconds;
        const Errors e = measure(v, pts, ref);
        std::printf("  %-28s %9.1f%% %9.1f%% %9.1f%% %9.3f %8.2f %8s\n", name, 100 * e.normalisedRms,
                    100 * e.rmsRelative, 100 * e.maxRelative, st.seconds, st.seconds / pointSeconds,
                    metaString(v.meta, "nodes_dilated", "-").c_str());
    }
}
}  // namespace

int main(int argc, char** argv) {
    const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
    const uint32_t rays = quick ? 64 : 512;
    const int points = quick ? 200 : 1000;
    const uint32_t refSamples = quick ? 1024 : 16384;
    std::printf("vdblight_bench_antialiased%s: error near surfaces against reference, equal ray budget\n",
                quick ? " --quick (small workloads, noisy figures)" : "");
    const Case cases[] = {
        {makeThinWallScene(), makeGrid({0.25, 0.1, 0.1}, 0.25, 15, 8, 8)},
        {makeTownScene(), makeGrid({0.2, 0.2, 0.2}, 0.4, 20, 7, 20)},
        {makeBarsScene(), makeGrid({0.15, 0.1, 0.15}, 0.2, 14, 10, 14)},
    };
    for (const Case& c : cases) runCase(c, rays, points, refSamples, 0);
    return 0;
}
