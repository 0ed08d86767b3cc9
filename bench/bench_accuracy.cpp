// vdblight_bench_accuracy: every method and mode against converged ground truth (issue 15).
//
// Scenes (accuracy_scenes.h): an office with hanging luminaires, the Cornell box, two rooms
// joined by a door in a wall thinner than the node spacing (one lit), an outdoor scene with
// sun and sky. Points: 200 per scene, uniformly random in the scene's box, kept if in free
// space (no axis ray from them meets a back face first: not inside a solid) and at least 1 %
// of the box diagonal from any surface (not in crevices), each with a uniformly random unit
// normal; deterministic (fixed seed).
// Ground truth: `reference` (reference.h) with 256 bounces and --ref-samples samples per
// point, luminance; cached in the build directory (or --cache DIR) by scene content hash,
// point-set hash, samples, bounces and seed. Its relative standard error is printed.
// Error of a method at a point: (E - E_ref) / E_ref (luminance; E_ref guarded below by 1 % of
// the scene's mean). Per configuration: RMS, p95 and max of |error|, signed bias (mean
// error), bake seconds (wall, --threads, 2 by default) and the process's CPU seconds during
// the bake (on a shared machine the wall time includes waiting for a core), nodes and file
// bytes per node.
// Decomposition per scene (as issue 5 did it, docs/methods.md "Where the error comes from"):
//  - floor: the representation at each point itself (a node exactly there, projected with
//    many rays: no interpolation, little noise), for SH order 2 and for the six irradiance
//    vectors of the photon volumes; noise extrapolated out from N/4 and N rays (1/N law);
//  - spatial: a nearly noise-free uniform bake (many rays / photons) against the floor's
//    values at the points, i.e. what interpolation between nodes adds;
//  - noise: configurations marked so are baked again with seed 2; the per-bake noise is
//    RMS((E1 - E2) / sqrt 2 / E_ref);
//  - bias: the mean signed error (every row).
// Regions (accuracy_scenes.h: the two rooms' lit and unlit room, the office's band around
// the luminaires) are reported on their own as well (CSV scene "SCENE:REGION").
// A new method or mode is one entry in configurations(): a name and a function that bakes
// (or otherwise builds) something that answers E(x, n).
// Output: tables on stdout, a CSV (--csv FILE; docs/accuracy.csv for the full run), which
// bench/plot_accuracy.sh turns into docs/images/accuracy_*.png.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <sys/resource.h>
#include <unistd.h>

#include "../libvdblight/src/bake/surface_cache.h"  // --probe-study: the probe pass's own cache
#include "../libvdblight/src/query/sh_uniform_lookup.h"  // internal: ShUniformLookup
#include "accuracy_scenes.h"
#include "bench_args.h"
#include "bench_util.h"
#include "vdblight/bake.h"
#include "vdblight/bake_adaptive.h"
#include "vdblight/bake_antialiased.h"
#include "vdblight/bake_bins.h"
#include "vdblight/bake_levels.h"
#include "vdblight/bake_depth.h"
#include "vdblight/node_budget.h"
#include "vdblight/irradiance_vectors.h"
#include "vdblight/layout_levels.h"
#include "vdblight/photons.h"
#include "vdblight/query.h"
#include "vdblight/query_direct.h"
#include "vdblight/reference.h"
#include "vdblight/bake_direct.h"
#include "vdblight/scene_lights.h"
#include "vdblight/sh.h"
#include "vdblight/trace.h"
#include "vdblight/vdb_io.h"
#include "vdblight/vector_grid_lookup.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------
// Settings and the things a configuration bakes.

struct Settings {
    bool quick = false;
    int threads = 2;
    int points = 200;
    uint32_t refSamples = 65536;
    int refBounces = 256;
    uint32_t floorRays = 8192;     ///< rays of the floor projection at each point
    uint32_t spatialRays = 1024;   ///< rays per node of the nearly noise-free SH bake
    uint64_t spatialPhotons = 4'000'000;
    fs::path cache;
    /// Workload scaling of --quick: resolutions halved, rays / photons divided by 16.
    int res(int full) const { return quick ? std::max(4, full / 2) : full; }
    uint32_t rays(uint32_t full) const { return quick ? std::max<uint32_t>(8, full / 16) : full; }
    uint64_t photons(uint64_t full) const { return quick ? std::max<uint64_t>(50'000, full / 32) : full; }
};

/// What a configuration produces: something that answers E(x, n), with its cost.
struct Baked {
    std::function<Rgb(const Vec3f&, const Vec3f&)> irradiance;
    double seconds = 0;
    uint64_t nodes = 0;
    uint64_t bytes = 0;  ///< the .vdb on disk
    std::string note;
};

struct Ctx {
    const Scene& scene;
    const Tracer& tracer;
    const Settings& settings;
    uint64_t seed;
};

/// One named method/mode. `bake` must use ctx.seed and ctx.settings.threads.
struct Config {
    std::string name;
    std::string what;
    std::function<Baked(const Ctx&)> bake;
    bool noise = false;  ///< also bake with seed 2 for the noise column
};

uint64_t bytesOnDisk(const Volume& v) {
    const fs::path tmp = fs::temp_directory_path() / ("vdblight_bench_accuracy_" + std::to_string(::getpid()) + ".vdb");
    writeVolume(v, tmp.string());
    const uint64_t size = fs::file_size(tmp);
    fs::remove(tmp);
    return size;
}

/// A Baked answering through IrradianceQuery (the library's run-time lookup, outside policy
/// Clamp: the default every application gets).
Baked fromVolume(Volume v, double seconds, uint64_t nodes) {
    Baked b;
    b.seconds = seconds;
    b.nodes = nodes;
    b.bytes = bytesOnDisk(v);
    auto volume = std::make_shared<Volume>(std::move(v));
    auto query = std::make_shared<IrradianceQuery>(*volume);
    b.irradiance = [volume, query](const Vec3f& x, const Vec3f& n) { return query->irradiance(x, n); };
    return b;
}

/// As fromVolume, but an occlusion volume's light visibility is interpolated trilinearly (the
/// lookup before issue 15 item 2; the SH part keeps its depth weights): for comparison.
Baked fromVolumeVisibilityTrilinear(Volume v, double seconds, uint64_t nodes) {
    Baked b = fromVolume(Volume(v), seconds, nodes);
    if (!v.direct.hasVisibility()) return b;
    auto volume = std::make_shared<Volume>(std::move(v));
    auto lookup = std::make_unique<OcclusionLookup>(std::make_unique<ShUniformLookup>(*volume, OutsidePolicy::Clamp), *volume);
    lookup->setVisibilityDepthWeights(false);
    auto query = std::make_shared<IrradianceQuery>(std::move(lookup), "sh2-uniform");
    b.irradiance = [volume, query](const Vec3f& x, const Vec3f& n) { return query->irradiance(x, n); };
    return b;
}

/// The uniform grid of `vdblight bake`: `resolution` nodes on the longest axis of the scene box.
GridSpec gridFor(const Scene& s, int resolution) {
    GridPlacement p;
    p.resolution = resolution;
    return placeUniformGrid(s.bounds(), p, 1);
}

GatherOptions gatherOptions(const Ctx& c, uint32_t rays) {
    GatherOptions g;
    g.raysPerNode = rays;
    g.seed = c.seed;
    g.threads = c.settings.threads;
    return g;
}

/// `bounces` > 0 overrides the transport's bounce cap (the decomposition's bakes match the
/// ground truth's, so that they measure representation and interpolation only).
/// `depth`: also depth moments from the gather's own rays, and lookups weighted by them
/// (visibility-aware interpolation, depth_moments.h).
Baked pointGather(const Ctx& c, int resolution, uint32_t rays, int bounces = 0, bool depth = false) {
    GatherOptions g = gatherOptions(c, rays);
    if (bounces > 0) g.transport.maxBounces = bounces;
    g.depthMoments = depth;
    const double t0 = bench::now();
    Volume v = bakeShGather(c.scene, c.tracer, gridFor(c.scene, resolution), g);
    const double t = bench::now() - t0;
    const uint64_t nodes = v.levels[0].grid.nodeCount();
    return fromVolume(std::move(v), t, nodes);
}

Baked antialiased(const Ctx& c, int resolution, uint32_t rays, NodeFit fit) {
    AntialiasedOptions a;
    a.raysPerCell = rays;
    a.seed = c.seed;
    a.threads = c.settings.threads;
    a.fit = fit;
    const double t0 = bench::now();
    Volume v = bakeShAntialiased(c.scene, c.tracer, gridFor(c.scene, resolution), a);
    const double t = bench::now() - t0;
    const uint64_t nodes = v.levels[0].grid.nodeCount();
    return fromVolume(std::move(v), t, nodes);
}

Baked adaptiveLayout(const Ctx& c, int resolution, uint32_t rays, int levels, int refine, bool depth = false) {
    LevelsPlacement lp;
    lp.kind = LayoutKind::Adaptive;
    lp.levels = levels;
    lp.refine = refine;
    const double t0 = bench::now();
    const LevelLayout layout = placeLevels(gridFor(c.scene, resolution), c.scene.positions, c.scene.indices, lp, 1);
    LevelsBakeStats st;
    GatherOptions g = gatherOptions(c, rays);
    g.depthMoments = depth;
    Volume v = bakeShGatherLevels(c.scene, c.tracer, layout, g, nullptr, &st);
    return fromVolume(std::move(v), bench::now() - t0, st.nodes);
}

Baked targetError(const Ctx& c, int resolution, double target, uint32_t maxRays) {
    AdaptiveOptions a;
    a.targetError = target;
    a.maxRays = maxRays;
    a.minRays = std::min<uint32_t>(a.minRays, maxRays);
    a.seed = c.seed;
    a.threads = c.settings.threads;
    const double t0 = bench::now();
    AdaptiveStats st;
    Volume v = bakeShGatherAdaptive(c.scene, c.tracer, gridFor(c.scene, resolution), a, nullptr, &st);
    Baked b = fromVolume(std::move(v), bench::now() - t0, st.nodes);
    b.note = std::to_string(st.samples / std::max<uint64_t>(1, st.nodes)) + " rays/node";
    return b;
}

/// `resolution` nodes on the longest axis, or (resolution 0) the default bake's grid of about
/// 16 384 nodes (as tryGrid's nodes=16384).
Baked photons(const Ctx& c, int resolution, uint64_t count, int bounces = 0, iv::Blend blend = iv::kDefaultBlend) {
    PhotonOptions p;
    if (bounces > 0) p.transport.maxBounces = bounces;
    p.photons = count;
    p.seed = c.seed;
    p.threads = c.settings.threads;
    GridSpec grid;
    if (resolution > 0) {
        grid = gridFor(c.scene, resolution);
    } else {
        GridPlacement gp;
        gp.spacing = spacingForNodeBudget(c.scene.bounds(), c.settings.quick ? 16384 / 8 : 16384);
        grid = placeUniformGrid(c.scene.bounds(), gp, 1);
    }
    const double t0 = bench::now();
    Volume v = bakePhotons(c.scene, c.tracer, grid, p);
    const double t = bench::now() - t0;
    // The library's default lookup reads the quadratic blend; another blend reads through its own.
    std::shared_ptr<VectorGridLookup> other;
    if (blend != iv::kDefaultBlend) other = std::make_shared<VectorGridLookup>(v, OutsidePolicy::Clamp, Interpolation::Trilinear, blend);
    Baked b = fromVolume(std::move(v), t, grid.nodeCount());
    if (other) b.irradiance = [other](const Vec3f& x, const Vec3f& n) { return other->irradiance(x, n); };
    return b;
}

Baked binsBake(const Ctx& c, int resolution, int binResolution) {
    BinsBakeOptions bo;
    bo.basis.kind = bins::BasisSpec::Kind::Bins;
    bo.basis.resolution = binResolution;
    bo.seed = c.seed;
    bo.threads = c.settings.threads;
    const double t0 = bench::now();
    LevelsBakeStats st;
    Volume v = bakeBins(c.scene, c.tracer, uniformLayout(gridFor(c.scene, resolution)), bo, nullptr, &st);
    return fromVolume(std::move(v), bench::now() - t0, st.nodes);
}

/// Point gather with `bake --direct MODE` (bake_direct.h): runtime answers add every light's
/// direct light with shadow rays at each lookup (what `vdblight query --scene` does, 256 rays
/// per polygon light); occlusion volumes answer through IrradianceQuery (exact direct x baked
/// visibility). Occlusion in a scene without lights falls back to baked, as the command does.
Baked directGather(const Ctx& c, int resolution, uint32_t rays, DirectMode mode, int probePasses = 0) {
    DirectOptions d;
    d.mode = mode;
    d.seed = c.seed;
    d.threads = c.settings.threads;
    const GridSpec grid = gridFor(c.scene, resolution);
    const double t0 = bench::now();
    if (mode != DirectMode::Baked && sceneLights(c.scene).empty()) d.mode = DirectMode::Baked;
    const DirectPlan plan = planDirectLight(c.scene, c.tracer, grid, d);
    GatherOptions g = gatherOptions(c, rays);
    g.transport.skipAtReceiver = plan.filter;
    g.probePasses = probePasses;
    Volume v = bakeShGather(c.scene, c.tracer, grid, g);
    bakeLightVisibility(c.scene, c.tracer, plan, d, v);
    const double t = bench::now() - t0;
    Baked b = fromVolume(std::move(v), t, grid.nodeCount());
    if (d.mode == DirectMode::Runtime) {
        auto lights = std::make_shared<std::vector<SceneLight>>(plan.lights);
        const Scene* scene = &c.scene;
        const Tracer* tracer = &c.tracer;
        auto stored = b.irradiance;
        b.irradiance = [stored, lights, scene, tracer](const Vec3f& x, const Vec3f& n) {
            uint32_t bits[3];
            std::memcpy(bits, &x.x, 4);
            std::memcpy(bits + 1, &x.y, 4);
            std::memcpy(bits + 2, &x.z, 4);
            RayCount rays;  // shadow-ray stream from the point: deterministic for any thread order
            const uint64_t stream = hashCombine(hashCombine(bits[0], bits[1]), bits[2]);
            return stored(x, n) + runtimeDirectIrradiance(*scene, *tracer, *lights, x, n, 256, stream, rays);
        };
        b.note = "+ direct with shadow rays at lookup";
    }
    return b;
}

/// A candidate default (--try SPEC): `key=value` pairs separated by commas, e.g.
/// "res=32,rays=512,passes=1,depth=1" or "nodes=32768,target=0.03,max=1024".
///   res=N      nodes on the longest axis (16); nodes=N: the spacing that gives about N nodes
///   rays=N     rays per node and pass (256); target=E, min=N, max=N: error-targeted instead
///   passes=N   probe-to-probe passes (1); depth=1: depth moments, weighted lookups
///   direct=baked|runtime|occlusion (occlusion)
/// Every bake of the command is reproduced (bake_direct.h plan, gather, visibility, depth).
struct TrySpec {
    int res = 16;
    uint64_t nodes = 0;
    uint32_t rays = 256, minRays = 64, maxRays = 2048;
    double target = 0;
    int passes = 1;
    bool depth = false;
    DirectMode direct = DirectMode::Occlusion;
};

TrySpec parseTry(const std::string& spec) {
    TrySpec t;
    std::size_t pos = 0;
    while (pos < spec.size()) {
        std::size_t end = spec.find(',', pos);
        if (end == std::string::npos) end = spec.size();
        const std::string kv = spec.substr(pos, end - pos);
        pos = end + 1;
        const std::size_t eq = kv.find('=');
        if (eq == std::string::npos) throw ValueError("--try: expected key=value, got '" + kv + "'");
        const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
        if (k == "res") t.res = std::stoi(v);
        else if (k == "nodes") t.nodes = std::stoull(v);
        else if (k == "rays") t.rays = uint32_t(std::stoul(v));
        else if (k == "min") t.minRays = uint32_t(std::stoul(v));
        else if (k == "max") t.maxRays = uint32_t(std::stoul(v));
        else if (k == "target") t.target = std::stod(v);
        else if (k == "passes") t.passes = std::stoi(v);
        else if (k == "depth") t.depth = v == "1";
        else if (k == "direct") t.direct = parseDirectMode(v);
        else throw ValueError("--try: unknown key '" + k + "'");
    }
    return t;
}

/// The grid of a TrySpec: `nodes` > 0 is spacingForNodeBudget (the default bake's rule).
GridSpec tryGrid(const Scene& s, const TrySpec& t, const Settings& st) {
    GridPlacement p;
    if (t.nodes > 0) {
        p.spacing = spacingForNodeBudget(s.bounds(), st.quick ? std::max<uint64_t>(64, t.nodes / 8) : t.nodes);
    } else {
        p.resolution = st.res(t.res);
    }
    return placeUniformGrid(s.bounds(), p, 1);
}

/// The volume a TrySpec bakes (every bake of the command: plan, gather, visibility, depth);
/// `note` gets the rays per node of error-targeted bakes.
Volume tryVolume(const Ctx& c, const TrySpec& t, std::string& note) {
    DirectOptions d;
    d.mode = t.direct;
    d.seed = c.seed;
    d.threads = c.settings.threads;
    const GridSpec grid = tryGrid(c.scene, t, c.settings);
    if (d.mode != DirectMode::Baked && sceneLights(c.scene).empty()) d.mode = DirectMode::Baked;
    const DirectPlan plan = planDirectLight(c.scene, c.tracer, grid, d);
    Volume v;
    if (t.target > 0) {
        AdaptiveOptions a;
        a.targetError = t.target;
        a.minRays = c.settings.rays(t.minRays);
        a.maxRays = std::max(a.minRays, c.settings.rays(t.maxRays));
        a.seed = c.seed;
        a.threads = c.settings.threads;
        a.transport.skipAtReceiver = plan.filter;
        a.probePasses = t.passes;
        AdaptiveStats st;
        v = bakeShGatherAdaptive(c.scene, c.tracer, grid, a, nullptr, &st);
        note = std::to_string(st.samples / std::max<uint64_t>(1, st.nodes)) + " rays/node";
        if (t.depth) {
            DepthOptions dopt;
            dopt.raysPerNode = c.settings.rays(256);
            dopt.seed = c.seed;
            dopt.threads = c.settings.threads;
            bakeDepthMoments(c.tracer, v, dopt);
        }
    } else {
        GatherOptions g = gatherOptions(c, c.settings.rays(t.rays));
        g.transport.skipAtReceiver = plan.filter;
        g.probePasses = t.passes;
        g.depthMoments = t.depth;
        v = bakeShGather(c.scene, c.tracer, grid, g);
    }
    bakeLightVisibility(c.scene, c.tracer, plan, d, v);
    return v;
}

Baked tryBake(const Ctx& c, const TrySpec& t) {
    const double t0 = bench::now();
    std::string note;
    Volume v = tryVolume(c, t, note);
    const double secs = bench::now() - t0;
    const uint64_t nodes = v.levels[0].grid.nodeCount();
    Baked b = fromVolume(std::move(v), secs, nodes);
    b.note = note;
    return b;
}

/// The table of methods and modes. Resolutions and budgets are the full run's; --quick
/// scales them down (Settings::res / rays / photons).
std::vector<Config> configurations() {
    std::vector<Config> v;
    // What `vdblight bake SCENE -o OUT` does with no other option (bake/bake_request.cpp, --quality
    // default; keep this in step with its qualityPreset): --direct occlusion (baked in a scene
    // without lights), about 16384 nodes in the scene box (node_budget.h), 768 rays of full
    // paths + one probe-to-probe pass of 768, depth moments from the gather's own first hits
    // and depth-weighted lookups. --quick: 1/8 of the nodes, 1/16 of the rays.
    v.push_back({"default", "vdblight bake SCENE -o OUT (--quality default: ~16384 nodes, 768 rays + 1 probe pass, "
                            "depth moments, --direct occlusion)",
                 [](const Ctx& c) { return tryBake(c, parseTry("nodes=16384,rays=768,passes=1,depth=1")); }, true});
    // The default with the light visibility interpolated trilinearly (as before issue 15 item 2).
    v.push_back({"default_vis_trilinear", "the default bake, light visibility looked up trilinearly (not depth-weighted)",
                 [](const Ctx& c) {
                     const double t0 = bench::now();
                     std::string note;
                     Volume vol = tryVolume(c, parseTry("nodes=16384,rays=768,passes=1,depth=1"), note);
                     const double t = bench::now() - t0;
                     const uint64_t nodes = vol.levels[0].grid.nodeCount();
                     return fromVolumeVisibilityTrilinear(std::move(vol), t, nodes);
                 }});
    // The default before this choice (issue 15 merges): 16 nodes on the longest axis, 256 rays
    // + one probe pass, no depth moments.
    v.push_back({"default_16_256", "16 nodes, 256 rays + 1 probe pass, --direct occlusion (the default before)",
                 [](const Ctx& c) { return tryBake(c, parseTry("res=16,rays=256,passes=1")); }});
    for (const auto& [mode, name] : {std::pair{DirectMode::Baked, "baked"}, std::pair{DirectMode::Runtime, "runtime"},
                                     std::pair{DirectMode::Occlusion, "occlusion"}})
        v.push_back({std::string("direct_") + name, std::string("--direct ") + name + ", 16 nodes, 256 rays",
                     [mode = mode](const Ctx& c) { return directGather(c, c.settings.res(16), c.settings.rays(256), mode); }});
    for (const uint32_t rays : {64u, 1024u})
        v.push_back({"point_16_" + std::to_string(rays), "point gather, 16 nodes, " + std::to_string(rays) + " rays",
                     [rays](const Ctx& c) { return pointGather(c, c.settings.res(16), c.settings.rays(rays)); },
                     rays == 1024});
    v.push_back({"point_16_1024_depth", "point gather, 16 nodes, 1024 rays, --depth-moments (weighted lookup)",
                 [](const Ctx& c) { return pointGather(c, c.settings.res(16), c.settings.rays(1024), 0, true); }});
    v.push_back({"point_32_256", "point gather, 32 nodes, 256 rays",
                 [](const Ctx& c) { return pointGather(c, c.settings.res(32), c.settings.rays(256)); }});
    v.push_back({"preview", "--quality preview: 16 nodes, 256 rays of full paths, no probe pass, no depth moments, "
                            "--direct occlusion",
                 [](const Ctx& c) { return tryBake(c, parseTry("res=16,rays=256,passes=0")); }});
    v.push_back({"probe_32_128", "--resolution 32 --rays 128 --probe-passes 1 (issue 15)",
                 [](const Ctx& c) {
                     GatherOptions g;
                     g.raysPerNode = c.settings.rays(128);
                     g.probePasses = 1;
                     g.seed = c.seed;
                     g.threads = c.settings.threads;
                     const double t0 = bench::now();
                     Volume vol = bakeShGather(c.scene, c.tracer, gridFor(c.scene, c.settings.res(32)), g);
                     const double t = bench::now() - t0;
                     const uint64_t nodes = vol.levels[0].grid.nodeCount();
                     return fromVolume(std::move(vol), t, nodes);
                 }});
    v.push_back({"antialiased", "--sampling antialiased (interior), 16 nodes, 256 rays/cell",
                 [](const Ctx& c) { return antialiased(c, c.settings.res(16), c.settings.rays(256), NodeFit::Projection); }});
    v.push_back({"antialiased_lsq", "--sampling antialiased --fit least-squares, 16 nodes, 256 rays/cell",
                 [](const Ctx& c) { return antialiased(c, c.settings.res(16), c.settings.rays(256), NodeFit::LeastSquares); }});
    v.push_back({"adaptive", "--layout adaptive --levels 3 --refine 2, 16 nodes, 128 rays",
                 [](const Ctx& c) { return adaptiveLayout(c, c.settings.res(16), c.settings.rays(128), 3, 2); }});
    v.push_back({"adaptive_depth", "--layout adaptive --levels 3 --refine 2 --depth-moments, 16 nodes, 128 rays",
                 [](const Ctx& c) { return adaptiveLayout(c, c.settings.res(16), c.settings.rays(128), 3, 2, true); }});
    v.push_back({"target_0.03", "--target-error 0.03 --max-rays 2048, 16 nodes",
                 [](const Ctx& c) { return targetError(c, c.settings.res(16), 0.03, c.settings.rays(2048)); }});
    v.push_back({"photons", "--method photons --photons 4000000, 16 nodes",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(4'000'000)); }, true});
    v.push_back({"photons_1M", "--method photons --photons 1000000, 16 nodes",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(1'000'000)); }});
    v.push_back({"photons_16k", "--method photons --photons 4000000 on the default's grid (~16384 nodes)",
                 [](const Ctx& c) { return photons(c, 0, c.settings.photons(4'000'000)); }, true});
    v.push_back({"photons_paper", "--method photons --photons 4000000, 16 nodes, read with query --iv-blend paper "
                                  "(the lookup before issue 15 item 5)",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(4'000'000), 0, iv::Blend::Paper); }});
    v.push_back({"bins_11", "--basis bins:11 (242 bins, 1 ray each), 16 nodes",
                 [](const Ctx& c) { return binsBake(c, c.settings.res(16), c.settings.quick ? 3 : 11); }});
    return v;
}

// ---------------------------------------------------------------------------------------
// Points, ground truth and errors.

struct Points {
    std::vector<Vec3f> x, n;
};

/// True if no surface lies within `clearance` of x along 26 directions (axes, face and body
/// diagonals): the point is not in a crevice (under a book, between a board and the floor),
/// where a relative error measures nothing any volume could hold.
bool clearOfSurfaces(const Tracer& tracer, const Vec3f& x, float clearance) {
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                if (!dx && !dy && !dz) continue;
                const Hit h = tracer.intersect(Ray{x, normalize(Vec3f(float(dx), float(dy), float(dz))), 0.0f, clearance});
                if (h.hit()) return false;
            }
    return true;
}

/// `count` free-space points uniformly in the scene box (inset by 0.1 % of its size), at least
/// 1 % of the box diagonal from every surface (clearOfSurfaces), with uniformly random unit
/// normals, from a fixed seed.
Points freeSpacePoints(const Scene& s, const Tracer& tracer, int count) {
    Rng rng(2026, 15);
    const Bounds box = s.bounds();
    const float clearance = float(0.01 * length(box.size()));
    Points p;
    for (int tries = 0; int(p.x.size()) < count && tries < 1000 * count; ++tries) {
        const Vec3d t(0.001 + 0.998 * rng.uniform(), 0.001 + 0.998 * rng.uniform(), 0.001 + 0.998 * rng.uniform());
        const Vec3f x(box.lo + box.size() * t);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        if (!bench::freeSpace(tracer, x) || !clearOfSurfaces(tracer, x, clearance)) continue;
        p.x.push_back(x);
        p.n.push_back(n);
    }
    return p;
}

std::string pointsHash(const Points& p) {
    uint64_t h = 0x15ull;
    for (std::size_t i = 0; i < p.x.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const float fx = p.x[i][k], fn = p.n[i][k];
            uint32_t a, b;
            std::memcpy(&a, &fx, 4);
            std::memcpy(&b, &fn, 4);
            h = hashCombine(hashCombine(h, a), b);
        }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

struct Truth {
    std::vector<double> e, se;  ///< luminance of E_ref and of its standard error
    double mean = 0;
    double guard = 0.01;  ///< the smallest denominator, as a fraction of `mean`
    double denominator(std::size_t i) const { return std::max(e[i], guard * mean); }
};

Truth groundTruth(const Scene& s, const Tracer& tracer, const Points& p, const Settings& st, uint32_t samples) {
    fs::create_directories(st.cache);
    const fs::path file = st.cache / (s.contentHash() + "_" + pointsHash(p) + "_" + std::to_string(samples) + "s_" +
                                      std::to_string(st.refBounces) + "b_seed1.txt");
    Truth t;
    if (std::ifstream in{file}) {
        double a, b;
        while (in >> a >> b) t.e.push_back(a), t.se.push_back(b);
    }
    if (t.e.size() != p.x.size()) {
        std::vector<ReferencePoint> rp;
        for (std::size_t i = 0; i < p.x.size(); ++i) rp.push_back({p.x[i], p.n[i]});
        ReferenceOptions o;
        o.samples = samples;
        o.transport.maxBounces = st.refBounces;
        const double t0 = bench::now();
        const auto r = referenceIrradiance(s, tracer, rp, o);
        t.e.clear(), t.se.clear();
        for (const auto& x : r) t.e.push_back(luminance(Rgb(x.irradiance))), t.se.push_back(luminance(Rgb(x.standardError)));
        const fs::path tmp = file.string() + ".tmp";
        {
            std::ofstream out(tmp);
            out.precision(17);
            for (std::size_t i = 0; i < t.e.size(); ++i) out << t.e[i] << ' ' << t.se[i] << '\n';
        }
        fs::rename(tmp, file);
        std::printf("  ground truth: %zu points x %u samples, %d bounces, computed in %.1f s, cached in %s\n", p.x.size(),
                    samples, st.refBounces, bench::now() - t0, file.c_str());
    } else {
        std::printf("  ground truth: read from %s\n", file.c_str());
    }
    for (double e : t.e) t.mean += e / double(t.e.size());
    return t;
}

struct Errors {
    double rms = 0, p95 = 0, max = 0, bias = 0;
};

/// Statistics of per-point relative errors (signed).
Errors summarise(const std::vector<double>& rel) {
    Errors e;
    std::vector<double> a;
    for (double r : rel) {
        const double x = std::isfinite(r) ? r : 1e30;
        a.push_back(std::abs(x));
        e.rms += x * x;
        e.bias += x;
    }
    std::sort(a.begin(), a.end());
    e.rms = std::sqrt(e.rms / double(a.size()));
    e.bias /= double(a.size());
    e.p95 = a[std::size_t(std::ceil(0.95 * double(a.size()))) - 1];
    e.max = a.back();
    return e;
}

std::vector<double> values(const std::function<Rgb(const Vec3f&, const Vec3f&)>& f, const Points& p) {
    std::vector<double> v(p.x.size());
    for (std::size_t i = 0; i < p.x.size(); ++i) v[i] = luminance(f(p.x[i], p.n[i]));
    return v;
}

std::vector<double> relative(const std::vector<double>& got, const std::vector<double>& want, const Truth& t) {
    std::vector<double> r(got.size());
    for (std::size_t i = 0; i < got.size(); ++i) r[i] = (got[i] - want[i]) / t.denominator(i);
    return r;
}

// ---------------------------------------------------------------------------------------
// The floor: the representations at the points themselves.

/// Incident radiance at a point projected, from the same samples, into SH order 2, the six
/// irradiance vectors (irradiance_vectors.h) and the cosine-weighted irradiance for the point's
/// normal (a check on the projection: that one has no representation error). Sampling as the
/// point gather's (bake.h): stratified uniform directions with gathered radiance, one NEE
/// sample of the emissive triangles per direction (MIS), punctual lights exactly.
struct AtPoint {
    Rgbd sh[sh::kCoeffs] = {};
    double iv[iv::kFloatsPerNode] = {};
    Rgbd e{0, 0, 0};
};

AtPoint projectAtPoint(const RadianceEstimator& est, const Vec3f& x, const Vec3f& n, uint32_t rays, uint64_t stream) {
    AtPoint a;
    auto add = [&](const Vec3f& d, const Rgbd& w) {
        float y[sh::kCoeffs];
        sh::evalUnrolled(d, y);
        for (int j = 0; j < sh::kCoeffs; ++j) a.sh[j] += w * double(y[j]);
        for (int axis = 0; axis < 3; ++axis) {
            const int dir = iv::direction(axis, d[axis] < 0.0f);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) a.iv[iv::channel(dir, c) * 3 + k] += w[c] * double(d[k]);
        }
        a.e += w * double(std::max(0.0f, dot(d, n)));
    };
    Rng rng(stream, 4);
    RayCount count;
    constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
    const double lightOffset = toUnitDouble(hashCombine(stream, 3));
    for (uint32_t i = 0; i < rays; ++i) {
        float u, v;
        sobol02(i, hashCombine(stream, 1), u, v);
        const Vec3f d = uniformSphere(u, v);
        add(d, Rgbd(est.gatherRadiance(x, d, kSpherePdf, rng, count)) * (4.0 * kPi / rays));
        if (!est.hasEmissiveTriangles()) continue;
        sobol02(i, hashCombine(stream, 2), u, v);
        double w = radicalInverse(3, i) + lightOffset;
        w -= std::floor(w);
        LightSample s;
        if (est.sampleEmissiveTriangles(x, u, v, w, s, count) && !est.skipsAtReceiver(s))
            add(s.direction, Rgbd(s.weight * misWeight(s.pdf, kSpherePdf)) / double(rays));
    }
    std::vector<LightSample> punctual;
    est.punctualLights(x, punctual, count);
    for (const LightSample& s : punctual)
        if (!est.skipsAtReceiver(s)) add(s.direction, Rgbd(s.weight));
    return a;
}

struct Floor {
    std::vector<double> sh, iv, e;  ///< luminance at each point's normal
    /// The same six vectors read with the paper's n^2 blend (the lookup before issue 15 item 5)
    /// and with the quadratic blend unclamped (`iv` is the library's default, bounded blend).
    std::vector<double> ivPaper, ivQuadratic;
};

Floor floorAt(const Scene& s, const Tracer& tracer, const Points& p, uint32_t rays, int refBounces) {
    TransportOptions t;
    t.maxBounces = refBounces;
    const RadianceEstimator est(s, tracer, t);
    const std::vector<double> zeros(p.x.size());
    Floor f{zeros, zeros, zeros, zeros, zeros};
    tbb::parallel_for(std::size_t(0), p.x.size(), [&](std::size_t i) {
        const AtPoint a = projectAtPoint(est, p.x[i], normalize(p.n[i]), rays, hashCombine(777, i));
        Rgb c[sh::kCoeffs];
        for (int j = 0; j < sh::kCoeffs; ++j) c[j] = Rgb(a.sh[j]);
        f.sh[i] = luminance(sh::irradiance(c, normalize(p.n[i])));
        float v[iv::kFloatsPerNode];
        for (int k = 0; k < iv::kFloatsPerNode; ++k) v[k] = float(a.iv[k]);
        const Vec3f n = normalize(p.n[i]);
        f.iv[i] = luminance(iv::irradiance(v, n));
        f.ivPaper[i] = luminance(iv::irradiance(v, n, iv::Blend::Paper));
        f.ivQuadratic[i] = luminance(iv::irradiance(v, n, iv::Blend::Quadratic));
        f.e[i] = luminance(Rgb(a.e));
    });
    return f;
}

/// An irradiance-vector volume on the uniform grid of `resolution` whose nodes hold the six
/// vectors projected at the node itself (projectAtPoint, `rays` rays, `bounces`), not the photon
/// pass's face-averaged flux: it separates what trilinear interpolation of the six vectors
/// costs from what the photon estimator adds (issue 15, item 5).
Volume ivPointVolume(const Scene& s, const Tracer& tracer, int resolution, uint32_t rays, int bounces) {
    TransportOptions t;
    t.maxBounces = bounces;
    const RadianceEstimator est(s, tracer, t);
    Volume v;
    v.basis = iv::basis();
    v.levels.resize(1);
    VolumeLevel& level = v.levels[0];
    level.grid = gridFor(s, resolution);
    level.data.assign(level.grid.nodeCount() * iv::kFloatsPerNode, 0.0f);
    tbb::parallel_for(std::size_t(0), level.grid.nodeCount(), [&](std::size_t n) {
        const AtPoint a = projectAtPoint(est, Vec3f(level.grid.node(n)), {0, 1, 0}, rays, hashCombine(991, n));
        for (int k = 0; k < iv::kFloatsPerNode; ++k) level.data[n * iv::kFloatsPerNode + k] = float(a.iv[k]);
    });
    return v;
}

/// RMS with the Monte Carlo noise extrapolated out of two estimates at N/4 and N samples
/// (squared noise falls as 1/N): sqrt((4 e_N^2 - e_{N/4}^2) / 3), 0 if negative.
double noiseFree(double eQuarter, double eFull) { return std::sqrt(std::max(0.0, (4 * eFull * eFull - eQuarter * eQuarter) / 3)); }

// ---------------------------------------------------------------------------------------

struct Row {
    Row(std::string s, std::string c, Errors err = {}) : scene(std::move(s)), config(std::move(c)), e(err) {}
    std::string scene, config;
    Errors e;
    double seconds = 0, cpu = 0, bytesPerNode = 0, noise = -1;
    uint64_t nodes = 0;
    std::string note;
};

void printRow(const Row& r) {
    char noise[32] = "";
    if (r.noise >= 0) std::snprintf(noise, sizeof noise, "%6.1f %%", 100 * r.noise);
    std::printf("  %-18s %7.1f %% %7.1f %% %8.1f %% %+7.1f %% %8.2f s %7.2f s %8llu %7.0f B %8s  %s\n", r.config.c_str(),
                100 * r.e.rms, 100 * r.e.p95, 100 * r.e.max, 100 * r.e.bias, r.seconds, r.cpu, (unsigned long long)r.nodes,
                r.bytesPerNode, noise, r.note.c_str());
}

void writeCsvRow(FILE* csv, const Row& r) {
    if (!csv) return;
    std::fprintf(csv, "%s,%s,%.5f,%.5f,%.5f,%.5f,%.3f,%.3f,%llu,%.1f,%s,%s\n", r.scene.c_str(), r.config.c_str(), r.e.rms,
                 r.e.p95, r.e.max, r.e.bias, r.seconds, r.cpu, (unsigned long long)r.nodes, r.bytesPerNode,
                 r.noise >= 0 ? std::to_string(r.noise).c_str() : "", r.note.c_str());
    std::fflush(csv);
}

/// The `count` points with the largest |error| (--worst N: where a method fails).
void printWorst(const std::vector<double>& rel, const std::vector<double>& got, const Truth& t, const Points& p, int count) {
    std::vector<std::size_t> order(rel.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(rel[a]) > std::abs(rel[b]); });
    for (int k = 0; k < count && k < int(order.size()); ++k) {
        const std::size_t i = order[std::size_t(k)];
        std::printf("    worst %d: x (%.3f, %.3f, %.3f) n (%.2f, %.2f, %.2f): E %.4g, E_ref %.4g +- %.2g, error %+.1f %%\n", k,
                    p.x[i].x, p.x[i].y, p.x[i].z, p.n[i].x, p.n[i].y, p.n[i].z, got[i], t.e[i], t.se[i], 100 * rel[i]);
    }
}

/// CPU seconds of this process (all threads): on a shared machine wall time includes waiting
/// for a core, CPU time does not.
double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

fs::path defaultCache(const char* argv0) {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) exe = fs::absolute(argv0);
    return exe.parent_path().parent_path() / "accuracy_cache";  // build/bin/.. = the build directory
}

// ---------------------------------------------------------------------------------------
// --study: where the default bake's error comes from, per scene and region (issue 15).
//
// floor   the default's representation at each point itself: the SH2 of the light the default
//         bake keeps in SH (its transport, with the chosen lights' direct light left out at the
//         receiver) projected at the point (F/4 and F rays, noise extrapolated out), plus each
//         chosen light's exact irradiance times its visibility from the point (256 samples);
// bakes   the default's grid with {no probe pass, one probe pass} x {R, 4R rays}, looked up
//         {depth-weighted, plain trilinear}; each against the truth and against the floor, with
//         the noise extrapolated out of R and 4R (squared noise ~ 1/N). "interp" = the bake
//         against the floor (what interpolation between nodes adds), "bias" = mean signed error.

struct StudyBake {
    std::string name;
    std::vector<double> lo, hi;  ///< values at the points at R and 4R rays
    double seconds = 0;
};

void printStudy(const char* region, const std::vector<std::size_t>& idx, const Truth& truth, const std::vector<double>& floorQ,
                const std::vector<double>& floorF, const std::vector<double>& cosF, const std::vector<StudyBake>& bakes, FILE* csv,
                const std::string& scene) {
    auto pick = [&](const std::vector<double>& v) {
        std::vector<double> o;
        for (std::size_t i : idx) o.push_back(v[i]);
        return o;
    };
    Truth t;
    t.mean = truth.mean;
    t.guard = truth.guard;
    t.e = pick(truth.e);
    t.se = pick(truth.se);
    const Errors fq = summarise(relative(pick(floorQ), t.e, t)), ff = summarise(relative(pick(floorF), t.e, t));
    // SH2 against the cosine-weighted E of the same samples: the representation alone (the
    // samples' noise is common to both and mostly cancels).
    const Errors rep = summarise(relative(pick(floorF), pick(cosF), t));
    std::printf("    %-10s %3zu points: floor RMS %.1f %% (noise-free %.1f %%), bias %+.1f %%; SH2 vs the same samples' cosine-weighted "
                "E: RMS %.1f %%, bias %+.1f %%\n", region, idx.size(), 100 * ff.rms, 100 * noiseFree(fq.rms, ff.rms), 100 * ff.bias,
                100 * rep.rms, 100 * rep.bias);
    Row fr{scene + (region[0] ? std::string(":") + region : ""), "study_floor", ff};
    fr.note = "noise-free " + std::to_string(noiseFree(fq.rms, ff.rms));
    writeCsvRow(csv, fr);
    for (const StudyBake& b : bakes) {
        const Errors lo = summarise(relative(pick(b.lo), t.e, t)), hi = summarise(relative(pick(b.hi), t.e, t));
        // Bake at R against the floor at F/4, at 4R against the floor at F: both noises fall 4x in squares.
        const Errors ilo = summarise(relative(pick(b.lo), pick(floorQ), t)), ihi = summarise(relative(pick(b.hi), pick(floorF), t));
        const double nf = noiseFree(lo.rms, hi.rms), inf = noiseFree(ilo.rms, ihi.rms);
        const double noiseR = std::sqrt(std::max(0.0, (lo.rms * lo.rms - nf * nf)));
        std::printf("      %-24s truth: R %5.1f %% (%+.1f), 4R %5.1f %% (%+.1f), noise-free %5.1f %% (noise at R %4.1f %%); "
                    "vs floor: 4R %5.1f %% (%+.1f), noise-free %5.1f %%\n",
                    b.name.c_str(), 100 * lo.rms, 100 * lo.bias, 100 * hi.rms, 100 * hi.bias, 100 * nf, 100 * noiseR,
                    100 * ihi.rms, 100 * ihi.bias, 100 * inf);
        Row r{fr.scene, "study_" + b.name, hi};
        r.seconds = b.seconds;
        r.note = "noise-free " + std::to_string(nf) + " interp-noise-free " + std::to_string(inf);
        writeCsvRow(csv, r);
    }
}

void studyDefault(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth, const Settings& st,
                  uint32_t rays, uint32_t floorRays, FILE* csv) {
    const Scene& s = as.scene;
    const double t0 = bench::now();
    // The default's plan and transport.
    const GridSpec grid = tryGrid(s, parseTry("nodes=16384"), st);
    DirectOptions d;
    d.mode = sceneLights(s).empty() ? DirectMode::Baked : DirectMode::Occlusion;
    d.threads = st.threads;
    const DirectPlan plan = planDirectLight(s, tracer, grid, d);
    TransportOptions tr;
    tr.skipAtReceiver = plan.filter;
    const RadianceEstimator est(s, tracer, tr);
    const std::size_t np = pts.x.size();
    std::vector<double> floorQ(np), floorF(np), cosF(np);
    tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) {
        const Vec3f n = normalize(pts.n[i]);
        Rgb direct(0, 0, 0);
        if (d.mode == DirectMode::Occlusion)
            for (std::size_t l = 0; l < plan.lights.size(); ++l) {
                RayCount rc;
                const double vis = lightVisibility(s, tracer, plan.lights[l], pts.x[i], 256, hashCombine(4242, i * 31 + l), rc);
                direct += exactIrradiance(plan.lights[l].light, Vec3d(pts.x[i]), Vec3d(n)) * float(vis);
            }
        for (int pass = 0; pass < 2; ++pass) {
            const uint32_t r = pass ? floorRays : floorRays / 4;
            const AtPoint a = projectAtPoint(est, pts.x[i], n, r, hashCombine(777 + pass, i));
            Rgb c[sh::kCoeffs];
            for (int j = 0; j < sh::kCoeffs; ++j) c[j] = Rgb(a.sh[j]);
            (pass ? floorF : floorQ)[i] = luminance(sh::irradiance(c, n) + direct);
            if (pass) cosF[i] = luminance(Rgb(a.e) + direct);
        }
    });
    std::printf("  study of the default (grid %d x %d x %d, spacing %.3f; %zu chosen lights; floor %.1f s)\n", grid.nx, grid.ny,
                grid.nz, grid.spacing, plan.lights.size(), bench::now() - t0);
    std::vector<StudyBake> bakes;
    Settings full = st;  // the study takes R as given (tryBake's rays scale with --quick)
    full.quick = false;
    for (const int passes : {0, 1}) {
        const std::string kind = passes ? "probe" : "plain";
        StudyBake on, off;
        on.name = kind + " depth";
        off.name = kind + " no-depth";
        for (const uint32_t r : {rays, 4 * rays}) {
            TrySpec ts = parseTry("nodes=16384,depth=1");
            ts.rays = r;
            ts.passes = passes;
            const double t1 = bench::now();
            std::string note;
            const Volume v = tryVolume(Ctx{s, tracer, full, 1}, ts, note);
            on.seconds = off.seconds = bench::now() - t1;
            const IrradianceQuery qOn(v), qOff(v, OutsidePolicy::Clamp, false);
            (r == rays ? on.lo : on.hi) = values([&](const Vec3f& x, const Vec3f& n) { return qOn.irradiance(x, n); }, pts);
            (r == rays ? off.lo : off.hi) = values([&](const Vec3f& x, const Vec3f& n) { return qOff.irradiance(x, n); }, pts);
            {
                const std::vector<double>& a = r == rays ? on.lo : on.hi;
                const std::vector<double>& b = r == rays ? off.lo : off.hi;
                double dmax = 0;
                for (std::size_t i = 0; i < a.size(); ++i) dmax = std::max(dmax, std::abs(a[i] - b[i]));
                std::printf("    (%s %u rays: %.1f s, depth grids %zu, weighted %d/%d, largest on-off difference %.3g)\n", kind.c_str(), r,
                            on.seconds, v.levels[0].depth.size(), int(qOn.depthWeighted()), int(qOff.depthWeighted()), dmax);
            }
        }
        bakes.push_back(on);
        bakes.push_back(off);
    }
    std::vector<std::size_t> all(np);
    for (std::size_t i = 0; i < np; ++i) all[i] = i;
    printStudy("all", all, truth, floorQ, floorF, cosF, bakes, csv, as.name);
    for (const bench::AccuracyRegion& region : as.regions) {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < np; ++i)
            if (region.contains(pts.x[i])) idx.push_back(i);
        if (!idx.empty()) printStudy(region.name.c_str(), idx, truth, floorQ, floorF, cosF, bakes, csv, as.name);
    }
}

// ---------------------------------------------------------------------------------------
// --time-to E: time to accuracy (issue 15 item 2's target: in two_rooms, reach 9 % RMS at least
// 5x faster than plain gathering, which took 8192 rays per node at 32 nodes, 21 s). Each ladder
// doubles the rays per node on one grid until the RMS is at most E; the time to E of a ladder
// is the bake time of its first step that reaches it (wall and CPU / threads; the machine may be
// shared, so CPU / threads is the better estimate of two free cores).

struct Rung {
    uint32_t rays = 0;
    Errors e;
    double wall = 0, cpu = 0;
};

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

// ---------------------------------------------------------------------------------------
// --probe-study R0: where the probe pass's bias comes from (issue 15). The probe pass ends a
// node's paths at their first hit p with a surface cache: the irradiance of pass 0's reflected
// light at p. Here the probe estimator runs at each point itself (K cosine-sampled directions,
// no SH at the point, no interpolation of the result) with the cache replaced in turn by:
//   library   the library's cache (bake/surface_cache.h) of pass 0 at R0 rays per node;
//   nodes     the same nodes, weights and visibility tests, each node's stored light replaced by
//             its exact reflected irradiance for the normal (M cosine-sampled paths from the node);
//   exact     the exact reflected irradiance at p itself (M paths from p): an unbiased cache,
//             so this is path tracing and checks the estimator's own bookkeeping;
// and without a cache (plain paths). library - nodes = how the cache represents a node's light
// (SH order 2 before issue 15's fourth session); nodes - exact = the nodes standing for p
// (their positions, weights); exact - truth = the rest.

enum class CacheKind { NodesExact, Exact };

/// The exact variants of the library's cache (above), with its lookup's node weights and tests.
class StudyCache : public SurfaceIrradianceCache {
public:
    StudyCache(const Tracer& tracer, const RadianceEstimator& plain, const GridSpec& grid, CacheKind kind, int paths)
        : tracer_(tracer), plain_(plain), grid_(grid), kind_(kind), paths_(paths) {}

    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override {
        Rng rng(hashOf(p, n), 9);
        if (kind_ == CacheKind::Exact) {
            out = exactReflected(p, n, rng, rays);
            return true;
        }
        Rgb sum{0, 0, 0};
        const float weight = bake_detail::forEachVisibleNode(tracer_, grid_, p, n, rays, [&](std::size_t, const Vec3f& node, float w) {
            sum += exactReflected(node, n, rng, rays) * w;
        });
        if (!(weight > 0)) return false;
        out = sum / weight;
        out = Rgb(std::max(0.0f, out.x), std::max(0.0f, out.y), std::max(0.0f, out.z));
        return true;
    }

private:
    static uint64_t hashOf(const Vec3f& p, const Vec3f& n) {
        uint64_t h = 0x9b;
        for (int k = 0; k < 3; ++k) {
            uint32_t a, b;
            const float pk = p[k], nk = n[k];
            std::memcpy(&a, &pk, 4);
            std::memcpy(&b, &nk, 4);
            h = hashCombine(hashCombine(h, a), b);
        }
        return h;
    }
    /// Irradiance of reflected light and sky at q for normal n (emission seen directly left
    /// out): `paths_` cosine-sampled full paths.
    Rgb exactReflected(const Vec3f& q, const Vec3f& n, Rng& rng, RayCount& rays) const {
        Vec3f t, b;
        orthonormalBasis(n, t, b);
        Rgb sum{0, 0, 0};
        for (int i = 0; i < paths_; ++i) {
            const Vec3f l = cosineHemisphere(rng.uniform(), rng.uniform());
            const Vec3f dir = t * l.x + b * l.y + n * l.z;
            Rgb emitted;
            const Rgb r = plain_.gatherRadiance(q, dir, l.z * float(kInvPi), rng, rays, nullptr, &emitted);
            sum += r - emitted;
        }
        return sum * float(kPi / paths_);
    }
    const Tracer& tracer_;
    const RadianceEstimator& plain_;
    GridSpec grid_;
    CacheKind kind_;
    int paths_;
};

void probeCacheStudy(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
                     const Settings& st, uint32_t passZeroRays, uint32_t pointRays, int paths) {
    const Scene& s = as.scene;
    const double t0 = bench::now();
    const GridSpec grid = tryGrid(s, parseTry("nodes=16384"), st);
    DirectOptions d;
    d.mode = sceneLights(s).empty() ? DirectMode::Baked : DirectMode::Occlusion;
    d.threads = st.threads;
    const DirectPlan plan = planDirectLight(s, tracer, grid, d);
    TransportOptions tr;
    tr.skipAtReceiver = plan.filter;
    // Pass 0 of the default's probe pass: stage 0 of a staged bake holds its reflected SH.
    GatherOptions g;
    g.raysPerNode = passZeroRays;
    g.seed = 1;
    g.threads = st.threads;
    g.transport = tr;
    g.probePasses = 1;
    g.stage = 0;
    const Volume stage0 = bakeShGather(s, tracer, grid, g);
    std::printf("  probe cache study (grid %d x %d x %d, spacing %.3f; pass 0 at %u rays: %.1f s; %u cosine samples per point, "
                "%d paths per exact value)\n", grid.nx, grid.ny, grid.nz, grid.spacing, passZeroRays, bench::now() - t0, pointRays,
                paths);
    const RadianceEstimator plain(s, tracer, tr);
    const std::size_t np = pts.x.size();
    std::vector<double> direct(np);
    tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) {
        const Vec3f n = normalize(pts.n[i]);
        Rgb e(0, 0, 0);
        if (d.mode == DirectMode::Occlusion)
            for (std::size_t l = 0; l < plan.lights.size(); ++l) {
                RayCount rc;
                const double vis = lightVisibility(s, tracer, plan.lights[l], pts.x[i], 256, hashCombine(4242, i * 31 + l), rc);
                e += exactIrradiance(plan.lights[l].light, Vec3d(pts.x[i]), Vec3d(n)) * float(vis);
            }
        direct[i] = luminance(e);
    });
    struct Variant {
        const char* name;
        std::unique_ptr<SurfaceIrradianceCache> cache;
        std::vector<double> e;
        double seconds = 0;
    };
    std::vector<Variant> vars;
    vars.push_back({"plain (no cache)", nullptr, {}});
    vars.push_back({"cache: library", std::make_unique<bake_detail::VolumeSurfaceCache>(tracer, grid, stage0.levels[0].data.data()), {}});
    vars.push_back({"cache: nodes, exact E", std::make_unique<StudyCache>(tracer, plain, grid, CacheKind::NodesExact, paths), {}});
    vars.push_back({"cache: exact E at p", std::make_unique<StudyCache>(tracer, plain, grid, CacheKind::Exact, paths), {}});
    for (Variant& v : vars) {
        RadianceEstimator est(s, tracer, tr);
        est.setSurfaceCache(v.cache.get());
        v.e.assign(np, 0.0);
        const double t1 = bench::now();
        tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) {
            const Vec3f n = normalize(pts.n[i]), x = pts.x[i];
            Vec3f tb, bb;
            orthonormalBasis(n, tb, bb);
            const uint64_t stream = hashCombine(31337, i);
            Rng rng(stream, 4);
            RayCount rc;
            Rgb sum{0, 0, 0};
            for (uint32_t k = 0; k < pointRays; ++k) {
                float u, w;
                sobol02(k, hashCombine(stream, 1), u, w);
                const Vec3f l = cosineHemisphere(u, w);
                const Vec3f dir = tb * l.x + bb * l.y + n * l.z;
                sum += est.gatherRadiance(x, dir, l.z * float(kInvPi), rng, rc) * float(kPi);
                if (!est.hasEmissiveTriangles()) continue;
                sobol02(k, hashCombine(stream, 2), u, w);
                LightSample ls;
                if (est.sampleEmissiveTriangles(x, u, w, rng.uniform(), ls, rc, &n) && !est.skipsAtReceiver(ls)) {
                    const float c = std::max(0.0f, dot(n, ls.direction));
                    sum += ls.weight * (c * misWeight(ls.pdf, c * float(kInvPi)));
                }
            }
            std::vector<LightSample> punctual;
            est.punctualLights(x, punctual, rc);
            Rgb p{0, 0, 0};
            for (const LightSample& ls : punctual)
                if (!est.skipsAtReceiver(ls)) p += ls.weight * std::max(0.0f, dot(n, ls.direction));
            v.e[i] = luminance(sum / float(pointRays) + p) + direct[i];
        });
        v.seconds = bench::now() - t1;
    }
    auto report = [&](const char* region, const std::vector<std::size_t>& idx) {
        std::printf("    %-10s %3zu points (bias +- its standard error over the points; RMS):\n", region, idx.size());
        for (const Variant& v : vars) {
            double m = 0, m2 = 0;
            for (std::size_t i : idx) {
                const double r = (v.e[i] - truth.e[i]) / truth.denominator(i);
                m += r, m2 += r * r;
            }
            const double n = double(idx.size()), mean = m / n, rms = std::sqrt(m2 / n);
            const double se = std::sqrt(std::max(0.0, m2 / n - mean * mean) / std::max(1.0, n - 1));
            std::printf("      %-28s vs truth: bias %+6.2f %% +- %4.2f %%, RMS %5.1f %%  (%.1f s)\n", v.name, 100 * mean, 100 * se,
                        100 * rms, v.seconds);
        }
        // Paired differences (common direction samples): sh - nodes, nodes - exact.
        for (const auto& [a, b] : {std::pair{1, 2}, std::pair{2, 3}, std::pair{1, 3}}) {
            double m = 0, m2 = 0;
            for (std::size_t i : idx) {
                const double r = (vars[std::size_t(a)].e[i] - vars[std::size_t(b)].e[i]) / truth.denominator(i);
                m += r, m2 += r * r;
            }
            const double n = double(idx.size()), mean = m / n;
            const double se = std::sqrt(std::max(0.0, m2 / n - mean * mean) / std::max(1.0, n - 1));
            std::printf("      [%s] - [%s]: %+6.2f %% +- %4.2f %%\n", vars[std::size_t(a)].name, vars[std::size_t(b)].name, 100 * mean,
                        100 * se);
        }
    };
    std::vector<std::size_t> all(np);
    for (std::size_t i = 0; i < np; ++i) all[i] = i;
    report("all", all);
    for (const bench::AccuracyRegion& region : as.regions) {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < np; ++i)
            if (region.contains(pts.x[i])) idx.push_back(i);
        if (!idx.empty()) report(region.name.c_str(), idx);
    }
}

}  // namespace

int main(int argc, char** argv) {
    bench::BenchArgs args("vdblight_bench_accuracy", {{"--csv", "FILE"},
                                                      {"--scene", "NAME"},
                                                      {"--config", "NAME"},
                                                      {"--threads", "N"},
                                                      {"--points", "N"},
                                                      {"--ref-samples", "N"},
                                                      {"--cache", "DIR"},
                                                      {"--worst", "N"},
                                                      {"--guard", "F"},
                                                      {"--try", "SPECS"},
                                                      {"--no-decompose", ""},
                                                      {"--study", "R"},
                                                      {"--study-floor", "F"},
                                                      {"--time-to", "E"},
                                                      {"--probe-study", "R0"},
                                                      {"--probe-rays", "K"},
                                                      {"--probe-paths", "M"}});
    if (!args.parse(argc, argv)) return 1;
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress visible when redirected to a file
    Settings st;
    st.quick = args.quick();
    st.threads = args.integer("--threads", 2);
    st.points = args.integer("--points", st.quick ? 60 : 200);
    st.refSamples = uint32_t(args.integer("--ref-samples", st.quick ? 2048 : 65536));
    st.floorRays = st.quick ? 512 : 8192;
    st.spatialRays = st.quick ? 128 : 1024;
    st.spatialPhotons = st.quick ? 1'000'000 : 4'000'000;
    st.cache = args.given("--cache") ? fs::path(args.text("--cache")) : defaultCache(argv[0]);
    const std::string onlyScene = args.text("--scene"), onlyConfig = args.text("--config");
    const bool decompose = !args.given("--no-decompose");
    FILE* csv = nullptr;
    if (args.given("--csv") && !(csv = std::fopen(args.text("--csv").c_str(), "w"))) {
        std::fprintf(stderr, "vdblight_bench_accuracy: cannot write %s\n", args.text("--csv").c_str());
        return 1;
    }
    if (csv) std::fprintf(csv, "scene,config,rms,p95,max,bias,bake_seconds,cpu_seconds,nodes,bytes_per_node,noise_rms,note\n");
    // Reference, floor and spatial runs use this many threads too (the bakes take --threads).
    tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(std::max(1, st.threads)));

    std::vector<Config> configs = configurations();
    // --try SPEC (repeatable as SPEC;SPEC): candidate defaults, named try_<spec>, measured with noise.
    if (args.given("--try")) {
        const std::string all = args.text("--try");
        std::size_t pos = 0;
        while (pos <= all.size()) {
            std::size_t end = all.find(';', pos);
            if (end == std::string::npos) end = all.size();
            const std::string spec = all.substr(pos, end - pos);
            pos = end + 1;
            if (spec.empty()) continue;
            const TrySpec t = parseTry(spec);
            std::string name = "try:" + spec;  // no commas in the CSV's config column
            std::replace(name.begin(), name.end(), ',', '/');
            configs.push_back({name, "--try " + spec, [t](const Ctx& c) { return tryBake(c, t); }, true});
        }
    }
    std::printf("vdblight_bench_accuracy%s: %d points per scene, ground truth %u samples x %d bounces, %d threads\n",
                st.quick ? " --quick (small workloads)" : "", st.points, st.refSamples, st.refBounces, st.threads);
    std::vector<Row> summary;
    for (bench::AccuracyScene& as : bench::accuracyScenes()) {
        if (!onlyScene.empty() && as.name != onlyScene) continue;
        const Scene& s = as.scene;
        const Tracer tracer(s);
        const Points pts = freeSpacePoints(s, tracer, st.points);
        std::printf("\n%s: %zu triangles, box %.2f x %.2f x %.2f, %zu free-space points\n", as.name.c_str(),
                    s.triangleCount(), s.bounds().size().x, s.bounds().size().y, s.bounds().size().z, pts.x.size());
        Truth truth = groundTruth(s, tracer, pts, st, st.refSamples * uint32_t(as.referenceScale));
        truth.guard = args.real("--guard", truth.guard);
        {
            std::vector<double> rse(truth.e.size());
            for (std::size_t i = 0; i < rse.size(); ++i) rse[i] = truth.se[i] / truth.denominator(i);
            const Errors e = summarise(rse);
            std::printf("  ground truth relative standard error: RMS %.2f %%, p95 %.2f %%, max %.2f %% (mean E %.4g)\n",
                        100 * e.rms, 100 * e.p95, 100 * e.max, truth.mean);
            Row r{as.name, "reference_se", e};
            writeCsvRow(csv, r);
        }
        std::printf("  %-18s %9s %9s %10s %9s %10s %9s %8s %9s %8s\n", "config", "RMS", "p95", "max", "bias", "bake", "CPU",
                    "nodes", "B/node", "noise");
        for (const Config& c : configs) {
            if (!onlyConfig.empty() && c.name.rfind(onlyConfig, 0) != 0) continue;  // a prefix: --config direct_
            Row r{as.name, c.name};
            std::vector<double> rel, noiseRel;  // per point: error, and (E1 - E2) / sqrt 2 / E_ref
            try {
                const double cpu0 = cpuSeconds();
                const Baked b = c.bake(Ctx{s, tracer, st, 1});
                r.cpu = cpuSeconds() - cpu0;
                const std::vector<double> got = values(b.irradiance, pts);
                rel = relative(got, truth.e, truth);
                r.e = summarise(rel);
                printWorst(rel, got, truth, pts, args.integer("--worst", 0));
                r.seconds = b.seconds;
                r.nodes = b.nodes;
                r.bytesPerNode = b.nodes ? double(b.bytes) / double(b.nodes) : 0;
                r.note = b.note;
                if (c.noise) {
                    const Baked b2 = c.bake(Ctx{s, tracer, st, 2});
                    const std::vector<double> got2 = values(b2.irradiance, pts);
                    double s2 = 0;
                    for (std::size_t i = 0; i < got.size(); ++i) {
                        const double d = (got[i] - got2[i]) / std::sqrt(2.0) / truth.denominator(i);
                        noiseRel.push_back(d);
                        s2 += d * d;
                    }
                    r.noise = std::sqrt(s2 / double(got.size()));
                }
            } catch (const Error& e) {
                std::printf("  %-18s failed: %s\n", c.name.c_str(), e.what());
                continue;
            }
            printRow(r);
            writeCsvRow(csv, r);
            summary.push_back(r);
            for (const bench::AccuracyRegion& region : as.regions) {
                std::vector<double> part;
                double n2 = 0;
                for (std::size_t i = 0; i < pts.x.size(); ++i)
                    if (region.contains(pts.x[i])) {
                        part.push_back(rel[i]);
                        if (!noiseRel.empty()) n2 += noiseRel[i] * noiseRel[i];
                    }
                if (part.empty()) continue;
                Row rr{as.name + ":" + region.name, c.name, summarise(part)};
                rr.note = std::to_string(part.size()) + " points";
                if (!noiseRel.empty()) rr.noise = std::sqrt(n2 / double(part.size()));
                char noise[32] = "";
                if (rr.noise >= 0) std::snprintf(noise, sizeof noise, ", noise %.1f %%", 100 * rr.noise);
                std::printf("    %-16s %7.1f %% %7.1f %% %8.1f %% %+7.1f %%  (%zu points%s)\n", region.name.c_str(), 100 * rr.e.rms,
                            100 * rr.e.p95, 100 * rr.e.max, 100 * rr.e.bias, part.size(), noise);
                writeCsvRow(csv, rr);
            }
        }
        if (args.given("--time-to")) timeToAccuracy(as, tracer, pts, truth, st, args.real("--time-to", 0.09), csv);
        if (args.given("--study")) studyDefault(as, tracer, pts, truth, st, uint32_t(args.integer("--study", 512)),
                                                  uint32_t(args.integer("--study-floor", 32768)), csv);
        if (args.given("--probe-study"))
            probeCacheStudy(as, tracer, pts, truth, st, uint32_t(args.integer("--probe-study", 2048)),
                            uint32_t(args.integer("--probe-rays", 2048)), args.integer("--probe-paths", 4));
        if (!decompose) continue;

        // The decomposition.
        const double t0 = bench::now();
        const Floor quarter = floorAt(s, tracer, pts, st.floorRays / 4, st.refBounces);
        const Floor full = floorAt(s, tracer, pts, st.floorRays, st.refBounces);
        const Errors shQ = summarise(relative(quarter.sh, truth.e, truth)), shF = summarise(relative(full.sh, truth.e, truth));
        const Errors ivQ = summarise(relative(quarter.iv, truth.e, truth)), ivF = summarise(relative(full.iv, truth.e, truth));
        const Errors eF = summarise(relative(full.e, truth.e, truth));
        const Errors ivP = summarise(relative(full.ivPaper, truth.e, truth));
        const Errors ivQd = summarise(relative(full.ivQuadratic, truth.e, truth));
        std::printf("  decomposition (floor: a node at each point, %u rays; noise-free: extrapolated from %u and %u rays; %.1f s)\n",
                    st.floorRays, st.floorRays / 4, st.floorRays, bench::now() - t0);
        std::printf("    cosine-weighted E at the point from the same samples (no representation): RMS %.1f %%, bias %+.1f %%\n",
                    100 * eF.rms, 100 * eF.bias);
        std::printf("    SH order-2 floor:          RMS %.1f %% (noise-free %.1f %%), p95 %.1f %%, max %.1f %%, bias %+.1f %%\n",
                    100 * shF.rms, 100 * noiseFree(shQ.rms, shF.rms), 100 * shF.p95, 100 * shF.max, 100 * shF.bias);
        std::printf("    irradiance-vector floor:   RMS %.1f %% (noise-free %.1f %%), p95 %.1f %%, max %.1f %%, bias %+.1f %%\n",
                    100 * ivF.rms, 100 * noiseFree(ivQ.rms, ivF.rms), 100 * ivF.p95, 100 * ivF.max, 100 * ivF.bias);
        std::printf("    irradiance vectors, the paper's n^2 blend (before issue 15 item 5): RMS %.1f %%, p95 %.1f %%, "
                    "bias %+.1f %%\n", 100 * ivP.rms, 100 * ivP.p95, 100 * ivP.bias);
        writeCsvRow(csv, Row{as.name, "floor_iv_paper_blend", ivP});
        std::printf("    irradiance vectors, the quadratic blend unclamped: RMS %.1f %%, p95 %.1f %%, bias %+.1f %%\n",
                    100 * ivQd.rms, 100 * ivQd.p95, 100 * ivQd.bias);
        writeCsvRow(csv, Row{as.name, "floor_iv_quadratic_blend", ivQd});
        Row fr{as.name, "floor_sh2", shF};
        fr.note = "noise-free " + std::to_string(noiseFree(shQ.rms, shF.rms));
        writeCsvRow(csv, fr);
        Row fi{as.name, "floor_iv", ivF};
        fi.note = "noise-free " + std::to_string(noiseFree(ivQ.rms, ivF.rms));
        writeCsvRow(csv, fi);
        Row fe{as.name, "floor_exact_at_point", eF};
        writeCsvRow(csv, fe);

        // Spatial: bakes at the default resolution with the ground truth's bounces against the
        // floors at the points, at N/4 and N rays (photons) with the noise extrapolated out.
        const Ctx ctx{s, tracer, st, 1};
        auto spatial = [&](const std::function<Baked(uint64_t)>& bake, uint64_t budget, const std::vector<double>& floorValues,
                           const char* label) {
            const Baked lo = bake(budget / 4), hi = bake(budget);
            const std::vector<double> loGot = values(lo.irradiance, pts), hiGot = values(hi.irradiance, pts);
            const Errors loE = summarise(relative(loGot, floorValues, truth)), hiE = summarise(relative(hiGot, floorValues, truth));
            const Errors total = summarise(relative(hiGot, truth.e, truth));
            std::printf("    spatial, %s (%llu and %llu, %.1f s): against the floor RMS %.1f %% (noise-free %.1f %%), bias %+.1f %%; "
                        "against the truth RMS %.1f %%, bias %+.1f %%\n",
                        label, (unsigned long long)(budget / 4), (unsigned long long)budget, hi.seconds, 100 * hiE.rms,
                        100 * noiseFree(loE.rms, hiE.rms), 100 * hiE.bias, 100 * total.rms, 100 * total.bias);
            Row r{as.name, std::string("spatial_") + label, hiE};
            r.seconds = hi.seconds;
            r.note = "noise-free " + std::to_string(noiseFree(loE.rms, hiE.rms));
            writeCsvRow(csv, r);
        };
        spatial([&](uint64_t rays) { return pointGather(ctx, st.res(16), uint32_t(rays), st.refBounces); }, st.spatialRays,
                full.sh, "sh2");
        spatial([&](uint64_t n) { return photons(ctx, st.res(16), n, st.refBounces); }, st.spatialPhotons, full.iv, "iv");
        // The same six vectors projected at the nodes (no photon estimator): interpolation only,
        // and the photon volume against it: what the face-averaged flux estimator adds.
        {
            const double t1 = bench::now();
            const Baked pointIv = fromVolume(ivPointVolume(s, tracer, st.res(16), st.spatialRays / 4, st.refBounces), 0, 0);
            const std::vector<double> pGot = values(pointIv.irradiance, pts);
            const Errors vsFloor = summarise(relative(pGot, full.iv, truth));
            const Baked ph = photons(ctx, st.res(16), st.spatialPhotons, st.refBounces);
            const Errors phVsPoint = summarise(relative(values(ph.irradiance, pts), pGot, truth));
            std::printf("    irradiance vectors projected at the nodes (%u rays, %.1f s): against the floor RMS %.1f %%, bias %+.1f %%; "
                        "the photon volume against them: RMS %.1f %%, bias %+.1f %%\n",
                        st.spatialRays / 4, bench::now() - t1, 100 * vsFloor.rms, 100 * vsFloor.bias, 100 * phVsPoint.rms,
                        100 * phVsPoint.bias);
            writeCsvRow(csv, Row{as.name, "iv_nodes_vs_floor", vsFloor});
            writeCsvRow(csv, Row{as.name, "photons_vs_iv_nodes", phVsPoint});
        }
    }

    std::printf("\nSummary: RMS relative error (bias) per configuration and scene\n  %-18s", "config");
    std::vector<std::string> scenes;
    for (const Row& r : summary)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    for (const std::string& s : scenes) std::printf(" %20s", s.c_str());
    std::printf("\n");
    for (const Config& c : configs) {
        bool any = false;
        for (const Row& r : summary) any |= r.config == c.name;
        if (!any) continue;
        std::printf("  %-18s", c.name.c_str());
        for (const std::string& s : scenes) {
            const auto it = std::find_if(summary.begin(), summary.end(), [&](const Row& r) { return r.scene == s && r.config == c.name; });
            if (it == summary.end()) std::printf(" %20s", "-");
            else {
                char cell[40];
                std::snprintf(cell, sizeof cell, "%.1f %% (%+.1f %%)", 100 * it->e.rms, 100 * it->e.bias);
                std::printf(" %20s", cell);
            }
        }
        std::printf("\n");
    }
    if (csv) std::fclose(csv);
    return 0;
}
