// vdblight bake [SCENE] -o OUT.vdb: a uniform SH order-2 irradiance volume.
#include <cmath>
#include <iostream>
#include <thread>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bake.h"
#include "vdblight/bake_adaptive.h"
#include "vdblight/bake_antialiased.h"
#include "vdblight/bake_bins.h"
#include "vdblight/bake_direct.h"
#include "vdblight/scene_lights.h"
#include "vdblight/bins.h"
#include "vdblight/bake_levels.h"
#include "vdblight/layout_levels.h"
#include "vdblight/solid_cull.h"
#include "vdblight/errors.h"
#include "vdblight/layout.h"
#include "vdblight/irradiance_vectors_compact.h"
#include "vdblight/photons.h"
#include "vdblight/sh.h"
#include "vdblight/scene_origin.h"
#include "vdblight/sh_window.h"
#include "vdblight/trace.h"
#include "vdblight/vdb_io.h"

namespace vdblight::app {

namespace {
struct BakeCommand {
    SceneOptions scene;
    std::string output;
    double spacing = 0;
    int resolution = 0;
    std::string bounds;
    uint32_t rays = 256;
    uint64_t seed = 1;
    int threads = 0;
    bool half = false;
    bool quiet = false;
    std::string method = "gather";
    uint64_t photons = 1'000'000;
    bool compact = false;            // --method photons: write the section 4.2 form
    std::string sampling = "point";  // point | antialiased (bake_antialiased.h)
    std::string domain;              // all | interior; default interior for antialiased
    std::string fit;                 // projection | least-squares (antialiased only; default projection)
    double invalidateBackface = -1;  // < 0: off (point sampling only)
    std::string layout = "uniform";
    int refine = 3;
    int levels = 3;
    bool cullSolids = false;
    double refineDistance = 0.0;
    bool shWindow = false;
    double targetError = 0;  // > 0: error-targeted point gather (bake_adaptive.h)
    uint32_t maxRays = 4096;
    uint32_t minRays = 64;
    std::string basis = "sh2";  // sh2 | bins:R | moment:n[:R] (bins.h)
    std::string direct;            // baked | runtime | occlusion (bake_direct.h); empty: the default
    int directLights = 4;          // --direct occlusion: lights with a visibility channel
};

/// --direct: parsed and checked against the other options before anything is loaded.
DirectOptions directFromOptions(const BakeCommand& c) {
    DirectOptions d;
    // The default is occlusion where it applies (docs/methods.md, "Direct light out of the SH"):
    // the uniform SH point gather of a scene with lights; elsewhere baked.
    const bool automatic = c.direct.empty();
    d.mode = automatic ? DirectMode::Occlusion : parseDirectMode(c.direct);
    d.maxLights = c.directLights;
    d.seed = c.seed;
    d.threads = c.threads;
    if (d.mode == DirectMode::Baked) return d;
    if (c.directLights < 1 || c.directLights > 16)
        throw ValueError("--direct-lights must be between 1 and 16, got " + std::to_string(c.directLights));
    const char* other = c.method != "gather" ? "--method photons"
                        : c.sampling != "point" ? "--sampling antialiased"
                        : c.layout != "uniform" ? "--layout bilevel/adaptive"
                        : c.basis != "sh2"      ? "--basis bins/moment"
                        : c.shWindow            ? "--sh-window"
                                                : nullptr;
    if (other && automatic) {
        d.mode = DirectMode::Baked;
        return d;
    }
    if (other)
        throw ValueError(std::string("--direct ") + c.direct + " is implemented for the uniform SH point gather only, not with " + other);
    return d;
}

void runPhotons(const BakeCommand& c);

/// Runs the pass the sampling options select.
Volume bakeSelected(const BakeCommand& c, const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                    const GatherOptions& options, Interrupter* progress, BakeStats* stats) {
    if (c.targetError > 0) {
        AdaptiveOptions a;
        a.targetError = c.targetError;
        a.minRays = c.minRays;
        a.maxRays = c.maxRays;
        a.seed = options.seed;
        a.threads = options.threads;
        a.transport = options.transport;
        AdaptiveStats as;
        Volume v = bakeShGatherAdaptive(scene, tracer, grid, a, progress, &as);
        *stats = as;
        if (!c.quiet)
            std::cout << "Error-targeted: relative standard error of mean irradiance p50 " << as.errorQuantile(0.5)
                      << ", p95 " << as.errorQuantile(0.95) << ", max " << as.errorQuantile(1.0) << " (target "
                      << c.targetError << ", " << as.nodesAtMax << " nodes stopped at --max-rays " << c.maxRays << "); "
                      << formatCount(double(as.samples)) << " gathered rays, "
                      << formatCount(double(as.samples) / double(as.nodes)) << " per node, "
                      << formatCount(double(uint64_t(c.maxRays) * as.nodes - as.samples)) << " ("
                      << int(100.0 * (1.0 - double(as.samples) / (double(c.maxRays) * as.nodes)))
                      << " %) saved against " << c.maxRays << " rays on every node.\n";
        return v;
    }
    if (c.sampling == "antialiased") {
        AntialiasedOptions aa;
        aa.raysPerCell = options.raysPerNode;
        aa.seed = options.seed;
        aa.threads = options.threads;
        aa.transport = options.transport;
        aa.domain = c.domain == "all" ? DomainMode::All : DomainMode::Interior;
        aa.fit = c.fit == "least-squares" ? NodeFit::LeastSquares : NodeFit::Projection;
        return bakeShAntialiased(scene, tracer, grid, aa, progress, stats);
    }
    if (c.invalidateBackface >= 0)
        return bakeShGatherInvalidated(scene, tracer, grid, options, c.invalidateBackface, progress, stats);
    return bakeShGather(scene, tracer, grid, options, progress, stats);
}

void run(const BakeCommand& c) {
    if (c.method != "gather" && c.method != "photons")
        throw ValueError("--method must be gather or photons, got '" + c.method + "'");
    DirectOptions direct = directFromOptions(c);
    if (c.method == "photons") return runPhotons(c);
    checkOutputWritable(c.output);
    Scene scene = loadSceneFromOptions(c.scene, c.quiet);

    GridPlacement placement;
    placement.spacing = c.spacing;
    placement.resolution = (c.spacing > 0 || c.resolution > 0) ? c.resolution : 16;
    if (!c.bounds.empty()) placement.bounds = toLocalBounds(parseBounds(c.bounds), scene.origin);
    // Bytes per node while baking and writing: float coefficients plus OpenVDB's copy.
    // The anti-aliased pass also holds double accumulators per node (coefficients + 2 weights).
    // The least-squares fit adds its 27-entry Gram row, and its solve a prior and six CG
    // vectors of all 27 values per node (node_least_squares.h).
    const std::size_t lsq = c.fit == "least-squares" ? 27 + 7 * sh::kCoeffs * 3 : 0;
    const std::size_t extra = c.sampling == "antialiased" ? (sh::kCoeffs * 3 + 2 + lsq) * sizeof(double) : 0;
    const bins::BasisSpec basisSpec = bins::parseBasisSpec(c.basis);
    const bool binned = basisSpec.kind != bins::BasisSpec::Kind::Sh2;
    const std::size_t channels = binned ? std::size_t(basisSpec.binCount()) : std::size_t(sh::kCoeffs);
    const GridSpec grid = placeUniformGrid(scene.bounds(), placement, 2 * channels * 3 * sizeof(float) + extra);

    const Tracer tracer(scene);
    GatherOptions options;
    options.raysPerNode = c.rays;
    options.seed = c.seed;
    options.threads = c.threads;
    options.transport = transportFromOptions(c.scene);
    if (c.direct.empty() && direct.mode == DirectMode::Occlusion && sceneLights(scene).empty())
        direct.mode = DirectMode::Baked;  // the default in a scene lit by the sky only
    const DirectPlan plan = planDirectLight(scene, tracer, grid, direct);  // baked: an empty plan
    options.transport.skipAtReceiver = plan.filter;

    ProgressBar progress(c.quiet);
    LevelsBakeStats stats;
    LevelsPlacement levels;
    levels.kind = parseLayoutKind(c.layout);
    levels.refine = c.refine;
    levels.levels = c.levels;
    levels.refineDistance = c.refineDistance;
    Volume volume;
    if (binned) {  // Greger bins / moments on any layout
        BinsBakeOptions bo;
        bo.basis = basisSpec;
        bo.samplesPerBin = std::max<uint32_t>(1, uint32_t((uint64_t(c.rays) + basisSpec.binCount() - 1) / basisSpec.binCount()));
        bo.seed = c.seed;
        bo.threads = c.threads;
        bo.transport = options.transport;
        const LevelLayout layout = levels.kind == LayoutKind::Uniform
                                       ? uniformLayout(grid)
                                       : placeLevels(grid, scene.positions, scene.indices, levels, 2 * channels * 3 * sizeof(float));
        volume = bakeBins(scene, tracer, layout, bo, &progress, &stats);
    } else if (levels.kind == LayoutKind::Uniform) {
        volume = bakeSelected(c, scene, tracer, grid, options, &progress, &stats);
    } else {
        levels.keepFinestGeometry = c.cullSolids;
        LevelLayout layout = placeLevels(grid, scene.positions, scene.indices, levels, 2 * sh::kCoeffs * 3 * sizeof(float));
        SolidCullStats cull;
        if (c.cullSolids) cullSolidNodes(layout, tracer, SolidCullOptions(), &cull);
        volume = bakeShGatherLevels(scene, tracer, layout, options, &progress, &stats);
        if (c.cullSolids && !c.quiet)
            std::cout << "Solid culling: " << cull.nodesCulled << " of " << cull.nodesBefore
                      << " nodes left out (inside closed solids: " << cull.solidRegions << " of " << cull.regions
                      << " regions of geometry-free cells, " << cull.solidCells << " solid cells).\n";
        if (!c.quiet)
            std::cout << "Layout " << c.layout << ": " << volume.levels.size() << " levels refined by " << layout.refine
                      << ", " << layout.totalNodes() << " nodes (" << stats.seamNodes << " seam nodes set from the coarser level) vs "
                      << layout.denseEquivalentNodes() << " in a dense grid at the finest spacing ("
                      << 100.0 * (1.0 - double(layout.totalNodes()) / layout.denseEquivalentNodes()) << " % saved"
                      << (c.cullSolids ? ", " + std::to_string(layout.culledNodes) + " of them culled inside solids" : "")
                      << ").\n";
    }
    if (direct.mode != DirectMode::Baked) {
        bakeLightVisibility(scene, tracer, plan, direct, volume, &progress);
        if (!c.quiet) {
            std::cout << "Direct light (" << directModeName(direct.mode) << "): " << plan.lights.size() << " of " << plan.sceneLightCount
                      << " lights kept out of the SH";
            if (direct.mode == DirectMode::Occlusion) {
                std::cout << ", with visibility channels; measured share of the direct light:";
                for (double share : plan.contribution) std::cout << ' ' << int(100.0 * share + 0.5) << " %";
            }
            std::cout << ".\n";
        }
    }
    if (c.refineDistance > 0) volume.meta["refine_distance"] = c.refineDistance;
    if (c.shWindow) applyShWindow(volume);
    placeVolumeInWorld(volume, scene.origin);  // baked in the scene's local frame (scene_origin.h)
    volume.meta["scene_file"] = c.scene.path.empty() ? std::string("(bundled default) ") + defaultScenePath() : c.scene.path;
    volume.meta["sky"] = c.scene.skyMap.empty() ? (c.scene.sky.empty() ? std::string("0,0,0") : c.scene.sky)
                                                : "map:" + c.scene.skyMap;
    WriteOptions write;
    write.halfFloat = c.half;
    writeVolume(volume, c.output, write);

    if (!c.quiet) {
        std::cout << "Baked " << stats.nodes << " nodes (" << (volume.levels.size() > 1 ? "level 0: " : "") << grid.nx << " x " << grid.ny << " x " << grid.nz
                  << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' ("
                  << scene.triangleCount() << " triangles";
        if (scene.stats.degenerateTrianglesSkipped)
            std::cout << ", " << scene.stats.degenerateTrianglesSkipped << " degenerate skipped";
        std::cout << ") with " << (c.targetError > 0 ? std::string("error-targeted")
                                   : binned ? metaString(volume.meta, "rays_per_node") : std::to_string(c.rays))
                  << " rays per node and up to " << c.scene.bounces << " bounces: "
                  << formatCount(double(stats.rays.total())) << " rays (" << formatCount(double(stats.rays.intersect))
                  << " closest-hit, " << formatCount(double(stats.rays.occluded)) << " shadow) in "
                  << formatSeconds(stats.seconds) << ", " << formatCount(stats.raysPerSecond()) << " rays/s on "
                  << int64_t(std::get<int64_t>(volume.meta["threads"])) << " threads";
        if (c.sampling == "antialiased") std::cout << " (sampling antialiased, domain " << metaString(volume.meta, "domain") << ")";
        if (volume.meta.count("nodes_dilated"))
            std::cout << "; " << metaString(volume.meta, "nodes_dilated") << " nodes filled by dilation";
        if (binned)
            std::cout << ". Wrote " << c.output << " (basis " << volume.basis.kind << ", " << channels << " Vec3f grids, "
                      << metaString(volume.meta, "samples_per_bin") << " samples per bin).\n";
        else
        std::cout << ". Wrote " << c.output << " (SH order 2 radiance, 9 Vec3f grids"
                  << (volume.levels[0].validity.empty() ? "" : " + validity") << ").\n";
    }
}
// --method photons: an irradiance-vector volume filled by photon tracing.
void runPhotons(const BakeCommand& c) {
    PhotonOptions options;
    options.photons = c.photons;
    options.seed = c.seed;
    options.threads = c.threads;
    options.transport = transportFromOptions(c.scene);
    checkPhotonCount(options.photons);  // before loading anything
    checkOutputWritable(c.output);
    Scene scene = loadSceneFromOptions(c.scene, c.quiet);
    GridPlacement placement;
    placement.spacing = c.spacing;
    placement.resolution = (c.spacing > 0 || c.resolution > 0) ? c.resolution : 16;
    if (!c.bounds.empty()) placement.bounds = toLocalBounds(parseBounds(c.bounds), scene.origin);
    // Bytes per node: double totals, a float buffer per thread, the volume and OpenVDB's copy.
    const GridSpec grid = placeUniformGrid(scene.bounds(), placement, 54 * (8 + 4 * 4));
    const Tracer tracer(scene);

    ProgressBar progress(c.quiet);
    PhotonStats stats;
    Volume volume = bakePhotons(scene, tracer, grid, options, &progress, &stats);
    placeVolumeInWorld(volume, scene.origin);  // baked in the scene's local frame (scene_origin.h)
    volume.meta["scene_file"] = c.scene.path.empty() ? std::string("(bundled default) ") + defaultScenePath() : c.scene.path;
    volume.meta["sky"] = c.scene.skyMap.empty() ? (c.scene.sky.empty() ? std::string("0,0,0") : c.scene.sky)
                                                : "map:" + c.scene.skyMap;
    WriteOptions write;
    write.halfFloat = c.half || c.compact;
    if (c.compact) volume = iv::compact(volume);
    writeVolume(volume, c.output, write);
    if (!c.quiet) {
        std::cout << "Baked " << grid.nodeCount() << " nodes (" << grid.nx << " x " << grid.ny << " x " << grid.nz
                  << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' (" << scene.triangleCount()
                  << " triangles) with " << formatCount(double(stats.photons)) << " photons: "
                  << formatCount(double(stats.segments)) << " segments, " << formatCount(double(stats.crossings))
                  << " face crossings, " << formatCount(double(stats.rays.total())) << " rays in "
                  << formatSeconds(stats.seconds) << " ("
                  << formatCount(stats.seconds > 0 ? double(stats.photons) / stats.seconds : 0.0) << " photons/s). Wrote "
                  << c.output
                  << (c.compact ? " (compact irradiance vectors: colour + direction, 12 half-float Vec3 grids).\n"
                                : " (irradiance vectors, 18 Vec3f grids).\n");
    }
}
}  // namespace

void addBakeCommand(CLI::App& app) {
    auto c = std::make_shared<BakeCommand>();
    CLI::App* cmd = app.add_subcommand("bake", "Bake a uniform SH order-2 irradiance volume into a .vdb");
    addSceneOptions(*cmd, c->scene);
    cmd->add_option("-o,--output", c->output, "Output .vdb file (written atomically)")->required();
    auto* spacing = cmd->add_option("--spacing", c->spacing, "Distance between nodes, in scene units");
    auto* resolution =
        cmd->add_option("--resolution", c->resolution, "Nodes along the longest axis (default 16)")->excludes(spacing);
    cmd->add_option("--bounds", c->bounds,
                    "Node box x0,y0,z0,x1,y1,z1 (default: scene bounds inset by half a spacing)");
    cmd->add_option("--rays", c->rays, "Ray directions per node")->capture_default_str()->check(CLI::Range(1u, 1u << 30));
    cmd->add_option("--seed", c->seed, "Random seed (same seed, same bits, any thread count)")->capture_default_str();
    cmd->add_option("--threads", c->threads, "Worker threads (0 = all cores)")->capture_default_str()->check(CLI::Range(0, 4096));
    cmd->add_flag("--half", c->half, "Store the grids as 16-bit floats");
    cmd->add_option("--method", c->method, "gather (SH order 2 at each node) or photons (irradiance vectors, Pacanowski et al.)")
        ->capture_default_str();
    cmd->add_option("--photons", c->photons, "Photons emitted in total (--method photons)")->capture_default_str();
    cmd->add_flag("--compact", c->compact,
                  "--method photons: write the compact colour + direction form (Pacanowski et al. 4.2; 12 half-float "
                  "grids) instead of the 18 full grids");
    cmd->add_option("--sampling", c->sampling,
                    "point: project at the nodes; antialiased: trilinear-weighted origins over each cell "
                    "(Kontkanen-Laine eq. 6; --rays is then rays per cell)")
        ->capture_default_str();
    cmd->add_option("--domain", c->domain,
                    "antialiased only: all, or interior = only origins that see no back-face (default)");
    cmd->add_option("--fit", c->fit,
                    "antialiased only: projection = eq. 6 (default), or least-squares = fit the node values to the "
                    "samples over the domain (docs/methods.md)");
    auto* invalidate = cmd->add_option("--invalidate-backface", c->invalidateBackface,
                    "point only: nodes whose rays hit back-faces more than this fraction (0..1) are replaced by "
                    "dilating valid neighbours");
    cmd->add_option("--layout", c->layout, "Node layout: uniform, bilevel (Greger et al.) or adaptive (n levels)")
        ->capture_default_str();
    auto* refine = cmd->add_option("--refine", c->refine, "bilevel/adaptive: split refined cells K x K x K")->capture_default_str();
    auto* levelsOpt = cmd->add_option("--levels", c->levels, "adaptive: number of levels including the first")->capture_default_str();
    auto* target = cmd->add_option("--target-error", c->targetError,
                    "point gather: sample each node in doubling rounds until the relative standard error of its "
                    "mean irradiance is below this (e.g. 0.02), up to --max-rays");
    auto* maxRays = cmd->add_option("--max-rays", c->maxRays, "--target-error: most rays a node may take")->capture_default_str();
    auto* minRays = cmd->add_option("--min-rays", c->minRays, "--target-error: rays of the first round")->capture_default_str();
    cmd->add_flag("--sh-window", c->shWindow,
                  "gather: window the SH bands (1, 0.584, 0.135) so that irradiance is never negative (blurs; "
                  "docs/methods.md)");
    cmd->add_option("--basis", c->basis,
                    "Directional basis: sh2, bins:R (Greger: 2 R^2 equal-area bins of irradiance) or moment:n[:R] "
                    "(n-th moment, eq. 5, for glossy lookups with query --view; R = 17 by default); with bins, "
                    "--rays is rounded up to a multiple of the bin count")
        ->capture_default_str();
    auto* refineDistance = cmd->add_option("--refine-distance", c->refineDistance,
                    "bilevel/adaptive: refine every cell within this distance (scene units, max-norm) of a "
                    "triangle, not only cells that contain one (0 = Greger's rule)")
                               ->capture_default_str();
    cmd->add_flag("--cull-solids", c->cullSolids,
                  "bilevel/adaptive with sh2: leave out nodes whose every cell lies inside a closed solid "
                  "(docs/format.md, Levels); queries there return 0");
    cmd->add_option("--direct", c->direct,
                    "Direct light: baked (in the SH), runtime (SH holds indirect light; the file lists the lights for "
                    "the run time to add) or occlusion (plus per-node visibility of the --direct-lights most important "
                    "lights, added exactly at lookup). Default: occlusion for the uniform SH point gather of a scene "
                    "with lights, baked otherwise");
    cmd->add_option("--direct-lights", c->directLights, "--direct occlusion: lights with a visibility channel (1..16)")
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", c->quiet, "No progress bar and no summary");
    cmd->callback([c, spacing, resolution, invalidate, refine, levelsOpt, target, maxRays, minRays, refineDistance] {
        if (target->count() > 0 && !(c->targetError > 0 && c->targetError <= 1))
            throw ValueError("--target-error must be in (0, 1], got " + std::to_string(c->targetError));
        if (c->shWindow && (c->method != "gather" || bins::parseBasisSpec(c->basis).kind != bins::BasisSpec::Kind::Sh2))
            throw ValueError("--sh-window applies to --method gather with --basis sh2 only");
        if (target->count() > 0 && (c->minRays < 2 || c->maxRays < c->minRays))
            throw ValueError("--min-rays must be at least 2 and --max-rays at least --min-rays, got " +
                             std::to_string(c->minRays) + " and " + std::to_string(c->maxRays));
        if (target->count() == 0 && (maxRays->count() > 0 || minRays->count() > 0))
            throw ValueError("--max-rays and --min-rays need --target-error");
        if (target->count() > 0 && (c->method != "gather" || c->sampling != "point" || invalidate->count() > 0 ||
                                    parseLayoutKind(c->layout) != LayoutKind::Uniform ||
                                    bins::parseBasisSpec(c->basis).kind != bins::BasisSpec::Kind::Sh2))
            throw ValueError("--target-error works with --method gather, --sampling point, --layout uniform and --basis sh2 only");
        const LayoutKind kind = parseLayoutKind(c->layout);
        if (bins::parseBasisSpec(c->basis).kind != bins::BasisSpec::Kind::Sh2 &&
            (c->method != "gather" || c->sampling != "point" || invalidate->count() > 0))
            throw ValueError("--basis bins/moment works with --method gather and --sampling point only");
        if (c->refine < 2) throw ValueError("--refine must be at least 2, got " + std::to_string(c->refine));
        if (c->levels < 1) throw ValueError("--levels must be at least 1, got " + std::to_string(c->levels));
        if (c->levels > 16)
            throw ValueError("--levels " + std::to_string(c->levels) + " is absurd (each level multiplies the resolution by --refine); use at most 16");
        if (kind == LayoutKind::Uniform && refine->count() > 0) throw ValueError("--refine needs --layout bilevel or adaptive");
        if (kind != LayoutKind::Adaptive && levelsOpt->count() > 0) throw ValueError("--levels needs --layout adaptive");
        if (kind != LayoutKind::Uniform && (c->sampling != "point" || invalidate->count() > 0 || c->method != "gather"))
            throw ValueError("--layout bilevel/adaptive works with --method gather and --sampling point only");
        if (refineDistance->count() > 0 && !(c->refineDistance >= 0 && std::isfinite(c->refineDistance)))
            throw ValueError("--refine-distance must be a finite distance >= 0, got " + std::to_string(c->refineDistance));
        if (refineDistance->count() > 0 && kind == LayoutKind::Uniform)
            throw ValueError("--refine-distance needs --layout bilevel or adaptive");
        if (c->cullSolids && (kind == LayoutKind::Uniform || bins::parseBasisSpec(c->basis).kind != bins::BasisSpec::Kind::Sh2))
            throw ValueError("--cull-solids needs --layout bilevel or adaptive and --basis sh2");
        // Refuse explicit zero or negative values here: 0 would otherwise mean "default".
        if (spacing->count() > 0 && !(c->spacing > 0))
            throw ValueError("--spacing must be positive, got " + std::to_string(c->spacing));
        if (resolution->count() > 0 && c->resolution < 1)
            throw ValueError("--resolution must be at least 1, got " + std::to_string(c->resolution));
        if (c->sampling != "point" && c->sampling != "antialiased")
            throw ValueError("--sampling must be point or antialiased, got '" + c->sampling + "'");
        if (!c->domain.empty() && c->domain != "all" && c->domain != "interior")
            throw ValueError("--domain must be all or interior, got '" + c->domain + "'");
        if (!c->fit.empty() && c->fit != "projection" && c->fit != "least-squares")
            throw ValueError("--fit must be projection or least-squares, got '" + c->fit + "'");
        if (!c->fit.empty() && c->sampling != "antialiased")
            throw ValueError("--fit needs --sampling antialiased");
        if (!c->domain.empty() && c->sampling != "antialiased")
            throw ValueError("--domain needs --sampling antialiased (point sampling has --invalidate-backface)");
        if (invalidate->count() > 0 && !(c->invalidateBackface >= 0 && c->invalidateBackface <= 1))
            throw ValueError("--invalidate-backface must be in [0, 1], got " + std::to_string(c->invalidateBackface));
        if (invalidate->count() > 0 && c->sampling != "point")
            throw ValueError("--invalidate-backface applies to --sampling point only");
        if (c->method == "photons" && (c->sampling != "point" || !c->domain.empty() || invalidate->count() > 0))
            throw ValueError("--sampling, --domain and --invalidate-backface apply to --method gather only");
        if (c->compact && c->method != "photons") throw ValueError("--compact applies to --method photons only");
        run(*c);
    });
}

}  // namespace vdblight::app
