// vdblight bake [SCENE] -o OUT.vdb: a uniform SH order-2 irradiance volume.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bake.h"
#include "vdblight/bake_adaptive.h"
#include "vdblight/bake_antialiased.h"
#include "vdblight/bake_depth.h"
#include "vdblight/bake_basis.h"
#include "vdblight/bake_bins.h"
#include "vdblight/basis.h"
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
#include "vdblight/tiles.h"
#include "vdblight/trace.h"
#include "vdblight/node_budget.h"
#include "vdblight/vdb_io.h"
#include "vdblight/volume_compact.h"

namespace vdblight::app {

namespace {
struct BakeCommand {
    SceneOptions scene;
    std::string output;
    double spacing = 0;
    int resolution = 0;
    uint64_t nodes = 0;  // > 0: about this many nodes (node_budget.h; the --quality preset's)
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
    uint32_t maxRays = 0;    // 0: the --quality preset's
    uint32_t minRays = 0;    // 0: the --quality preset's
    std::string quality = "default";  // preview | default | high (qualityPreset)
    int probePasses = 0;              // GatherOptions::probePasses
    std::string basis = "sh2";  // sh2 | bins:R | moment:n[:R] (bins.h)
    std::string direct;            // baked | runtime | occlusion (bake_direct.h); empty: the default
    int directLights = 4;          // --direct occlusion: lights with a visibility channel
    bool depthMoments = false;  // per-node depth moments for visibility-weighted lookups (bake_depth.h)
    uint32_t depthRays = 0;     // 0: as many as --rays (then the gather's own first rays)
    bool reproducible = true;   // leave run-specific metadata out of the file (vdb_io.h)
    int tiles = 0;              // > 0: bake only tile `tile` of this many (tiles.h)
    int tile = -1;
    int stage = -1;             // >= 0: only this pass of a bake with probe passes (tiles.h, "Staged bakes")
    std::string stageInput;     // stage > 0: the merged tiles of the stage before
    std::string parameters;     // every option that changes the result, for the tile hash
    bool planOnly = false;      // bakeStageCount: parse and resolve the presets, bake nothing
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
                        : c.basis != "sh2"      ? "--basis other than sh2"
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

/// Why a bake with these options cannot be split into tiles, or "" if it can.
std::string untileable(const BakeCommand& c) {
    if (c.method == "photons") return "--method photons cannot be tiled yet (its photons cross every tile)";
    if (c.sampling == "antialiased")
        return "--sampling antialiased cannot be tiled (cells share nodes across tile borders, dilation crosses them)";
    if (c.invalidateBackface >= 0) return "--invalidate-backface cannot be tiled (its dilation crosses tile borders)";
    if (c.shWindow) return "--sh-window cannot be tiled yet (the window would have to follow the seams at merge)";
    // Each probe-to-probe pass reads every node of the pass before: one stage per pass.
    if (c.probePasses > 0 && c.stage < 0)
        return "probe-to-probe passes are tiled in stages (each pass reads every node of the pass before): bake "
               "every tile with --stage 0, merge them, then every tile with --stage 1 --stage-input STAGE0.vdb, ... up "
               "to --stage " + std::to_string(c.probePasses) + ", and merge the last stage ('vdblight slurm' writes "
               "this chain; docs/scaling.md), or add --probe-passes 0";
    return "";
}

/// The canonical text of the options that change a bake's result: each as given on the
/// command line, so that every tile of one bake must be started with the same options.
std::string bakeParameters(const CLI::App& cmd) {
    // --stage-input: its content, not its path, is part of the parameters (run()).
    static const char* const kIgnored[] = {"--output", "--tile", "--threads", "--quiet", "--help", "--reproducible",
                                           "--stage-input"};
    std::vector<std::string> lines;
    for (const CLI::Option* opt : cmd.get_options()) {
        const std::string name = opt->get_name();
        if (std::find(std::begin(kIgnored), std::end(kIgnored), name) != std::end(kIgnored)) continue;
        std::string line = name + "=";
        for (const std::string& r : opt->results()) line += r + ";";
        lines.push_back(line);
    }
    std::sort(lines.begin(), lines.end());
    std::string text;
    for (const std::string& l : lines) text += l + "\n";
    return text;
}

void runPhotons(const BakeCommand& c);

/// What --quality means for the point gather (docs/methods.md, "The default bake", issue 15).
/// `preview`: 16 nodes on the longest axis, a fixed 256 rays per node of full paths, no
/// depth moments (sub-second bakes to iterate on a scene).
/// `default`: about kDefaultNodes nodes in the scene box (node_budget.h: the spacing
/// follows the scene's volume, 16..64 nodes on its longest axis), kDefaultRays rays of full
/// paths, then one probe-to-probe pass of as many rays that ends paths at their first hit
/// with the first pass's reflected light (GatherOptions::probePasses), and depth moments from
/// the gather's own first hits so that lookups do not interpolate across walls
/// (depth_moments.h). The measured choice against the accuracy benchmark's ground truth.
/// `high`: the default's grid and depth moments, every node sampled to a relative standard
/// error of 3 % (64..2048 rays, bake_adaptive.h), two probe passes. Explicit --resolution,
/// --spacing, --rays, --target-error, --probe-passes, --[no-]depth-moments, --min-rays and
/// --max-rays override the preset's.
constexpr uint64_t kDefaultNodes = 16384;
constexpr uint32_t kDefaultRays = 512;
struct QualityPreset {
    double targetError;  ///< 0: fixed budget (--rays)
    uint32_t minRays, maxRays;
    int probePasses;
    uint64_t nodes;      ///< 0: 16 nodes on the longest axis
    uint32_t rays;       ///< rays per node and pass of a fixed budget
    bool depthMoments;
};
QualityPreset qualityPreset(const std::string& quality) {
    if (quality == "preview") return {0.0, 0, 0, 0, 0, 256, false};
    if (quality == "default") return {0.0, 0, 0, 1, kDefaultNodes, kDefaultRays, true};
    if (quality == "high") return {0.03, 64, 2048, 2, kDefaultNodes, kDefaultRays, true};
    throw ValueError("--quality must be preview, default or high, got '" + quality + "'");
}

/// The bake's own noise estimate, honestly labelled: per node the relative standard error of
/// its mean irradiance from the sample variance; what it does not measure is said.
void printNoiseSummary(const BakeStats& stats, const Volume& volume, const GridSpec& grid) {
    auto percent = [](double e) { return std::to_string(int(std::lround(e * 1000.0)) / 10) + "." +
                                         std::to_string(int(std::lround(e * 1000.0)) % 10) + " %"; };
    const std::vector<float>& err = stats.estimatedError;
    std::size_t worst = 0;
    for (std::size_t n = 1; n < err.size(); ++n)
        if (err[n] > err[worst]) worst = n;
    std::cout << "Noise per node (relative standard error of its irradiance, from the sample variance): p50 "
              << percent(stats.errorQuantile(0.5)) << ", p95 " << percent(stats.errorQuantile(0.95)) << ", max "
              << percent(err[worst]) << " at node " << worst % grid.nx << "," << (worst / grid.nx) % grid.ny << ","
              << worst / (std::size_t(grid.nx) * grid.ny);
    if (volume.meta.count("nodes_at_max_rays"))
        std::cout << "; " << metaString(volume.meta, "nodes_at_max_rays") << " nodes stopped at the ray cap above the target";
    std::cout << ". Not included: SH truncation, interpolation between nodes.\n";
}

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
        a.probePasses = options.probePasses;
        a.only = options.only;
        a.stage = options.stage;
        a.stageInput = options.stageInput;
        AdaptiveStats as;
        Volume v = bakeShGatherAdaptive(scene, tracer, grid, a, progress, &as);
        *stats = as;
        if (!c.quiet && !as.estimatedError.empty() && !options.only)
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
    SceneLoadReport read;
    Scene scene = loadSceneFromOptions(c.scene, c.quiet, &read);
    TileId tileId;
    NodeMask tileMask;
    if (c.tiles > 0) {
        tileId.index = c.tile, tileId.count = c.tiles;
        // A stage's tiles depend on the stage before's merged file: its content is a parameter.
        const std::string input = c.stage > 0 ? "stage_input_sha256=" + fileContentHash(c.stageInput).sha256 + "\n" : "";
        tileId.paramsHash = tileParamsHash(scene.contentHash(), c.parameters + input);
        TileId onDisk;
        bool done = false;
        std::error_code ec;
        try {  // an unreadable or foreign file there is simply baked over
            done = std::filesystem::exists(c.output, ec) && readTileId(c.output, onDisk) && onDisk.index == tileId.index &&
                   onDisk.count == tileId.count && onDisk.paramsHash == tileId.paramsHash &&
                   fileContentHash(c.output).uuidFromContent;  // and not damaged since
        } catch (const Error&) {
        }
        if (done) {
            if (!c.quiet)
                std::cout << "Tile " << c.tile << " of " << c.tiles << " is already baked with the same scene and parameters ("
                          << c.output << "): skipped.\n";
            return;
        }
    }
    // The tile's nodes once the layout is known (every level of it).
    auto selectTile = [&](const std::vector<LevelTopology>& levels) -> const NodeMask* {
        if (c.tiles <= 0) return nullptr;
        tileMask = tileNodeMask(volumeLevels(levels), c.tiles, c.tile);
        return &tileMask;
    };

    GridPlacement placement;
    placement.spacing = c.spacing;
    placement.resolution = (c.spacing > 0 || c.resolution > 0 || c.nodes > 0) ? c.resolution : 16;
    if (!c.bounds.empty()) placement.bounds = toLocalBounds(parseBounds(c.bounds), scene.origin);
    if (c.nodes > 0) placement.spacing = spacingForNodeBudget(placement.bounds ? *placement.bounds : scene.bounds(), c.nodes);
    // Bytes per node while baking and writing: float coefficients plus OpenVDB's copy.
    // The anti-aliased pass also holds double accumulators per node (coefficients + 2 weights).
    // The least-squares fit adds its 27-entry Gram row, and its solve a prior and six CG
    // vectors of all 27 values per node (node_least_squares.h).
    const std::size_t lsq = c.fit == "least-squares" ? 27 + 7 * sh::kCoeffs * 3 : 0;
    const std::size_t extra = c.sampling == "antialiased" ? (sh::kCoeffs * 3 + 2 + lsq) * sizeof(double) : 0;
    const std::unique_ptr<Basis> basis = makeBasis(c.basis);  // the registry (basis.h)
    bins::BasisSpec basisSpec;
    const bool binned = bins::specFromVolume(basis->desc(), basisSpec);  // bins / moments: their own gather
    const bool generic = !binned && basis->desc().kind != "sh2";        // any other basis: the generic gather
    const std::size_t channels = std::size_t(basis->channelCount());
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
    options.probePasses = c.probePasses;
    // The point gather records depth moments from its own first rays (no extra rays).
    options.depthMoments = c.depthMoments && (c.depthRays == 0 || c.depthRays == c.rays);
    // A staged bake (tiles.h): this pass only, from the merged tiles of the stage before.
    Volume stageInput;
    options.stage = c.stage;
    // Every stage of one bake has the same options but --stage (and maybe --tiles): their hash
    // ties a stage file to the stages after it.
    std::string sameBake;
    if (c.stage >= 0) {
        std::string others;
        std::istringstream lines(c.parameters);
        for (std::string line; std::getline(lines, line);)
            if (line.compare(0, 8, "--stage=") != 0 && line.compare(0, 8, "--tiles=") != 0) others += line + "\n";
        sameBake = tileParamsHash(scene.contentHash(), others);
    }
    if (c.stage > 0) {
        stageInput = readProbeStage(c.stageInput);
        if (metaString(stageInput.meta, "probe_stage_params_hash") != sameBake)
            throw ValueError("'" + c.stageInput + "' is a stage of a bake with another scene or other options than --stage " +
                             std::to_string(c.stage) + " here");
        options.stageInput = &stageInput;
    }
    const bool lastStage = c.stage < 0 || c.stage == c.probePasses;

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
        bo.only = selectTile(layout.levels);
        volume = bakeBins(scene, tracer, layout, bo, &progress, &stats);
    } else if (generic) {  // any other basis of the registry (bake_basis.h)
        BasisBakeOptions bo;
        bo.raysPerNode = c.rays;
        bo.seed = c.seed;
        bo.threads = c.threads;
        bo.transport = options.transport;
        const LevelLayout layout = levels.kind == LayoutKind::Uniform
                                       ? uniformLayout(grid)
                                       : placeLevels(grid, scene.positions, scene.indices, levels, 2 * channels * 3 * sizeof(float));
        bo.only = selectTile(layout.levels);
        volume = bakeBasis(scene, tracer, layout, *basis, bo, &progress, &stats);
    } else if (levels.kind == LayoutKind::Uniform) {
        LevelTopology shape;
        shape.grid = grid;
        options.only = selectTile({shape});
        volume = bakeSelected(c, scene, tracer, grid, options, &progress, &stats);
    } else {
        levels.keepFinestGeometry = c.cullSolids;
        LevelLayout layout = placeLevels(grid, scene.positions, scene.indices, levels, 2 * sh::kCoeffs * 3 * sizeof(float));
        SolidCullStats cull;
        if (c.cullSolids) cullSolidNodes(layout, tracer, SolidCullOptions(), &cull);
        options.only = selectTile(layout.levels);
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
    if (direct.mode != DirectMode::Baked && lastStage) {
        bakeLightVisibility(scene, tracer, plan, direct, volume, &progress, c.tiles > 0 ? &tileMask : nullptr);
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
    DepthStats depthStats;
    if (c.depthMoments && !volume.hasDepth() && lastStage) {  // passes without the gather's hook (bake_depth.h)
        DepthOptions depthOptions;
        depthOptions.raysPerNode = c.depthRays > 0 ? c.depthRays : c.rays;
        depthOptions.seed = c.seed;
        depthOptions.threads = c.threads;
        depthOptions.only = c.tiles > 0 ? &tileMask : nullptr;
        bakeDepthMoments(tracer, volume, depthOptions, nullptr, &depthStats);
    }
    placeVolumeInWorld(volume, scene.origin);  // baked in the scene's local frame (scene_origin.h)
    volume.meta["scene_file"] = c.scene.path.empty() ? std::string("(bundled default) ") + defaultScenePath() : c.scene.path;
    volume.meta["sky"] = c.scene.skyMap.empty() ? (c.scene.sky.empty() ? std::string("0,0,0") : c.scene.sky)
                                                : "map:" + c.scene.skyMap;
    WriteOptions write;
    write.halfFloat = c.half;
    write.reproducible = c.reproducible;
    if (c.tiles > 0) {
        // The per-node errors of the uniform point gathers, for the merge's error summary.
        TileNodeStats nodeStats;
        if (volume.levels.size() == 1 && !binned) nodeStats.estimatedError = stats.estimatedError;
        if (!lastStage) {
            write.halfFloat = false;  // the next stage reads the reflected light exactly
            volume.meta["probe_stage_params_hash"] = sameBake;
        }
        writeTile(volume, tileMask, tileId, c.output, write, &nodeStats);
        uint64_t mine = 0;
        for (const auto& l : tileMask) mine += uint64_t(std::count(l.begin(), l.end(), uint8_t(1)));
        if (!c.quiet)
            std::cout << "Baked tile " << c.tile << " of " << c.tiles
                      << (c.stage >= 0 ? " (stage " + std::to_string(c.stage) + " of 0.." + std::to_string(c.probePasses) + ")" : "")
                      << ": " << mine << " of " << stats.nodes << " nodes, " << formatCount(double(stats.rays.total()))
                      << " rays in " << formatSeconds(stats.seconds) << ". Wrote " << c.output
                      << (lastStage ? " (merge the tiles with 'vdblight merge')"
                                    : " (merge this stage's tiles with 'vdblight merge', then bake stage " +
                                          std::to_string(c.stage + 1) + " with --stage-input MERGED.vdb)")
                      << ".\n";
        return;
    }
    writeVolume(volume, c.output, write);
    if (c.depthMoments && !c.quiet)
        std::cout << "Depth moments: " << (depthStats.rays ? formatCount(double(depthStats.rays)) + " first-hit rays in " +
                                                                 formatSeconds(depthStats.seconds)
                                                           : std::string("from the gather's own first hits"))
                  << " (" << depth::kBytesPerNode << " B per node at 8 bits).\n";

    if (!c.quiet) {
        std::cout << "Baked " << stats.nodes << " nodes (" << (volume.levels.size() > 1 ? "level 0: " : "") << grid.nx << " x " << grid.ny << " x " << grid.nz
                  << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' ("
                  << scene.triangleCount() << " triangles";
        std::cout << "; " << describeSceneSource(read);
        if (scene.stats.degenerateTrianglesSkipped)
            std::cout << ", " << scene.stats.degenerateTrianglesSkipped << " degenerate skipped";
        std::cout << ") with " << (c.targetError > 0 ? std::string("error-targeted")
                                   : binned || generic ? metaString(volume.meta, "rays_per_node") : std::to_string(c.rays))
                  << " rays per node"
                  << (c.probePasses > 0 ? " (+ " + std::to_string(c.probePasses) + " probe-to-probe pass" +
                                              (c.probePasses > 1 ? "es" : "") + ")"
                                        : std::string())
                  << " and "
                  << (c.scene.bounces >= kSafetyBounces ? std::string("all bounces (Russian roulette)")
                                                        : "up to " + std::to_string(c.scene.bounces) + " bounces")
                  << ": "
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
        else if (generic)
            std::cout << ". Wrote " << c.output << " (basis " << volume.basis.kind << ": " << basis->describe() << ", "
                      << channels << " Vec3f grids).\n";
        else
        std::cout << ". Wrote " << c.output << " (SH order 2 radiance, 9 Vec3f grids"
                  << (volume.levels[0].validity.empty() ? "" : " + validity") << ").\n";
        if (!stats.estimatedError.empty()) printNoiseSummary(stats, volume, grid);
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
    SceneLoadReport read;
    Scene scene = loadSceneFromOptions(c.scene, c.quiet, &read);
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
    write.reproducible = c.reproducible;
    if (c.compact) volume = iv::compact(volume);
    writeVolume(volume, c.output, write);
    if (!c.quiet) {
        std::cout << "Baked " << grid.nodeCount() << " nodes (" << grid.nx << " x " << grid.ny << " x " << grid.nz
                  << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' (" << scene.triangleCount()
                  << " triangles; " << describeSceneSource(read) << ") with " << formatCount(double(stats.photons)) << " photons: "
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

namespace {
void addBakeCommandTo(CLI::App& app, const std::shared_ptr<BakeCommand>& c) {
    CLI::App* cmd = app.add_subcommand("bake", "Bake a uniform SH order-2 irradiance volume into a .vdb");
    addSceneOptions(*cmd, c->scene);
    cmd->add_option("-o,--output", c->output, "Output .vdb file (written atomically)")->required();
    auto* spacing = cmd->add_option("--spacing", c->spacing, "Distance between nodes, in scene units");
    auto* resolution =
        cmd->add_option("--resolution", c->resolution, "Nodes along the longest axis (default 16)")->excludes(spacing);
    cmd->add_option("--bounds", c->bounds,
                    "Node box x0,y0,z0,x1,y1,z1 (default: scene bounds inset by half a spacing)");
    auto* rays = cmd->add_option("--rays", c->rays,
                                 "Ray directions per node and pass: a fixed budget (default 256; --quality high "
                                 "samples to an error target instead)")
                     ->check(CLI::Range(1u, 1u << 30));
    cmd->add_option("--quality", c->quality,
                    "preview: 16 nodes on the longest axis, 256 rays per node of full paths (sub-second, noisy "
                    "where light is hard to reach); default: about 16384 nodes in the scene box (16..64 on its "
                    "longest axis), 512 rays + one probe-to-probe pass of 512, depth moments (seconds; the "
                    "measured most accurate within 30 s, docs/methods.md); high: default's grid, each node "
                    "sampled to a relative standard error of 3 % (64..2048 rays) + two probe passes. Presets "
                    "apply to --method gather, --sampling point, --layout uniform, --basis sh2; other passes "
                    "take 16 nodes on the longest axis and the fixed --rays (default 256)")
        ->capture_default_str();
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
    auto* maxRays = cmd->add_option("--max-rays", c->maxRays,
                                    "error-targeted bakes: most rays a node may take (default 2048)");
    auto* minRays = cmd->add_option("--min-rays", c->minRays,
                                    "error-targeted bakes: rays of the first round (default 64)");
    cmd->add_flag("--sh-window", c->shWindow,
                  "gather: window the SH bands (1, 0.584, 0.135) so that irradiance is never negative (blurs; "
                  "docs/methods.md)");
    cmd->add_option("--basis", c->basis,
                    "Directional basis (docs/format.md): " + basisChoices())
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
    auto* probe = cmd->add_option("--probe-passes", c->probePasses,
                    "point gather: after a first pass of full paths, this many passes that end "
                    "each gathered path at its first hit with the previous pass's reflected light (probe-to-probe "
                    "bounces, DDGI-style; less noise where light comes through openings, some bias; docs/methods.md). "
                    "Default: 0 with --quality preview, 1 with default, 2 with high")
        ->check(CLI::Range(0, 8));  // default: the --quality preset's
    auto* depthOpt = cmd->add_flag("--depth-moments,!--no-depth-moments", c->depthMoments,
                  "gather with sh2: also store per-node depth moments, so that lookups do not interpolate across "
                  "walls (docs/methods.md, visibility-aware interpolation). Default: on with --quality default "
                  "and high where the preset applies, off otherwise");
    auto* depthRays = cmd->add_option("--depth-rays", c->depthRays,
                                      "--depth-moments: first-hit rays per node (default: as many as --rays)")
                          ->check(CLI::Range(1u, 1u << 20));
    cmd->add_flag("--reproducible,!--no-reproducible", c->reproducible,
                  "Same inputs, parameters and seed give the same file bytes on any machine and thread count: "
                  "the wall-clock time and thread count are printed, not stored (default); --no-reproducible "
                  "stores them as vdblight:bake_seconds and vdblight:threads");
    cmd->add_flag("-q,--quiet", c->quiet, "No progress bar and no summary");
    auto* tilesOpt = cmd->add_option("--tiles", c->tiles,
                    "Split the bake into this many tiles (bricks of 8^3 nodes of every level, balanced by cost) and "
                    "bake only --tile I of them; 'vdblight merge' puts the tile files together (docs/scaling.md). "
                    "A tile file that exists with the same scene and parameters is skipped (resumable)");
    auto* tileOpt = cmd->add_option("--tile", c->tile, "With --tiles N: the tile to bake, 0 .. N-1");
    auto* stageOpt = cmd->add_option("--stage", c->stage,
                    "With --tiles and probe-to-probe passes: bake only pass S (0 .. --probe-passes) of the tile; "
                    "stages after 0 read the merged tiles of the stage before (--stage-input); merging the last "
                    "stage's tiles gives the single bake (docs/scaling.md, staged bakes)");
    auto* stageInputOpt = cmd->add_option("--stage-input", c->stageInput,
                    "With --stage S > 0: the merged tiles of stage S-1 ('vdblight merge' of their tile files)");
    cmd->callback([c, cmd, spacing, resolution, invalidate, refine, levelsOpt, target, maxRays, minRays, refineDistance,
                   rays, probe, depthRays, depthOpt, tilesOpt, tileOpt, stageOpt, stageInputOpt] {
        if (c->depthMoments && c->method != "gather")
            throw ValueError("--depth-moments works with --method gather only (the irradiance-vector lookup does not weight by depth yet)");
        if (target->count() > 0 && !(c->targetError > 0 && c->targetError <= 1))
            throw ValueError("--target-error must be in (0, 1], got " + std::to_string(c->targetError));
        const QualityPreset preset = qualityPreset(c->quality);
        if (target->count() > 0 && rays->count() > 0)
            throw ValueError("--target-error and --rays exclude each other (an error target or a fixed budget)");
        // The quality's error target and probe passes apply where the point gather on a
        // uniform SH grid runs; other passes take the fixed --rays (default 256).
        // --basis through the registry (basis.h): a bad spec is refused here, before anything runs.
        const std::unique_ptr<Basis> basis = makeBasis(c->basis);
        bins::BasisSpec binsSpec;
        const bool sh2Basis = basis->desc().kind == "sh2", binsBasis = bins::specFromVolume(basis->desc(), binsSpec);
        const bool targetable = c->method == "gather" && c->sampling == "point" && invalidate->count() == 0 &&
                                parseLayoutKind(c->layout) == LayoutKind::Uniform && sh2Basis;
        if (target->count() == 0 && rays->count() == 0 && preset.targetError > 0 && targetable)
            c->targetError = preset.targetError;
        if (c->targetError > 0) {
            const QualityPreset caps = qualityPreset("high");
            if (minRays->count() == 0) c->minRays = caps.minRays;
            if (maxRays->count() == 0) c->maxRays = std::max(caps.maxRays, c->minRays);
        }
        if (probe->count() == 0 && targetable) c->probePasses = preset.probePasses;
        if (targetable && spacing->count() == 0 && resolution->count() == 0) c->nodes = preset.nodes;
        if (targetable && rays->count() == 0 && c->targetError == 0) c->rays = preset.rays;
        if (targetable && depthOpt->count() == 0) c->depthMoments = preset.depthMoments;
        if (depthRays->count() > 0 && !c->depthMoments) throw ValueError("--depth-rays needs --depth-moments");
        if (c->planOnly) {  // vdblight slurm: refuse what would not tile before writing any script
            BakeCommand staged = *c;
            staged.stage = 0;
            const std::string why = untileable(staged);
            if (!why.empty()) throw ValueError(why);
            return;
        }
        // After the --quality preset, which may add an error target or probe passes.
        if ((tilesOpt->count() > 0) != (tileOpt->count() > 0)) throw ValueError("--tiles and --tile go together");
        if (tilesOpt->count() > 0) {
            if (c->tiles < 1) throw ValueError("--tiles must be at least 1, got " + std::to_string(c->tiles));
            if (c->tile < 0 || c->tile >= c->tiles)
                throw ValueError("--tile must be between 0 and " + std::to_string(c->tiles - 1) + ", got " + std::to_string(c->tile));
            const std::string why = untileable(*c);
            if (!why.empty()) throw ValueError(why);
            c->parameters = bakeParameters(*cmd);
        }
        if (stageOpt->count() > 0) {
            if (tilesOpt->count() == 0) throw ValueError("--stage needs --tiles and --tile (one stage of a tiled bake; --tiles 1 --tile 0 for all nodes)");
            if (c->probePasses == 0) throw ValueError("--stage needs probe-to-probe passes (a bake without them has one stage: leave --stage out)");
            if (c->stage < 0 || c->stage > c->probePasses)
                throw ValueError("--stage must be between 0 and " + std::to_string(c->probePasses) +
                                 " (one stage per pass: the first pass and " + std::to_string(c->probePasses) +
                                 " probe-to-probe passes), got " + std::to_string(c->stage));
        }
        if ((c->stage > 0) != (stageInputOpt->count() > 0))
            throw ValueError(c->stage > 0 ? "--stage " + std::to_string(c->stage) + " needs --stage-input (the merged tiles of stage " +
                                                std::to_string(c->stage - 1) + ")"
                                          : std::string("--stage-input needs --stage 1 or later"));
        if (c->shWindow && (c->method != "gather" || !sh2Basis))
            throw ValueError("--sh-window applies to --method gather with --basis sh2 only");
        if (probe->count() > 0 && c->probePasses > 0 && !targetable)
            throw ValueError("--probe-passes works with --method gather, --sampling point, --layout uniform and "
                             "--basis sh2 only");
        if (c->targetError > 0 && (c->minRays < 2 || c->maxRays < c->minRays))
            throw ValueError("--min-rays must be at least 2 and --max-rays at least --min-rays, got " +
                             std::to_string(c->minRays) + " and " + std::to_string(c->maxRays));
        if (c->targetError == 0 && (maxRays->count() > 0 || minRays->count() > 0))
            throw ValueError("--max-rays and --min-rays need an error-targeted bake (--target-error, or --quality "
                             "default/high without --rays)");
        if (target->count() > 0 && (c->method != "gather" || c->sampling != "point" || invalidate->count() > 0 ||
                                    parseLayoutKind(c->layout) != LayoutKind::Uniform ||
                                    !sh2Basis))
            throw ValueError("--target-error works with --method gather, --sampling point, --layout uniform and --basis sh2 only");
        const LayoutKind kind = parseLayoutKind(c->layout);
        if (!sh2Basis && (c->method != "gather" || c->sampling != "point" || invalidate->count() > 0))
            throw ValueError("--basis " + (binsBasis ? std::string("bins/moment") : c->basis) +
                             " works with --method gather and --sampling point only");
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
        if (c->cullSolids && (kind == LayoutKind::Uniform || !sh2Basis))
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
}  // namespace

void addBakeCommand(CLI::App& app) { addBakeCommandTo(app, std::make_shared<BakeCommand>()); }

int bakeStageCount(const std::string& scene, const std::vector<std::string>& bakeArgs) {
    CLI::App app;
    auto c = std::make_shared<BakeCommand>();
    c->planOnly = true;
    addBakeCommandTo(app, c);
    std::vector<std::string> words = {"vdblight", "bake", scene};
    words.insert(words.end(), bakeArgs.begin(), bakeArgs.end());
    words.insert(words.end(), {"-o", "plan.vdb"});
    std::vector<const char*> argv;
    for (const std::string& w : words) argv.push_back(w.c_str());
    try {
        app.parse(int(argv.size()), argv.data());
    } catch (const CLI::ParseError& e) {
        throw ValueError(std::string("bake options: ") + e.what());
    }
    return c->probePasses + 1;
}

}  // namespace vdblight::app
