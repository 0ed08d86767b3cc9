// vdblight_bench_walls: visibility-aware interpolation (depth moments, issue 15 item 4) on
// thin-wall scenes, against each scene's own SH order-2 representation floor.
//
// Scenes: `thin_wall_door` (leak_scenes.h: a 0.1 wall with a door, ceiling panel on one side)
// and `two_rooms` (a 0.08 wall with a door; the only light is a panel in the first room
// facing away from the door, so the second room is lit only by bounces through the door).
// Points: 200 random free-space points in the node box, and 200 more within one cell of the
// dividing wall, each with a random unit normal.
// Ground truth: `reference` (cached like vdblight_bench_error). Floor: a node baked exactly at
// each point with many rays (no interpolation, little noise), then the SH order-2 irradiance
// for the normal; what storing SH order 2 costs by itself.
// Rows: point gather (uniform, bilevel refine 2) and antialiased (interior; and with
// visibleSupport, whose node supports stop at walls) bakes, each
// looked up plainly and with depth weights (the same volume; the depth pass's time and rays
// are printed). Error |E - Eref| / max(Eref, 0.05 mean Eref) on luminance: RMS, p95, max,
// signed mean; and RMS / floor RMS. Every bake and the floor use --bounces 32.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bench_util.h"
#include "vdblight/bake/each_pass.h"
#include "bake/bake_antialiased.h"
#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "vdblight/reference/reference.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

#include "support/leak_scenes.h"
#include "support/scene_generators.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
constexpr int kBounces = 32;

// Two rooms [0,2]x[0,2]x[0,2] and [2.08,4]... joined by a door (0.8 x 1.4) in a wall 0.08
// thick at x = 1.96..2.04; a 0.6 x 0.6 panel at x = 0.5 facing -x (away from the door).
Scene twoRooms() {
    Scene s;
    s.name = "two_rooms_thin_wall";
    s.materials.resize(2);
    s.materials[0].albedo = Rgb(0.7f, 0.7f, 0.7f);
    s.materials[1].albedo = Rgb(0, 0, 0);
    s.materials[1].emission = Rgb(20, 20, 20);
    appendBox(s, Vec3f(0, 0, 0), Vec3f(4, 2, 2), /*inward=*/true, 0);
    const float lo = 1.96f, hi = 2.04f, e = 0.01f;
    appendBox(s, Vec3f(lo, -e, -e), Vec3f(hi, 2 + e, 0.6f), false, 0);
    appendBox(s, Vec3f(lo, -e, 1.4f), Vec3f(hi, 2 + e, 2 + e), false, 0);
    appendBox(s, Vec3f(lo, 1.4f, 0.6f), Vec3f(hi, 2 + e, 1.4f), false, 0);
    const float x = 0.5f, y0 = 0.7f, y1 = 1.3f, z0 = 0.7f, z1 = 1.3f;  // normal -x
    addTriangle(s, Vec3f(x, y0, z0), Vec3f(x, y0, z1), Vec3f(x, y1, z0), 1);
    addTriangle(s, Vec3f(x, y1, z0), Vec3f(x, y0, z1), Vec3f(x, y1, z1), 1);
    return s;
}

std::vector<ReferencePoint> points(const Tracer& tracer, const Bounds& box, int count, double nearWall, uint64_t seed) {
    Rng rng(seed);
    std::vector<ReferencePoint> pts;
    for (int tries = 0; int(pts.size()) < count && tries < 1000 * count; ++tries) {
        Vec3d t(rng.uniform(), rng.uniform(), rng.uniform());
        Vec3f p(box.lo + box.size() * t);
        if (nearWall > 0) p.x = float(2.0 + (2.0 * rng.uniform() - 1.0) * nearWall);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        if (bench::freeSpace(tracer, p)) pts.push_back({p, n});
    }
    return pts;
}

std::vector<double> cachedReference(const Scene& s, const Tracer& tracer, const std::vector<ReferencePoint>& pts,
                                    uint32_t samples, const std::string& tag) {
    const char* env = std::getenv("VDBLIGHT_BENCH_CACHE");
    const fs::path dir = env ? fs::path(env) : fs::temp_directory_path() / "vdblight_bench_cache";
    fs::create_directories(dir);
    const fs::path file = dir / ("walls_" + s.contentHash() + "_" + tag + "_" + std::to_string(pts.size()) + "_" +
                                 std::to_string(samples) + "_b" + std::to_string(kBounces) + ".txt");
    std::vector<double> ref;
    if (std::ifstream in{file}) {
        double a;
        while (in >> a) ref.push_back(a);
    }
    if (ref.size() == pts.size()) return ref;
    ReferenceOptions o;
    o.samples = samples;
    o.transport.maxBounces = kBounces;
    ref.clear();
    for (const auto& r : referenceIrradiance(s, tracer, pts, o)) ref.push_back(luminance(Rgb(r.irradiance)));
    std::ofstream out(file);
    out.precision(17);
    for (double r : ref) out << r << '\n';
    return ref;
}

/// The SH order-2 floor: a node baked at each point itself, evaluated for its normal.
std::vector<double> floorAtPoints(const Scene& s, const Tracer& tracer, const std::vector<ReferencePoint>& pts,
                                  uint32_t rays) {
    TransportOptions t;
    t.maxBounces = kBounces;
    const RadianceEstimator est(s, tracer, t);
    std::vector<double> out(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
        Rgbd c[9];
        RayCount count;
        projectIncidentRadiance(est, pts[i].position, rays, 99, i, c, count);
        float y[9];
        sh::evalUnrolled(normalize(pts[i].normal), y);
        Rgbd e{0, 0, 0};
        for (int j = 0; j < 9; ++j) e += c[j] * (sh::kCosineLobe[sh::bandOf(j)] * y[j]);
        out[i] = luminance(Rgb(e));
    }
    return out;
}

struct Errors {
    double rms = 0, p95 = 0, max = 0, bias = 0;
};
Errors errors(const std::vector<double>& got, const std::vector<double>& ref) {
    double mean = 0;
    for (double r : ref) mean += r / ref.size();
    std::vector<double> e;
    Errors out;
    double s2 = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const double d = (got[i] - ref[i]) / std::max(ref[i], 0.05 * mean);
        e.push_back(std::fabs(d));
        s2 += d * d;
        out.bias += d / ref.size();
    }
    std::sort(e.begin(), e.end());
    out.rms = std::sqrt(s2 / e.size());
    out.p95 = e[std::size_t(std::ceil(0.95 * e.size())) - 1];
    out.max = e.back();
    return out;
}

std::vector<double> lookups(const IrradianceQuery& q, const std::vector<ReferencePoint>& pts) {
    std::vector<double> out;
    for (const ReferencePoint& p : pts)
        out.push_back(std::max(0.0f, luminance(q.irradiance(p.position, normalize(p.normal)))));
    return out;
}
}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_walls",
                          {{"--rays", "N"}, {"--resolution", "N"}, {"--scene", "NAME"}, {"--variant", "NAME"}});
    if (!args.parse(argc, argv)) return 1;
    const bool quick = args.quick();
    const uint32_t rays = args.text("--rays").empty() ? (quick ? 128u : 1024u) : uint32_t(std::stoul(args.text("--rays")));
    const int resolution = args.text("--resolution").empty() ? (quick ? 8 : 16) : std::stoi(args.text("--resolution"));
    const int count = quick ? 60 : 200;
    const uint32_t refSamples = quick ? 2048 : 16384, floorRays = quick ? 1024 : 8192;

    struct Named {
        std::string name;
        Scene scene;
    };
    std::vector<Named> scenes;
    scenes.push_back({"thin_wall_door", makeThinWallScene().scene});
    scenes.push_back({"two_rooms", twoRooms()});
    const std::string onlyScene = args.text("--scene"), onlyVariant = args.text("--variant");
    if (!onlyScene.empty())
        scenes.erase(std::remove_if(scenes.begin(), scenes.end(), [&](const Named& n) { return n.name != onlyScene; }),
                     scenes.end());
    const auto wanted = [&](const char* variant) { return onlyVariant.empty() || onlyVariant == variant; };
    std::printf("scene,points,variant,weights,nodes,bake_s,depth_s,err_rms,err_p95,err_max,bias,floor_rms,rms_over_floor\n");
    for (const Named& sc : scenes) {
        const Scene& s = sc.scene;
        const Tracer tracer(s);
        const GridSpec grid = bench::uniformGrid(s.bounds(), resolution);
        struct PointSet {
            const char* name;
            std::vector<ReferencePoint> pts;
            std::vector<double> ref, floor;
            Errors floorErr;
        };
        std::vector<PointSet> sets;
        sets.push_back({"free_space", points(tracer, grid.nodeBounds(), count, 0, 11), {}, {}, {}});
        sets.push_back({"near_wall", points(tracer, grid.nodeBounds(), count, grid.spacing, 12), {}, {}, {}});
        for (PointSet& set : sets) {
            set.ref = cachedReference(s, tracer, set.pts, refSamples, set.name);
            set.floor = floorAtPoints(s, tracer, set.pts, floorRays);
            set.floorErr = errors(set.floor, set.ref);
            std::fprintf(stderr, "  %s %s: %zu points, floor RMS %.4f (node at each point, %u rays)\n", sc.name.c_str(),
                         set.name, set.pts.size(), set.floorErr.rms, floorRays);
        }
        std::fprintf(stderr, "  %s: %d x %d x %d nodes, spacing %.3f, %u rays per node\n", sc.name.c_str(), grid.nx,
                     grid.ny, grid.nz, grid.spacing, rays);

        GatherOptions g;
        g.raysPerNode = rays;
        g.transport.maxBounces = kBounces;
        DepthOptions d;
        d.raysPerNode = rays;
        auto report = [&](const char* variant, Volume& v, uint64_t nodes, double bakeSeconds) {
            DepthStats ds;
            bakeDepthMoments(tracer, v, d, nullptr, &ds);
            for (const bool weighted : {false, true}) {
                const IrradianceQuery q(v, OutsidePolicy::Clamp, weighted);
                for (const PointSet& set : sets) {
                    const Errors e = errors(lookups(q, set.pts), set.ref);
                    std::printf("%s,%s,%s,%s,%llu,%.3f,%.3f,%.4f,%.4f,%.4f,%+.4f,%.4f,%.2f\n", sc.name.c_str(), set.name,
                                variant, weighted ? "depth" : "off", (unsigned long long)nodes, bakeSeconds, ds.seconds,
                                e.rms, e.p95, e.max, e.bias, set.floorErr.rms, e.rms / set.floorErr.rms);
                }
            }
            std::fflush(stdout);
        };
        if (wanted("point_uniform")) {
            BakeStats st;
            Volume v = bakeShGather(s, tracer, grid, g, nullptr, &st);
            report("point_uniform", v, st.nodes, st.seconds);
            // Lookup throughput on one thread, weights off and on (the best of 3 runs).
            const bench::LookupInputs in = bench::randomLookups(grid.nodeBounds(), quick ? 200'000 : 1'000'000);
            Rgb sink{0, 0, 0};
            const double off = bench::lookupRate(IrradianceQuery(v, OutsidePolicy::Clamp, false), in, 3, sink);
            const double on = bench::lookupRate(IrradianceQuery(v, OutsidePolicy::Clamp, true), in, 3, sink);
            std::fprintf(stderr, "  %s: lookups per second on one thread: %.2f M plain, %.2f M depth-weighted (%.2fx) [%g]\n",
                         sc.name.c_str(), off * 1e-6, on * 1e-6, off / on, double(sink.x));
        }
        if (wanted("point_bilevel2")) {
            LevelsPlacement lp;
            lp.kind = LayoutKind::Bilevel;
            lp.refine = 2;
            const LevelLayout layout = placeLevels(grid, s.positions, s.indices, lp, 1);
            LevelsBakeStats ls;
            Volume v = bakeShGatherLevels(s, tracer, layout, g, nullptr, &ls);
            report("point_bilevel2", v, ls.nodes, ls.seconds);
        }
        if (wanted("antialiased_interior")) {
            AntialiasedOptions a;
            a.raysPerCell = rays;
            a.transport.maxBounces = kBounces;
            BakeStats st;
            Volume v = bakeShAntialiased(s, tracer, grid, a, nullptr, &st);
            report("antialiased_interior", v, st.nodes, st.seconds);
            // The node supports stop at walls too (AntialiasedOptions::visibleSupport).
            a.visibleSupport = true;
            v = bakeShAntialiased(s, tracer, grid, a, nullptr, &st);
            report("antialiased_visible_support", v, st.nodes, st.seconds);
        }
    }
    return 0;
}
