// vdblight_bench_accuracy: the bakes a configuration runs, each reproducing what a `vdblight
// bake` command does through the library, answering E(x, n) through the run-time lookup.
#include "accuracy.h"

#include "vdblight/basis/basis.h"

#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include <unistd.h>

#include "vdblight/bake/each_pass.h"
#include "bake/bake_antialiased.h"
#include "bake/bake_bins.h"
#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "query/query_direct.h"
#include "vdblight/light/light.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/query/query.h"


namespace vdblight::accuracy {

namespace {
uint64_t bytesOnDisk(const Volume& v) {
    const fs::path tmp = fs::temp_directory_path() / ("vdblight_bench_accuracy_" + std::to_string(::getpid()) + ".vdb");
    writeVolume(v, tmp.string());
    const uint64_t size = fs::file_size(tmp);
    fs::remove(tmp);
    return size;
}
}  // namespace

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
    // The SH part as IrradianceQuery reads it: the first lookup of the registry that accepts
    // the volume (SH order 2's own, or the generic one for sh:N, the default).
    const LookupKind* kind = nullptr;
    for (const LookupKind& k : lookupKinds())
        if (!kind && k.accepts(*volume)) kind = &k;
    if (!kind) throw FormatError("no lookup for volume basis '" + volume->basis.kind + "'");
    auto lookup = std::make_unique<OcclusionLookup>(kind->create(*volume, OutsidePolicy::Clamp), *volume);
    lookup->setVisibilityDepthWeights(false);
    auto query = std::make_shared<IrradianceQuery>(std::move(lookup), kind->name);
    b.irradiance = [volume, query](const Vec3f& x, const Vec3f& n) { return query->irradiance(x, n); };
    return b;
}

/// The uniform grid of `vdblight bake`: `resolution` nodes on the longest axis of the scene box.
GridSpec gridFor(const Scene& s, int resolution) {
    GridPlacement p;
    p.resolution = resolution;
    return placeUniformGrid(s.bounds(), p, 1);
}

namespace {
GatherOptions gatherOptions(const Ctx& c, uint32_t rays) {
    GatherOptions g;
    g.raysPerNode = rays;
    g.seed = c.seed;
    g.threads = c.settings.threads;
    return g;
}
}  // namespace

/// `bounces` > 0 overrides the transport's bounce cap (the decomposition's bakes match the
/// ground truth's, so that they measure representation and interpolation only).
/// `depth`: also depth moments from the gather's own rays, and lookups weighted by them
/// (visibility-aware interpolation, depth_moments.h).
Baked pointGather(const Ctx& c, int resolution, uint32_t rays, int bounces, bool depth) {
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

Baked adaptiveLayout(const Ctx& c, int resolution, uint32_t rays, int levels, int refine, bool depth) {
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
Baked photons(const Ctx& c, int resolution, uint64_t count, int bounces, iv::Blend blend, uint32_t depthRays) {
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
    if (depthRays > 0) {  // bake --method photons --depth-moments: first-hit rays from the nodes
        DepthOptions d;
        d.raysPerNode = depthRays;
        d.seed = c.seed;
        d.threads = c.settings.threads;
        bakeDepthMoments(c.tracer, v, d);
    }
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

/// What a runtime answer adds to the volume's (indirect) light: every listed light's direct
/// light with shadow rays at each lookup (what `vdblight query --scene` does, 256 rays per
/// polygon light).
void addRuntimeDirect(const Ctx& c, const std::vector<SceneLight>& planned, Baked& b) {
    auto lights = std::make_shared<std::vector<SceneLight>>(planned);
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

/// Point gather with `bake --direct MODE` (bake_direct.h): runtime answers add every light's
/// direct light with shadow rays at each lookup (what `vdblight query --scene` does, 256 rays
/// per polygon light); occlusion volumes answer through IrradianceQuery (exact direct x baked
/// visibility). Occlusion in a scene without lights falls back to baked, as the command does.
Baked directGather(const Ctx& c, int resolution, uint32_t rays, DirectMode mode, int probePasses, bool shadowEdges) {
    DirectOptions d;
    d.mode = mode;
    d.shadowEdges = shadowEdges;
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
    if (d.mode == DirectMode::Runtime) addRuntimeDirect(c, plan.lights, b);
    return b;
}

TrySpec parseTry(const std::string& spec) {
    std::vector<std::pair<std::string, std::string>> keys;
    for (std::size_t pos = 0; pos < spec.size();) {
        std::size_t end = spec.find(',', pos);
        if (end == std::string::npos) end = spec.size();
        const std::string kv = spec.substr(pos, end - pos);
        pos = end + 1;
        const std::size_t eq = kv.find('=');
        if (eq == std::string::npos) throw ValueError("--try: expected key=value, got '" + kv + "'");
        keys.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
    }
    TrySpec t;
    // preset=NAME starts from that quality's spec wherever it is written, so that the other
    // keys change it: `preset=default,byerror=1` is one lever measured on the default.
    for (const auto& [k, v] : keys)
        if (k == "preset") t = presetTry(v);
    for (const auto& [k, v] : keys) {
        if (k == "preset") continue;  // applied first, above
        else if (k == "res") t.res = std::stoi(v);
        else if (k == "nodes") t.nodes = std::stoull(v);
        else if (k == "rays") t.rays = uint32_t(std::stoul(v));
        else if (k == "min") t.minRays = uint32_t(std::stoul(v));
        else if (k == "max") t.maxRays = uint32_t(std::stoul(v));
        else if (k == "target") t.target = std::stod(v);
        else if (k == "passes") t.passes = std::stoi(v);
        else if (k == "depth") t.depth = v == "1";
        else if (k == "direct") t.direct = parseDirectMode(v);
        else if (k == "basis") t.basis = v;
        else if (k == "cache") t.surfaceCache = v == "surface";
        else if (k == "filter") t.filter = std::stoi(v);
        else if (k == "bilateral") t.filterByNoise = v == "1";
        else if (k == "edges") t.shadowEdges = v == "1";
        else if (k == "guide") t.guide = v == "1";
        else if (k == "blend") t.blend = v == "1";
        else if (k == "extra") t.extraPaths = v == "1";
        else if (k == "extrapaths") t.extraPathsPerNode = uint32_t(std::stoul(v));
        else if (k == "split") t.splitLights = std::stoi(v);
        else if (k == "byerror") t.byError = v == "1";
        else if (k == "probebyerror") t.probeByError = v == "1";
        else if (k == "lightsamples") t.lightSamples = std::stoi(v);
        else throw ValueError("--try: unknown key '" + k + "'");
    }
    return t;
}

TrySpec defaultTry() { return presetTry("default"); }

TrySpec presetTry(const std::string& quality) {
    BakeRequest given;
    given.quality = quality;
    const BakeRequest r = resolveBakeRequest(given);
    if (r.pass != "gather" || r.params.has("target-error") || !r.nodes)
        throw ValueError("--quality " + quality + " is no longer a fixed-budget point gather on a node budget: update presetTry");
    TrySpec t;
    t.nodes = *r.nodes;
    t.rays = r.params.get<uint32_t>("rays");
    t.passes = r.params.get<int>("probe-passes");
    t.depth = r.params.get<bool>("depth-moments");
    t.basis = r.basis;
    t.surfaceCache = r.params.get<std::string>("probe-cache") == "surface";
    t.filter = r.params.get<int>("node-filter");
    t.filterByNoise = true;  // what the gather pass asks for (pass_options.cpp)
    t.guide = r.params.get<bool>("guide-probe-directions");
    t.blend = r.params.get<bool>("blend-first-pass");
    t.extraPaths = r.params.get<bool>("extra-cache-paths");
    t.extraPathsPerNode = r.params.get<uint32_t>("extra-cache-paths-per-node");
    t.byError = r.params.get<bool>("first-pass-by-error");
    t.probeByError = r.params.get<bool>("probe-pass-by-error");
    t.lightSamples = int(r.params.get<uint32_t>("probe-light-samples"));
    return t;
}

std::string describeTry(const TrySpec& t) {
    std::string s = t.nodes ? "~" + std::to_string(t.nodes) + " nodes" : std::to_string(t.res) + " nodes on the longest axis";
    s += ", " + std::to_string(t.rays) + " rays";
    if (t.passes) s += " + " + std::to_string(t.passes) + " probe pass" + (t.passes > 1 ? "es" : "");
    if (t.depth) s += ", depth moments";
    if (t.surfaceCache) s += ", surface probe cache";
    if (t.filter) s += ", node filter x" + std::to_string(t.filter) + (t.filterByNoise ? " (bilateral)" : "");
    if (t.guide) s += ", guided probe directions";
    if (t.blend) s += ", pass 0 blended in";
    if (t.extraPaths) s += ", " + std::to_string(t.extraPathsPerNode) + " extra cache paths per node where pass 0 is noisiest";
    if (t.byError) s += ", pass 0's rays by its error";
    if (t.probeByError) s += ", the probe pass's rays by its error";
    if (t.lightSamples > 1) s += ", " + std::to_string(t.lightSamples) + " light samples at each probe-pass path's end";
    if (t.splitLights > 1) s += ", quad lights as " + std::to_string(t.splitLights) + " x " + std::to_string(t.splitLights) + " pieces";
    return s + ", basis " + t.basis;
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
Volume tryVolume(const Ctx& c, const TrySpec& t, std::string& note, std::vector<SceneLight>* runtimeLights) {
    DirectOptions d;
    d.mode = t.direct;
    d.shadowEdges = t.shadowEdges;
    d.splitLights = t.splitLights;
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
        g.surfaceProbeCache = t.surfaceCache;
        g.nodeFilterPasses = t.filter;
        g.nodeFilterByNoise = t.filterByNoise;
        g.guideProbeDirections = t.guide;
        g.blendFirstPass = t.blend;
        g.extraCachePaths = t.extraPaths;
        g.extraCachePathsPerNode = t.extraPathsPerNode;
        g.firstPassByError = t.byError;
        g.probePassByError = t.probeByError;
        g.transport.cacheEndLightSamples = t.lightSamples;
        if (t.basis != "sh2") g.basis = makeBasis(t.basis);
        v = bakeShGather(c.scene, c.tracer, grid, g);
    }
    bakeLightVisibility(c.scene, c.tracer, plan, d, v);
    if (runtimeLights) *runtimeLights = d.mode == DirectMode::Runtime ? plan.lights : std::vector<SceneLight>{};
    return v;
}

Baked tryBake(const Ctx& c, const TrySpec& t, Baked (*answer)(Volume, double, uint64_t)) {
    const double t0 = bench::now();
    std::string note;
    std::vector<SceneLight> runtimeLights;
    Volume v = tryVolume(c, t, note, &runtimeLights);
    const double secs = bench::now() - t0;
    const uint64_t nodes = v.levels[0].grid.nodeCount();
    Baked b = answer(std::move(v), secs, nodes);
    // --direct runtime: the volume holds indirect light only; the lookup adds the direct.
    if (t.direct == DirectMode::Runtime && !runtimeLights.empty()) addRuntimeDirect(c, runtimeLights, b);
    b.note = note.empty() ? b.note : note + (b.note.empty() ? "" : ", " + b.note);
    return b;
}

}  // namespace vdblight::accuracy
