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
// Error decomposition (full runs; `--no-decompose` skips it): the SH order-2 projection at
// each evaluation point itself (at N and 16 N rays; its noise-free error is the floor no SH2
// volume can go below: the best reachable ratio to point sampling is printed beside the
// target), and each method baked again at 4x the rays (the Monte Carlo part of its error, and
// the rest against the SH2 projection at the points: interpolation / filtering).
// `--cost-only` bakes point, aa/interior and aa/interior least-squares once each without a
// reference (for callgrind); `--rays N` and `--threads N` override the defaults.
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

#include <tbb/parallel_for.h>

#include "bench_args.h"
#include "bake/bake_antialiased.h"
#include "vdblight/query/query.h"
#include "vdblight/reference/reference.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

#include "support/leak_scenes.h"

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

/// The errors of per-point irradiance luminances `got` against `ref`.
Errors measureValues(const std::vector<double>& got, const std::vector<double>& ref) {
    double num = 0, den = 0, rel2 = 0;
    Errors e;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const double r = ref[i];
        num += (got[i] - r) * (got[i] - r);
        den += r * r;
        const double rel = std::abs(got[i] - r) / std::max(r, 1e-6);
        rel2 += rel * rel;
        e.maxRelative = std::max(e.maxRelative, rel);
    }
    e.normalisedRms = std::sqrt(num / den);
    e.rmsRelative = std::sqrt(rel2 / double(got.size()));
    return e;
}

/// rel.RMS of `got` against `target`, normalised by the reference's sum of squares (so that
/// errors against the SH2 projection at the points add up with those against `reference`).
double relRmsAgainst(const std::vector<double>& got, const std::vector<double>& target, const std::vector<double>& ref) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < got.size(); ++i) num += (got[i] - target[i]) * (got[i] - target[i]), den += ref[i] * ref[i];
    return std::sqrt(num / den);
}

std::vector<double> lookup(const Volume& v, const std::vector<EvalPoint>& pts) {
    const IrradianceQuery q(v);
    std::vector<double> out(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) out[i] = luminance(q.irradiance(pts[i].position, pts[i].normal));
    return out;
}

/// The error left when the Monte Carlo part, falling as 1/N in the squared error, is taken
/// out, from errors at N and k N rays: e_N^2 = b^2 + n^2, e_kN^2 = b^2 + n^2 / k.
double noiseFree(double eN, double ekN, double k) { return std::sqrt(std::max(0.0, (k * ekN * ekN - eN * eN) / (k - 1))); }

/// Irradiance (luminance) at each point from the SH order-2 projection of the incident
/// radiance at the point itself (bakeShGather's estimator and sampling, `rays` rays): the
/// best an SH2 value can hold there, without any spatial interpolation or filtering.
std::vector<double> shAtPoints(const Scene& s, const Tracer& tracer, const TransportOptions& transport,
                               const std::vector<EvalPoint>& pts, uint32_t rays) {
    const RadianceEstimator estimator(s, tracer, transport);
    std::vector<double> out(pts.size());
    tbb::parallel_for(std::size_t(0), pts.size(), [&](std::size_t i) {
        Rgbd c[sh::kCoeffs];
        RayCount count;
        projectIncidentRadiance(estimator, pts[i].position, rays, 7, 1'000'000 + i, c, count);
        Rgb f[sh::kCoeffs];
        for (int j = 0; j < sh::kCoeffs; ++j) f[j] = Rgb(c[j]);
        out[i] = luminance(sh::irradiance(f, pts[i].normal));
    });
    return out;
}

void runCase(const Case& c, uint32_t raysPerNode, int points, uint32_t refSamples, int threads, int repeats,
             double tikhonov, const std::string& writeDir, bool decompose) {
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
    std::vector<double> refLum(pts.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const ReferenceResult& r = ref[i];
        refLum[i] = luminance(Rgb(r.irradiance));
        refErr = std::max(refErr, double(luminance(Rgb(r.standardError)) / std::max(1e-6f, luminance(Rgb(r.irradiance)))));
    }

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

    // The floor of any SH order-2 volume at these points: the SH2 projection at each point
    // itself, at N and 16 N rays (truncation to order 2 + noise; the noise extrapolated out).
    std::vector<double> sh16;
    double floorN = 0, floor16 = 0, floorClean = 0;
    if (decompose) {
        floorN = relRmsAgainst(shAtPoints(s, tracer, transport, pts, raysPerNode), refLum, refLum);
        sh16 = shAtPoints(s, tracer, transport, pts, 16 * raysPerNode);
        floor16 = relRmsAgainst(sh16, refLum, refLum);
        floorClean = noiseFree(floorN, floor16, 16);
        std::printf("  SH2 projected at the points themselves (no interpolation): rel.RMS %.1f%% at %u rays, %.1f%% at "
                    "%u rays, %.1f%% without noise (the SH order-2 floor)\n",
                    100 * floorN, raysPerNode, 100 * floor16, 16 * raysPerNode, 100 * floorClean);
    }

    std::printf("  %-28s %10s %10s %10s %9s %8s %9s %9s %8s", "method", "rel.RMS", "RMS(rel)", "max(rel)", "bake s",
                "x point", "cpu x pt", "rays x pt", "dilated");
    if (decompose) std::printf(" %8s %9s %8s %8s", "4x rays", "no-noise", "noise", "spatial");
    std::printf("\n");
    double pointSeconds = 0, pointCpu = 0, pointRays = 0;
    double relRms[8] = {}, relRms4[8] = {};
    static const char* const kName[8] = {"point", "point + invalidation (0.25)", "antialiased/all", "antialiased/interior",
                                         "aa/interior, visible support", "aa/all, least-squares",
                                         "aa/interior, least-squares", "aa/interior, Algorithm 2 only"};
    const auto bake = [&](int m, uint32_t scale, BakeStats& st) {
        GatherOptions p = po;
        p.raysPerNode *= scale;
        AntialiasedOptions a = ao;
        a.raysPerCell *= scale;
        if (m == 0) return bakeShGather(s, tracer, g, p, nullptr, &st);
        if (m == 1) return bakeShGatherInvalidated(s, tracer, g, p, 0.25, nullptr, &st);
        a.domain = m == 2 || m == 5 ? DomainMode::All : DomainMode::Interior;
        a.visibleSupport = m == 4;
        a.fit = m == 5 || m == 6 ? NodeFit::LeastSquares : NodeFit::Projection;
        a.fallback = m == 7 ? DomainFallback{0, 0} : DomainFallback{};
        return bakeShAntialiased(s, tracer, g, a, nullptr, &st);
    };
    for (int m = 0; m < 8; ++m) {
        BakeStats st;
        Volume v;
        double seconds = std::numeric_limits<double>::max(), cpu = seconds;
        for (int rep = 0; rep < repeats; ++rep) {  // the fastest of `repeats` identical bakes
            const double cpuStart = processCpuSeconds();
            v = bake(m, 1, st);
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
        const std::vector<double> got = lookup(v, pts);
        const Errors e = measureValues(got, refLum);
        relRms[m] = e.normalisedRms;
        std::printf("  %-28s %9.1f%% %9.1f%% %9.1f%% %9.3f %8.2f %9.2f %9.2f %8s", kName[m], 100 * e.normalisedRms,
                    100 * e.rmsRelative, 100 * e.maxRelative, st.seconds, st.seconds / pointSeconds, cpu / pointCpu,
                    double(st.rays.total()) / pointRays, metaString(v.meta, "nodes_dilated", "-").c_str());
        if (decompose && m != 4 && m != 7) {  // (visible support and Algorithm 2 alone: same error sources)
            BakeStats st4;
            const std::vector<double> got4 = lookup(bake(m, 4, st4), pts);
            const double e4 = relRmsAgainst(got4, refLum, refLum), clean = noiseFree(e.normalisedRms, e4, 4);
            relRms4[m] = e4;
            const double spatial = noiseFree(relRmsAgainst(got, sh16, refLum), relRmsAgainst(got4, sh16, refLum), 4);
            std::printf(" %7.1f%% %8.1f%% %7.1f%% %7.1f%%", 100 * e4, 100 * clean,
                        100 * std::sqrt(std::max(0.0, e.normalisedRms * e.normalisedRms - clean * clean)), 100 * spatial);
        }
        std::printf("\n");
    }
    if (decompose) {
        const double lsqClean = noiseFree(relRms[6], relRms4[6], 4);
        std::printf("  trilinear grid of this spacing: the least-squares fit without noise (the interpolated field closest "
                    "to the samples over the domain, as far as tikhonov lets it) reaches %.1f%%, i.e. %.2fx point, "
                    "%.2fx point+invalidation (targets 3x, 1.5x)\n",
                    100 * lsqClean, relRms[0] / lsqClean, relRms[1] / lsqClean);
        std::printf("  ('4x rays': the same bake at 4x the rays; 'no-noise' extrapolates N and 4N rays assuming the Monte "
                    "Carlo part of the squared error falls as 1/N; 'noise' = sqrt(rel.RMS^2 - no-noise^2); 'spatial': "
                    "the no-noise error against the SH2 projection at each point (16x rays), i.e. what interpolation / "
                    "filtering of the nodes adds to SH truncation)\n");
        std::printf("  targets for antialiased/interior: rel.RMS <= point / 3 = %.1f%% and <= point+invalidation / 1.5 = "
                    "%.1f%%; any SH2 volume without noise is at best near the floor %.1f%%: best reachable ratios "
                    "%.2fx point (target 3x), %.2fx point+invalidation (target 1.5x); at N rays, the SH2 projection at "
                    "the points themselves (no interpolation, same noise as a point node) reaches %.2fx and %.2fx\n",
                    100 * relRms[0] / 3, 100 * relRms[1] / 1.5, 100 * floorClean, relRms[0] / floorClean,
                    relRms[1] / floorClean, relRms[0] / floorN, relRms[1] / floorN);
        std::printf("  reached: eq. 6 %.2fx / %.2fx, least squares %.2fx / %.2fx lower than point / point+invalidation\n",
                    relRms[0] / relRms[3], relRms[1] / relRms[3], relRms[0] / relRms[6], relRms[1] / relRms[6]);
    }
}

/// `--cost-only`: no reference, no errors; point, aa/interior and aa/interior least-squares
/// baked once each (for profiling, e.g. under callgrind, where instruction counts replace
/// the noisy times of a loaded machine).
void costOnly(const Case& c, uint32_t raysPerNode, int threads) {
    const Scene& s = c.scene.scene;
    const GridSpec& g = c.grid;
    const Tracer tracer(s);
    TransportOptions transport;
    transport.maxBounces = 3;
    GatherOptions po;
    po.raysPerNode = raysPerNode;
    po.transport = transport;
    po.threads = threads;
    AntialiasedOptions ao;
    ao.raysPerCell = uint32_t(std::lround(double(raysPerNode) * double(g.nodeCount()) / double(cellCount(g))));
    ao.transport = transport;
    ao.threads = threads;
    std::printf("%s: cost only, %u rays/node\n", s.name.c_str(), raysPerNode);
    for (int m = 0; m < 3; ++m) {
        BakeStats st;
        const double cpuStart = processCpuSeconds();
        Volume v;
        if (m == 0) v = bakeShGather(s, tracer, g, po, nullptr, &st);
        ao.fit = m == 2 ? NodeFit::LeastSquares : NodeFit::Projection;
        if (m > 0) v = bakeShAntialiased(s, tracer, g, ao, nullptr, &st);
        std::printf("  %-28s cpu %.3f s, wall %.3f s, %.3f M rays, CG iterations %s\n",
                    m == 0 ? "point" : m == 1 ? "aa/interior" : "aa/interior, least-squares",
                    processCpuSeconds() - cpuStart, st.seconds, double(st.rays.total()) / 1e6,
                    metaString(v.meta, "fit_cg_iterations", "-").c_str());
    }
}
}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_antialiased",
                          {{"--fine", ""}, {"--write-volumes", "DIR"}, {"--scene", "NAME"}, {"--tikhonov", "T"},
                           {"--rays", "N"}, {"--threads", "N"}, {"--cost-only", ""}, {"--no-decompose", ""}});
    if (!args.parse(argc, argv)) return 2;
    const bool quick = args.quick(), fine = args.given("--fine"), cost = args.given("--cost-only");
    const bool decompose = !args.given("--no-decompose");
    const uint32_t raysOverride = uint32_t(args.integer("--rays", 0));
    const int threads = args.integer("--threads", 0);
    const std::string writeDir = args.text("--write-volumes"), only = args.text("--scene");
    const double tikhonov = args.real("--tikhonov", AntialiasedOptions{}.tikhonov);
    const uint32_t rays = raysOverride ? raysOverride : quick ? 64 : 512;
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
        if (only.empty() || c.scene.scene.name == only) {
            if (cost) costOnly(c, rays, threads);
            else runCase(c, rays, points, refSamples, threads, quick ? 1 : 3, tikhonov, writeDir, decompose && !quick);
        }
    return 0;
}
