// vdblight bake [SCENE] -o OUT.vdb: parses the options into a BakeRequest and calls the
// library's bakeToFile (bake_volume.h), which selects the pass (pass.h), checks the options,
// bakes and writes the file; the pass writes the summary printed (bakeSummary).
#include <algorithm>
#include <deque>
#include <iostream>
#include <string>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bake/bake.h"
#include "vdblight/basis/basis.h"
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
    int splitLights = 1;           // --direct occlusion: each quad light as K x K pieces
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

/// Declares every option the passes declare (passOptionTable, pass.h), once per name, in the
/// order of the registry, with its help, its default and the passes that take it.
void addPassOptions(CLI::App& cmd, BakeCommand& c) {
    for (const PassOptionEntry& entry : passOptionTable()) {
        BakeCommand::PassFlag& f = c.passOptions.emplace_back(BakeCommand::PassFlag{entry.option, {}, false, nullptr});
        const std::string name = "--" + f.option.name;
        if (f.option.flag)
            f.cli = cmd.add_flag(f.option.negatable ? name + ",!--no-" + f.option.name : name, f.on, entry.help);
        else
            f.cli = cmd.add_option(name, f.text, entry.help)
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
        if (f.cli->count() > 0) r.params.setText(f.option.name, f.option.flag ? (f.on ? "true" : "false") : f.text);
    r.direct = c.direct;
    r.directLights = c.directLights;
    r.splitLights = c.splitLights;
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

void run(const BakeCommand& c, const BakeRequest& request) {
    checkBakeRequest(request);  // every option, before anything is loaded
    checkOutputWritable(c.output);
    SceneLoadReport read;
    const Scene scene = loadSceneFromOptions(c.scene, c.quiet, &read);
    ProgressBar progress(c.quiet);
    BakeReport report;
    const Volume volume = bakeToFile(scene, request, c.output, &progress, &report);
    if (!c.quiet) std::cout << bakeSummary({scene, describeSceneSource(read), c.output, request, report, volume});
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
    cmd->add_option("--split-lights", c->splitLights,
                    "--direct occlusion: list each chosen quad light as K x K pieces (1..4), each with its own "
                    "visibility and edges: closer to exact where a blocker hides part of a light that a surface "
                    "sees at a slant (the accuracy benchmark's Cornell box: the default 0.9 -> 0.7 % RMS), for K^2 x the lights' channels "
                    "and lookup work (docs/shadow_visibility.md)")
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
            c->stages = tiledBakeStages(toRequest(*c, g));
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
