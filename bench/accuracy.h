// vdblight_bench_accuracy (issue 15): what its parts share. bench_accuracy.cpp says what
// the benchmark measures and how; one file per part:
//  - accuracy_configs.cpp: the table of methods and modes; accuracy_bakes.cpp: their bakes;
//    accuracy_engine_layouts.cpp: default_l2 and the engine-size export layouts (one bake);
//  - accuracy_truth.cpp: points, ground truth, error statistics;
//  - accuracy_floor.cpp and accuracy_decompose.cpp: the decomposition (floor, spatial);
//  - accuracy_study.cpp (--study), accuracy_time_to.cpp (--time-to),
//    accuracy_probe_study.cpp (--probe-study);
//  - accuracy_report.cpp: table rows, CSV, worst points, summary.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "accuracy_scenes.h"
#include "bench_util.h"
#include "bake/bake_antialiased.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/light/light.h"
#include "vdblight/query/query.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight::accuracy {

namespace fs = std::filesystem;

// --- Settings and the things a configuration bakes (accuracy_bakes.cpp) -------------------

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

/// A Baked answering through IrradianceQuery (the library's run-time lookup, outside policy
/// Clamp: the default every application gets).
Baked fromVolume(Volume v, double seconds, uint64_t nodes);
/// As fromVolume, but an occlusion volume's light visibility is interpolated trilinearly (the
/// lookup before issue 15 item 2; the SH part keeps its depth weights): for comparison.
Baked fromVolumeVisibilityTrilinear(Volume v, double seconds, uint64_t nodes);
/// The uniform grid of `vdblight bake`: `resolution` nodes on the longest axis of the scene box.
GridSpec gridFor(const Scene& s, int resolution);

/// `bounces` > 0 overrides the transport's bounce cap; `depth`: depth moments and weighted
/// lookups.
Baked pointGather(const Ctx& c, int resolution, uint32_t rays, int bounces = 0, bool depth = false);
Baked antialiased(const Ctx& c, int resolution, uint32_t rays, NodeFit fit);
Baked adaptiveLayout(const Ctx& c, int resolution, uint32_t rays, int levels, int refine, bool depth = false);
Baked targetError(const Ctx& c, int resolution, double target, uint32_t maxRays);
/// `resolution` 0: the default bake's grid (about 16384 nodes).
/// depthRays > 0: also depth moments from that many first-hit rays per node (weighted lookup).
Baked photons(const Ctx& c, int resolution, uint64_t count, int bounces = 0, iv::Blend blend = iv::kDefaultBlend,
              uint32_t depthRays = 0);
Baked binsBake(const Ctx& c, int resolution, int binResolution);
Baked directGather(const Ctx& c, int resolution, uint32_t rays, DirectMode mode, int probePasses = 0,
                  bool shadowEdges = true);

/// A candidate default (--try SPEC): `key=value` pairs separated by commas, e.g.
/// "res=32,rays=512,passes=1,depth=1" or "nodes=32768,target=0.03,max=1024".
///   res=N      nodes on the longest axis (16); nodes=N: the spacing that gives about N nodes
///   rays=N     rays per node and pass (256); target=E, min=N, max=N: error-targeted instead
///   passes=N   probe-to-probe passes (1); depth=1: depth moments, weighted lookups
///   direct=baked|runtime|occlusion (occlusion); cache=nodes|surface: the probe pass's cache
///   filter=N   passes of the filter across nodes (--filter-passes; node_filter.h)
///   guide=1, blend=1, extra=1: the preview's --guide-probe-directions, --blend-first-pass, --extra-cache-paths
///   extrapaths=N: --extra-cache-paths-per-node; byerror=1: the preview's --first-pass-by-error;
///   probebyerror=1: `fast`'s --probe-pass-by-error
///   lightsamples=N: --probe-light-samples; split=K: --split-lights K
///   preset=default|preview|fast|high: start from that --quality's spec (presetTry), the other keys
///   change it, e.g. `preset=default,byerror=1`
/// Every bake of the command is reproduced (bake_direct.h plan, gather, visibility, depth).
struct TrySpec {
    int res = 16;
    uint64_t nodes = 0;
    uint32_t rays = 256, minRays = 64, maxRays = 2048;
    double target = 0;
    int passes = 1;
    bool depth = false;
    DirectMode direct = DirectMode::Occlusion;
    std::string basis = "sh2";  ///< the gather's stored basis (`basis=sh:4`; fixed budgets only)
    bool surfaceCache = false;  ///< `cache=surface`: --probe-cache surface (fixed budgets only)
    int filter = 0;             ///< `filter=N`: passes of the node filter (node_filter.h; fixed budgets only)
    bool filterByNoise = false; ///< `bilateral=1`: its weights also from the nodes' error estimates
    bool shadowEdges = true;    ///< `edges=0`: bake --no-shadow-edges
    int splitLights = 1;        ///< `split=K`: bake --split-lights K
    bool blend = false;         ///< `blend=1`: GatherOptions::blendFirstPass
    bool guide = false;         ///< `guide=1`: guided probe directions (GatherOptions::guideProbeDirections)
    bool extraPaths = false;    ///< `extra=1`: GatherOptions::extraCachePaths
    uint32_t extraPathsPerNode = 256;  ///< `extrapaths=N`: GatherOptions::extraCachePathsPerNode
    bool byError = false;       ///< `byerror=1`: GatherOptions::firstPassByError
    bool probeByError = false;  ///< `probebyerror=1`: GatherOptions::probePassByError
    int lightSamples = 1;       ///< `lightsamples=N`: TransportOptions::cacheEndLightSamples (--probe-light-samples)
};

TrySpec parseTry(const std::string& spec);
/// What `vdblight bake SCENE -o OUT` bakes: resolveBakeRequest of an empty request.
TrySpec defaultTry();
/// What `vdblight bake SCENE -o OUT --quality QUALITY` bakes (resolveBakeRequest).
TrySpec presetTry(const std::string& quality);
/// One line for the report ("~16384 nodes, 1024 rays + 1 probe pass, depth moments, basis sh:4").
std::string describeTry(const TrySpec& t);
GridSpec tryGrid(const Scene& s, const TrySpec& t, const Settings& st);
/// The volume `vdblight bake` makes for the spec (a note says what it did, e.g. no lights);
/// `runtimeLights`, if given, gets the lights a --direct runtime lookup must add (else empty).
Volume tryVolume(const Ctx& c, const TrySpec& t, std::string& note, std::vector<SceneLight>* runtimeLights = nullptr);
/// tryVolume, timed, then `answer` (fromVolume: the library's lookup; or another reading of the
/// same volume, e.g. fromVolumeVisibilityTrilinear); for `direct=runtime`, plus the direct light
/// with shadow rays at each lookup (as directGather).
Baked tryBake(const Ctx& c, const TrySpec& t, Baked (*answer)(Volume, double, uint64_t) = &fromVolume);

/// default_l2 (the default's bands 0..2) and the engine-size export layouts' readings of the
/// same bake, default_l2_l1, default_l2_sh2_32 and default_l2_sh1_16 (accuracy_engine_layouts.cpp).
void addEngineLayoutConfigs(std::vector<Config>& v, const TrySpec& def);

/// The table of methods and modes (accuracy_configs.cpp). Resolutions and budgets are the full
/// run's; --quick scales them down (Settings::res / rays / photons).
std::vector<Config> configurations();

// --- Points, ground truth and errors (accuracy_truth.cpp) ---------------------------------

struct Points {
    std::vector<Vec3f> x, n;
};

struct Truth {
    std::vector<double> e, se;  ///< luminance of E_ref and of its standard error
    double mean = 0;
    double guard = 0.01;  ///< the smallest denominator, as a fraction of `mean`
    double denominator(std::size_t i) const { return std::max(e[i], guard * mean); }
};

struct Errors {
    double rms = 0, p95 = 0, max = 0, bias = 0;
};

/// `count` uniformly random free-space points clear of surfaces, random unit normals (fixed seed).
Points freeSpacePoints(const Scene& s, const Tracer& tracer, int count);
/// `reference` at the points (cached by scene, points, samples, bounces and seed).
Truth groundTruth(const Scene& s, const Tracer& tracer, const Points& p, const Settings& st, uint32_t samples);
/// Statistics of per-point relative errors (signed).
Errors summarise(const std::vector<double>& rel);
/// Luminance of f at every point and normal.
std::vector<double> values(const std::function<Rgb(const Vec3f&, const Vec3f&)>& f, const Points& p);
/// (got - want) / the truth's guarded denominator, per point.
std::vector<double> relative(const std::vector<double>& got, const std::vector<double>& want, const Truth& t);

/// RMS with the Monte Carlo noise extrapolated out of two estimates at N/4 and N samples
/// (squared noise falls as 1/N): sqrt((4 e_N^2 - e_{N/4}^2) / 3), 0 if negative.
inline double noiseFree(double eQuarter, double eFull) {
    return std::sqrt(std::max(0.0, (4 * eFull * eFull - eQuarter * eQuarter) / 3));
}

// --- The floor: the representations at the points themselves (accuracy_floor.cpp) --------

/// Incident radiance at a point projected, from the same samples, into SH order 2, the six
/// irradiance vectors (irradiance_vectors.h) and the cosine-weighted irradiance for the point's
/// normal (a check on the projection: that one has no representation error). Sampling as the
/// point gather's (bake.h): stratified uniform directions with gathered radiance, one NEE
/// sample of the emissive triangles per direction (MIS), punctual lights exactly.
struct AtPoint {
    Rgbd sh[sh::kCoeffs] = {};
    /// The same samples in real SH of order 4 (the `sh:4` basis, 25 coefficients): what a
    /// higher order would leave of the representation error (band 3 adds nothing to
    /// irradiance, band 4 is the next term of the clamped cosine).
    Rgbd sh4[25] = {};
    double iv[iv::kFloatsPerNode] = {};
    Rgbd e{0, 0, 0};
};

struct Floor {
    std::vector<double> sh, iv, e;  ///< luminance at each point's normal
    /// The same six vectors read with the paper's n^2 blend (the lookup before issue 15 item 5)
    /// and with the quadratic blend unclamped (`iv` is the library's default, bounded blend).
    std::vector<double> ivPaper, ivQuadratic;
};

AtPoint projectAtPoint(const RadianceEstimator& est, const Vec3f& x, const Vec3f& n, uint32_t rays, uint64_t stream);
/// Irradiance for the unit normal n from AtPoint::sh4 (through the sh:4 basis's terms).
Rgb sh4Irradiance(const AtPoint& a, const Vec3f& n);
Floor floorAt(const Scene& s, const Tracer& tracer, const Points& p, uint32_t rays, int refBounces);
/// An irradiance-vector volume whose nodes hold the six vectors projected at the node itself.
Volume ivPointVolume(const Scene& s, const Tracer& tracer, int resolution, uint32_t rays, int bounces);

/// The decomposition of one scene's error: floors, spatial (accuracy_decompose.cpp).
void decompose(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
               const Settings& st, FILE* csv);

// --- Studies ------------------------------------------------------------------------------

/// The default bake's plan (accuracy_study.cpp): its grid, the lights it takes out of the SH
/// (--direct occlusion; baked in a scene without lights) and the transport that leaves them
/// out at the receiver.
struct DefaultPlan {
    GridSpec grid;
    DirectMode mode = DirectMode::Baked;
    DirectPlan lights;
    TransportOptions transport;
};
DefaultPlan defaultPlan(const Scene& s, const Tracer& tracer, const Settings& st);
/// What the default adds exactly at point i: each chosen light's irradiance for the point's
/// normal times its visibility (256 samples); zero without chosen lights.
Rgb exactDirectAt(const Scene& s, const Tracer& tracer, const DefaultPlan& p, const Points& pts, std::size_t i);

void studyDefault(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth, const Settings& st,
                  uint32_t rays, uint32_t floorRays, FILE* csv);
void timeToAccuracy(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
                    const Settings& st, double target, FILE* csv);
void probeCacheStudy(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
                     const Settings& st, uint32_t passZeroRays, uint32_t pointRays, int paths);

// --- Report (accuracy_report.cpp) ---------------------------------------------------------

struct Row {
    Row(std::string s, std::string c, Errors err = {}) : scene(std::move(s)), config(std::move(c)), e(err) {}
    std::string scene, config;
    Errors e;
    double seconds = 0, cpu = 0, bytesPerNode = 0, noise = -1;
    uint64_t nodes = 0;
    std::string note;
};

void printRow(const Row& r);
void writeCsvRow(FILE* csv, const Row& r);
/// The `count` points with the largest |error| (--worst N: where a method fails).
void printWorst(const std::vector<double>& rel, const std::vector<double>& got, const Truth& t, const Points& p, int count);
/// RMS (bias) per configuration and scene, as a table.
void printSummary(const std::vector<Config>& configs, const std::vector<Row>& summary);
/// CPU seconds of this process (all threads): on a shared machine wall time includes waiting
/// for a core, CPU time does not.
double cpuSeconds();
/// The ground-truth cache beside the binary: build/accuracy_cache.
fs::path defaultCache(const char* argv0);

}  // namespace vdblight::accuracy
