// vdblight bake [SCENE] -o OUT.vdb: parses the options into a BakeRequest and calls the
// library's bakeToFile (bake_volume.h), which selects the pass (pass.h), checks the options,
// bakes and writes the file; this file only prints what the bake did.
#include <algorithm>
#include <cmath>
#include <deque>
#include <iostream>
#include <string>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bake/bake.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/volume/volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/scene/scene.h"

namespace vdblight::app {

namespace {
struct BakeCommand {
    SceneOptions scene;
    std::string output;
    double spacing = 0;
    int resolution = 0;
    std::string bounds;
    uint64_t seed = 1;
    int threads = 0;
    bool half = false;
    bool quiet = false;
    std::string method = "gather";
    std::string sampling = "point";  // point | antialiased (bake_antialiased.h)
    std::string layout = "uniform";
    std::string quality = "default";  // preview | default | high (resolveBakeRequest)
    std::string basis;  // a spec of the basis registry (basis.h): sh2, sh:N, bins:R, moment:n[:R]; empty: the preset's
    std::string direct;            // baked | runtime | occlusion (bake_direct.h); empty: the default
    int directLights = 4;          // --direct occlusion: lights with a visibility channel
    bool shadowEdges = true;       // --direct occlusion: their shadow edges (shadow_edges.h)
    bool reproducible = true;   // leave run-specific metadata out of the file (vdb_io.h)
    int tiles = 0;              // > 0: bake only tile `tile` of this many (tiles.h)
    int tile = -1;
    int stage = -1;             // >= 0: only this pass of a bake with probe passes (tiles.h, "Staged bakes")
    std::string stageInput;     // stage > 0: the merged tiles of the stage before
    std::string parameters;     // every option that changes the result, for the tile hash
    bool planOnly = false;      // bakeStageCount: parse and resolve the presets, bake nothing
    int stages = 1;             // bakeStageCount's answer
    /// The passes' own options (pass.h), one command-line option each: the table of passes.
    struct PassFlag {
        PassOption option;
        std::vector<std::string> passes;  // that declare it
        std::string text;
        bool on = false;
        CLI::Option* cli = nullptr;
    };
    std::deque<PassFlag> passOptions;
};

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

/// The bake's own noise estimate, honestly labelled: per node the relative standard error of
/// its mean irradiance from the sample variance, over the nodes that lookups in free space read
/// (error_summary.h); what it does not measure is said, and the nodes left out are counted.
void printNoiseSummary(const BakeStats& stats, const Volume& volume, const GridSpec& grid) {
    auto percent = [](double e) { return std::to_string(int(std::lround(e * 1000.0)) / 10) + "." +
                                         std::to_string(int(std::lround(e * 1000.0)) % 10) + " %"; };
    const std::vector<float>& err = stats.estimatedError;
    std::size_t worst = err.size();  // the largest error a free-space lookup reads
    for (std::size_t n = 0; n < err.size(); ++n)
        if (err[n] >= 0.0f && (worst == err.size() || err[n] > err[worst])) worst = n;
    const std::size_t inside = nodesInsideSolids(err);
    if (worst == err.size()) {
        std::cout << "Noise per node: every one of the " << inside << " nodes lies inside solids.\n";
        return;
    }
    std::cout << "Noise per node (relative standard error of its irradiance, from the sample variance"
              << (inside ? ", over the nodes that lookups in free space read" : "") << "): p50 "
              << percent(stats.errorQuantile(0.5)) << ", p95 " << percent(stats.errorQuantile(0.95)) << ", max "
              << percent(err[worst]) << " at node " << worst % grid.nx << "," << (worst / grid.nx) % grid.ny << ","
              << worst / (std::size_t(grid.nx) * grid.ny);
    if (volume.meta.count("nodes_at_max_rays"))
        std::cout << "; " << metaString(volume.meta, "nodes_at_max_rays") << " nodes stopped at the ray cap above the target";
    std::cout << ". Not included: SH truncation, interpolation between nodes.\n";
    if (inside)
        std::cout << inside << " nodes inside solids (most of their rays hit back faces), not read by free-space "
                     "lookups (the depth weights keep them out).\n";
}

/// The shared options whose absence means "the default" (the passes' own are in
/// BakeCommand::passOptions).
struct GivenOptions {
    CLI::Option *spacing, *resolution, *tiles, *tile, *stage;
};

template <typename T>
std::optional<T> given(const CLI::Option* option, const T& value) {
    return option->count() > 0 ? std::optional<T>(value) : std::nullopt;
}

std::string choiceList(const std::vector<std::string>& words) {
    std::string text;
    for (const std::string& w : words) text += (text.empty() ? "" : "|") + w;
    return text;
}

/// Declares every option the passes declare (pass.h), once per name, in the order of the
/// registry, with the first declaration's help, its default and the passes that take it.
void addPassOptions(CLI::App& cmd, BakeCommand& c) {
    for (const Pass* pass : passRegistry())
        for (const PassOption& o : pass->options()) {
            auto same = std::find_if(c.passOptions.begin(), c.passOptions.end(),
                                     [&](const BakeCommand::PassFlag& f) { return f.option.name == o.name; });
            if (same != c.passOptions.end()) {
                same->passes.push_back(pass->name());
                continue;
            }
            c.passOptions.push_back({o, {pass->name()}, {}, false, nullptr});
        }
    for (BakeCommand::PassFlag& f : c.passOptions) {
        std::string takers;
        for (const std::string& p : f.passes) takers += (takers.empty() ? "" : ", ") + p;
        const std::string name = "--" + f.option.name;
        const std::string help = f.option.help + " [pass" + (f.passes.size() > 1 ? "es " : " ") + takers + "]";
        if (f.option.flag)
            f.cli = cmd.add_flag(f.option.negatable ? name + ",!--no-" + f.option.name : name, f.on, help);
        else
            f.cli = cmd.add_option(name, f.text, help)
                        ->type_name(f.option.choices.empty() ? "NUMBER" : choiceList(f.option.choices))
                        ->default_str(f.option.defaultValue);
    }
}

BakeRequest toRequest(const BakeCommand& c, const GivenOptions& g) {
    BakeRequest r;
    r.method = c.method;
    r.sampling = c.sampling;
    r.layout = c.layout;
    r.basis = c.basis;
    r.quality = c.quality;
    r.seed = c.seed;
    r.threads = c.threads;
    r.transport = transportFromOptions(c.scene);
    r.spacing = given(g.spacing, c.spacing);
    r.resolution = given(g.resolution, c.resolution);
    if (!c.bounds.empty()) r.bounds = parseBounds(c.bounds);
    for (const BakeCommand::PassFlag& f : c.passOptions)
        if (f.cli->count() > 0) f.option.setText(r, f.option.flag ? (f.on ? "true" : "false") : f.text);
    r.direct = c.direct;
    r.directLights = c.directLights;
    r.shadowEdges = c.shadowEdges;
    r.halfFloat = c.half;
    r.reproducible = c.reproducible;
    r.tiles = given(g.tiles, c.tiles);
    r.tile = given(g.tile, c.tile);
    r.stage = given(g.stage, c.stage);
    r.stageInput = c.stageInput;
    r.tileParameters = c.parameters;
    r.sceneFile = c.scene.path.empty() ? std::string("(bundled default) ") + defaultScenePath() : c.scene.path;
    r.sky = c.scene.skyMap.empty() ? (c.scene.sky.empty() ? std::string("0,0,0") : c.scene.sky) : "map:" + c.scene.skyMap;
    return r;
}

void printPhotonSummary(const BakeCommand& c, const Scene& scene, const SceneLoadReport& read, const BakeReport& report) {
    const GridSpec& grid = report.grid;
    const PhotonStats& stats = *report.photons;
    std::cout << "Baked " << grid.nodeCount() << " nodes (" << grid.nx << " x " << grid.ny << " x " << grid.nz
              << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' (" << scene.triangleCount()
              << " triangles; " << describeSceneSource(read) << ") with " << formatCount(double(stats.photons)) << " photons: "
              << formatCount(double(stats.segments)) << " segments, " << formatCount(double(stats.crossings))
              << " face crossings, " << formatCount(double(stats.rays.total())) << " rays in "
              << formatSeconds(stats.seconds) << " ("
              << formatCount(stats.seconds > 0 ? double(stats.photons) / stats.seconds : 0.0) << " photons/s). Wrote "
              << c.output
              << (report.resolved.compact ? " (compact irradiance vectors: colour + direction, 12 half-float Vec3 grids).\n"
                            : " (irradiance vectors, 18 Vec3f grids).\n");
    if (report.depth)  // the default's (--no-depth-moments: none)
        std::cout << "Depth moments: " << formatCount(double(report.depth->rays)) << " first-hit rays in "
                  << formatSeconds(report.depth->seconds) << " (" << depth::kBytesPerNode << " B per node at 8 bits).\n";
}

/// What the pass did before the file was written (error target, layout, direct light).
void printPassLines(const BakeReport& report) {
    const BakeRequest& r = report.resolved;
    if (report.adaptive && !report.adaptive->estimatedError.empty() && !r.tiles) {
        const AdaptiveStats& as = *report.adaptive;
        const uint32_t maxRays = *r.maxRays;
        std::cout << "Error-targeted: relative standard error of mean irradiance p50 " << as.errorQuantile(0.5)
                  << ", p95 " << as.errorQuantile(0.95) << ", max " << as.errorQuantile(1.0) << " (target "
                  << *r.targetError << ", " << as.nodesAtMax << " nodes stopped at --max-rays " << maxRays << "); "
                  << formatCount(double(as.samples)) << " gathered rays, "
                  << formatCount(double(as.samples) / double(as.nodes)) << " per node, "
                  << formatCount(double(uint64_t(maxRays) * as.nodes - as.samples)) << " ("
                  << int(100.0 * (1.0 - double(as.samples) / (double(maxRays) * as.nodes)))
                  << " %) saved against " << maxRays << " rays on every node.\n";
    }
    if (report.cull)
        std::cout << "Solid culling: " << report.cull->nodesCulled << " of " << report.cull->nodesBefore
                  << " nodes left out (inside closed solids: " << report.cull->solidRegions << " of " << report.cull->regions
                  << " regions of geometry-free cells, " << report.cull->solidCells << " solid cells).\n";
    if (report.layout) {
        const LayoutSummary& l = *report.layout;
        std::cout << "Layout " << r.layout << ": " << l.levels << " levels refined by " << l.refine << ", " << l.nodes
                  << " nodes (" << report.stats.seamNodes << " seam nodes set from the coarser level) vs "
                  << l.denseEquivalentNodes << " in a dense grid at the finest spacing ("
                  << 100.0 * (1.0 - double(l.nodes) / l.denseEquivalentNodes) << " % saved"
                  << (r.cullSolids ? ", " + std::to_string(l.culledNodes) + " of them culled inside solids" : "") << ").\n";
    }
    const DirectPlan& plan = report.direct;
    if (plan.mode != DirectMode::Baked && report.lastStage) {
        std::cout << "Direct light (" << directModeName(plan.mode) << "): " << plan.lights.size() << " of "
                  << plan.sceneLightCount << " lights kept out of the SH";
        if (plan.mode == DirectMode::Occlusion) {
            std::cout << ", with visibility channels; measured share of the direct light:";
            for (double share : plan.contribution) std::cout << ' ' << int(100.0 * share + 0.5) << " %";
        }
        std::cout << ".\n";
    }
}

void printSummary(const BakeCommand& c, const Scene& scene, const SceneLoadReport& read, const BakeReport& report,
                  Volume& volume) {
    const BakeRequest& r = report.resolved;
    const GridSpec& grid = report.grid;
    const LevelsBakeStats& stats = report.stats;
    const bool binned = report.pass->name() == "bins";
    if (*r.depthMoments)
        std::cout << "Depth moments: " << (report.depth && report.depth->rays
                                               ? formatCount(double(report.depth->rays)) + " first-hit rays in " +
                                                     formatSeconds(report.depth->seconds)
                                               : std::string("from the gather's own first hits"))
                  << " (" << depth::kBytesPerNode << " B per node at 8 bits).\n";
    std::cout << "Baked " << stats.nodes << " nodes (" << (volume.levels.size() > 1 ? "level 0: " : "") << grid.nx << " x "
              << grid.ny << " x " << grid.nz << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' ("
              << scene.triangleCount() << " triangles";
    std::cout << "; " << describeSceneSource(read);
    if (scene.stats.degenerateTrianglesSkipped)
        std::cout << ", " << scene.stats.degenerateTrianglesSkipped << " degenerate skipped";
    std::cout << ") with " << (r.targetError ? std::string("error-targeted")
                               : binned      ? metaString(volume.meta, "rays_per_node")
                                             : std::to_string(*r.rays))
              << " rays per node"
              << (*r.probePasses > 0 ? " (+ " + std::to_string(*r.probePasses) + " probe-to-probe pass" +
                                           (*r.probePasses > 1 ? "es" : "") + ")"
                                     : std::string())
              << " and "
              << (c.scene.bounces >= kSafetyBounces ? std::string("all bounces (Russian roulette)")
                                                    : "up to " + std::to_string(c.scene.bounces) + " bounces")
              << ": " << formatCount(double(stats.rays.total())) << " rays (" << formatCount(double(stats.rays.intersect))
              << " closest-hit, " << formatCount(double(stats.rays.occluded)) << " shadow) in "
              << formatSeconds(stats.seconds) << ", " << formatCount(stats.raysPerSecond()) << " rays/s on "
              << int64_t(std::get<int64_t>(volume.meta["threads"])) << " threads";
    if (r.sampling == "antialiased") std::cout << " (sampling antialiased, domain " << metaString(volume.meta, "domain") << ")";
    if (volume.meta.count("nodes_dilated"))
        std::cout << "; " << metaString(volume.meta, "nodes_dilated") << " nodes filled by dilation";
    if (binned && volume.meta.count("samples_per_bin"))
        std::cout << ". Wrote " << c.output << " (basis " << volume.basis.kind << ", "
                  << volume.basis.channelCount() << " Vec3f grids, "
                  << metaString(volume.meta, "samples_per_bin") << " samples per bin).\n";
    else if (binned || !volume.basis.isSh2())  // a registry basis (basis.h): generic or point gather
        std::cout << ". Wrote " << c.output << " (basis " << volume.basis.kind << ": " << makeBasis(r.basis)->describe()
                  << ", " << volume.basis.channelCount() << " Vec3f grids).\n";
    else
        std::cout << ". Wrote " << c.output << " (SH order 2 radiance, 9 Vec3f grids"
                  << (volume.levels[0].validity.empty() ? "" : " + validity") << ").\n";
    if (!stats.estimatedError.empty()) printNoiseSummary(stats, volume, grid);
}

void run(const BakeCommand& c, const BakeRequest& request) {
    checkBakeRequest(request);  // every option, before anything is loaded
    checkOutputWritable(c.output);
    SceneLoadReport read;
    const Scene scene = loadSceneFromOptions(c.scene, c.quiet, &read);
    ProgressBar progress(c.quiet);
    BakeReport report;
    Volume volume = bakeToFile(scene, request, c.output, &progress, &report);
    if (c.quiet) return;
    if (report.skipped) {
        std::cout << "Tile " << c.tile << " of " << c.tiles << " is already baked with the same scene and parameters ("
                  << c.output << "): skipped.\n";
        return;
    }
    if (report.photons && report.photonSums) {
        const PhotonSums& sums = *report.photonSums;
        std::cout << "Baked tile " << c.tile << " of " << c.tiles << ": photon batches " << sums.firstBatch << ".."
                  << sums.endBatch - 1 << " of " << sums.batches << " (" << formatCount(double(report.photons->photons))
                  << " of " << formatCount(double(report.resolved.photons.value_or(0))) << " photons), "
                  << formatCount(double(report.photons->rays.total())) << " rays in "
                  << formatSeconds(report.photons->seconds)
                  << (report.depth ? "; depth moments of its share of the nodes, " + formatCount(double(report.depth->rays)) +
                                         " first-hit rays in " + formatSeconds(report.depth->seconds)
                                   : std::string())
                  << ". Wrote " << c.output
                  << " (the whole grid's sums of these batches; merge the tiles with 'vdblight merge').\n";
        return;
    }
    if (report.photons) return printPhotonSummary(c, scene, read, report);
    printPassLines(report);
    const BakeRequest& r = report.resolved;
    if (r.tiles) {
        const int stage = r.stage.value_or(-1);
        std::cout << "Baked tile " << c.tile << " of " << c.tiles
                  << (stage >= 0 ? " (stage " + std::to_string(stage) + " of 0.." + std::to_string(*r.probePasses) + ")" : "")
                  << ": " << report.tileNodes << " of " << report.stats.nodes << " nodes, "
                  << formatCount(double(report.stats.rays.total())) << " rays in " << formatSeconds(report.stats.seconds)
                  << ". Wrote " << c.output
                  << (report.lastStage ? " (merge the tiles with 'vdblight merge')"
                                       : " (merge this stage's tiles with 'vdblight merge', then bake stage " +
                                             std::to_string(stage + 1) + " with --stage-input MERGED.vdb)")
                  << ".\n";
        return;
    }
    printSummary(c, scene, read, report, volume);
}
}  // namespace

namespace {
void addBakeCommandTo(CLI::App& app, const std::shared_ptr<BakeCommand>& c) {
    // The description and the presets' help come from the library's resolution of the presets
    // (describeQuality), so that they say what the code does (issue 29).
    CLI::App* cmd = app.add_subcommand("bake", "Bake an irradiance volume into a .vdb; by default " + describeQuality("default"));
    addSceneOptions(*cmd, c->scene);
    cmd->add_option("-o,--output", c->output, "Output .vdb file (written atomically)")->required();
    auto* spacing = cmd->add_option("--spacing", c->spacing, "Distance between nodes, in scene units (default: the --quality preset's grid)");
    auto* resolution = cmd->add_option("--resolution", c->resolution,
                                       "Nodes along the longest axis (default: the --quality preset's grid)")
                           ->excludes(spacing);
    cmd->add_option("--bounds", c->bounds,
                    "Node box x0,y0,z0,x1,y1,z1 (default: scene bounds inset by half a spacing)");
    std::string presets;
    for (const std::string& q : qualityNames()) presets += q + ": " + describeQuality(q) + ". ";
    cmd->add_option("--quality", c->quality,
                    presets + "Presets apply to --method gather, --sampling point, --layout uniform, --basis sh2 or "
                    "sh:N (docs/methods.md, \"The default bake\"); other passes take " +
                        std::to_string(kDefaultResolution) +
                        " nodes on the longest axis and the fixed --rays; --target-error replaces the rays by an "
                        "error target (SH order 2)")
        ->capture_default_str();
    cmd->add_option("--seed", c->seed, "Random seed (same seed, same bits, any thread count)")->capture_default_str();
    cmd->add_option("--threads", c->threads, "Worker threads (0 = all cores)")->capture_default_str()->check(CLI::Range(0, 4096));
    cmd->add_flag("--half", c->half, "Store the grids as 16-bit floats");
    cmd->add_option("--method", c->method, "gather (SH radiance at each node; --basis for others) or photons (irradiance vectors, Pacanowski et al.)")
        ->capture_default_str();
    cmd->add_option("--sampling", c->sampling,
                    "point: project at the nodes; antialiased: trilinear-weighted origins over each cell "
                    "(Kontkanen-Laine eq. 6; --rays is then rays per cell)")
        ->capture_default_str();
    cmd->add_option("--layout", c->layout, "Node layout: uniform, bilevel (Greger et al.) or adaptive (n levels)")
        ->capture_default_str();
    cmd->add_option("--basis", c->basis,
                    "Directional basis (docs/format.md): " + basisChoices() +
                        ". Default: the --quality preset's where its point gather runs (see --quality; SH order 4 "
                        "holds a bright opening seen from a dark room, docs/methods.md), sh2 for every other pass");
    cmd->add_option("--direct", c->direct,
                    "Direct light: baked (in the SH), runtime (SH holds indirect light; the file lists the lights for "
                    "the run time to add) or occlusion (plus per-node visibility of the --direct-lights most important "
                    "lights, added exactly at lookup). Default: occlusion for the uniform SH point gather of a scene "
                    "with lights, baked otherwise");
    cmd->add_option("--direct-lights", c->directLights, "--direct occlusion: lights with a visibility channel (1..16)")
        ->capture_default_str();
    cmd->add_flag("--shadow-edges,!--no-shadow-edges", c->shadowEdges,
                  "--direct occlusion: also store each listed light's shadow edges, which keep its shadows sharp between "
                  "the nodes (default; docs/shadow_visibility.md); --no-shadow-edges: the visibility channels alone");
    cmd->add_flag("--reproducible,!--no-reproducible", c->reproducible,
                  "Same inputs, parameters and seed give the same file bytes on any machine and thread count: "
                  "the wall-clock time and thread count are printed, not stored (default); --no-reproducible "
                  "stores them as vdblight:bake_seconds and vdblight:threads");
    cmd->add_flag("-q,--quiet", c->quiet, "No progress bar and no summary");
    auto* tilesOpt = cmd->add_option("--tiles", c->tiles,
                    "Split the bake into this many tiles (bricks of 8^3 nodes of every level, balanced by cost; "
                    "--method photons: runs of the photon batches, at most as many as batches) and "
                    "bake only --tile I of them; 'vdblight merge' puts the tile files together (docs/scaling.md). "
                    "A tile file that exists with the same scene and parameters is skipped (resumable)");
    auto* tileOpt = cmd->add_option("--tile", c->tile, "With --tiles N: the tile to bake, 0 .. N-1");
    auto* stageOpt = cmd->add_option("--stage", c->stage,
                    "With --tiles and probe-to-probe passes: bake only pass S (0 .. --probe-passes) of the tile; "
                    "stages after 0 read the merged tiles of the stage before (--stage-input); merging the last "
                    "stage's tiles gives the single bake (docs/scaling.md, staged bakes)");
    cmd->add_option("--stage-input", c->stageInput,
                    "With --stage S > 0: the merged tiles of stage S-1 ('vdblight merge' of their tile files)");
    addPassOptions(*cmd, *c);
    std::string passes = "Passes (the options select one; each takes the options marked with its name):";
    for (const Pass* p : passRegistry()) passes += "\n  " + p->name() + ": " + p->description();
    cmd->footer(passes);
    const GivenOptions g{spacing, resolution, tilesOpt, tileOpt, stageOpt};
    cmd->callback([c, cmd, g] {
        if (c->planOnly) {  // vdblight slurm: refuse what would not tile before writing any script
            BakeRequest staged = resolveBakeRequest(toRequest(*c, g));
            if (staged.depthRays && !*staged.depthMoments) throw ValueError("--depth-rays needs --depth-moments");
            staged.stage = 0;
            const std::string why = findPass(staged.pass).untileable(staged);
            if (!why.empty()) throw ValueError(why);
            c->stages = *staged.probePasses + 1;
            return;
        }
        // Every option that changes the result, for the tile hash.
        if (g.tiles->count() > 0) c->parameters = bakeParameters(*cmd);
        run(*c, toRequest(*c, g));
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
    return c->stages;
}

}  // namespace vdblight::app
