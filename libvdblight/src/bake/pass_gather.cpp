// The point gather as a Pass (bake.h): SH order 2 (or real SH of order N, `--basis sh:N`)
// at the nodes of a uniform grid, with probe-to-probe passes, depth moments from its own
// first hits, direct light out of the SH and, as an option (sh2), the engines' back-face
// invalidation (bake_antialiased.h).
#include "passes.h"

#include "direction_guide.h"
#include "pass_options.h"
#include "surface_bins.h"
#include "bake/bake_antialiased.h"
#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "basis/sh.h"

namespace vdblight::bake_detail {

namespace {
class GatherPass : public Pass {
public:
    std::string name() const override { return "gather"; }
    std::string description() const override {
        return "point gather: SH order 2 (or sh:N) of the incident radiance at each node of a uniform grid (bake.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesDirectLight() const override { return true; }
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};
}  // namespace

namespace {
/// --node-filter N (node_filter.h). 0 is what every other pass does: only more is refused there.
PassOption nodeFilterOption() {
    PassOption o = numberOption<int>("node-filter",
                 "passes of the filter across nodes after the bake: a 3x3x3 kernel weighted by the depth "
                 "moments (not across walls) and by the nodes' error estimates (differences the noise does "
                 "not explain are kept); less noise, some blur (docs/time_to_accuracy.md)",
                 presetNumbers("node-filter"), 0, 8,
                 "--node-filter works with the uniform point gather (--method gather, --sampling point, "
                 "--layout uniform, a fixed budget) only");
    o.zeroIsUnset = true;
    return o;
}
/// --guide-probe-directions, --blend-first-pass, --extra-cache-paths, --first-pass-by-error,
/// --probe-pass-by-error (issue 32): what the preview and `fast` add to their one probe pass. The
/// first two tile (a stage carries pass 0's map and values: stage_carry.h); the others choose
/// rays by every node's pass at once, so a tiled bake leaves them off, and refuses them when
/// given (`tiled` false).
PassOption previewProbeFlag(const std::string& name, const std::string& help, bool tiled = false) {
    PassOption o = flagOption(name,
                              help + ". Default: " + presetValues([name](const BakeRequest& r) {
                                  return std::string(r.params.get<bool>(name) ? "on" : "off");
                              }) + (tiled ? std::string(", tiled bakes too") : std::string(" (never in a tiled bake)")) +
                                  "; --no-" + name + " turns it off",
                              "--" + name + " works with the uniform point gather with probe passes only");
    o.negatable = true;  // the preview's default is on
    o.defaultValue = "the --quality preset's";
    return o;
}
}  // namespace

std::vector<PassOption> GatherPass::options() const {
    return {raysOption("Ray directions per node and pass: a fixed budget (--target-error samples to an error target "
                       "instead; antialiased: rays per cell; bins, moments: rounded up to a multiple of the bin count; "
                       "other bases such as sh:N on bilevel/adaptive layouts: to 2 R^2, R = round(sqrt(rays / 2)))"),
            probePassesOption(),
            wordOption("probe-cache",
                       "what the probe pass reads at a path's first hit: nodes = the nodes' reflected light around "
                       "it (DDGI-style), surface = irradiance samples that the first pass's own paths took at the "
                       "surfaces (less bias near walls and openings; docs/methods.md). Default: surface with exactly "
                       "one probe pass (the presets'), nodes otherwise",
                       "surface", {"nodes", "surface"},
                       "--probe-cache works with --method gather --sampling point only"),
            numberOption<double>("invalidate-backface",
                         "nodes whose rays hit back-faces more than this fraction (0..1) are replaced by dilating "
                         "valid neighbours (the engines' heuristic)",
                         "off", 0, 1,
                         "--invalidate-backface applies to --sampling point only", "in [0, 1]"),
            nodeFilterOption(),
            previewProbeFlag("guide-probe-directions",
                             "draw the probe pass's directions from the first pass's light per direction, pooled "
                             "over neighbouring nodes and weighted back (unbiased; less noise through doors; "
                             "docs/time_to_accuracy.md)",
                             true),
            previewProbeFlag("blend-first-pass",
                             "blend the first pass's values into the probe pass's by their noise estimates "
                             "(one probe pass; docs/time_to_accuracy.md)",
                             true),
            previewProbeFlag("extra-cache-paths",
                             "trace more first-pass paths from the nodes whose first-pass noise is far above the "
                             "median, for the surface probe cache only (less noise in a room lit through a door; "
                             "--probe-cache surface; docs/time_to_accuracy.md)"),
            numberOption<uint32_t>("extra-cache-paths-per-node",
                                   "the paths that --extra-cache-paths traces from each such node",
                                   presetNumbers("extra-cache-paths-per-node"), 1, 1 << 20,
                                   "--extra-cache-paths-per-node works with the uniform point gather with probe passes only"),
            numberOption<uint32_t>("probe-light-samples",
                                   "emitter samples at the end of each probe-pass path, where the cache ends it at its "
                                   "first hit (each weighted 1 / N; a shadow ray costs far less than the ray and the "
                                   "cache read; docs/time_to_accuracy.md)",
                                   presetNumbers("probe-light-samples"), 1, 64,
                                   "--probe-light-samples works with the uniform point gather with probe passes only"),
            previewProbeFlag("first-pass-by-error",
                             "trace the first pass in two rounds at the same total rays: a quarter at every node, "
                             "then the rest by the nodes' noise estimates (docs/time_to_accuracy.md)"),
            previewProbeFlag("probe-pass-by-error",
                             "trace the probe pass in two rounds likewise, by its own noise estimates (one probe "
                             "pass; docs/time_to_accuracy.md)"),
            depthMomentsOption(), depthRaysOption(), shWindowOption()};
}

void GatherPass::validate(const BakeRequest& request) const {
    const PassParameters& p = request.params;
    if (p.has("invalidate-backface") && p.find<int>("probe-passes").value_or(0) > 0)
        throw ValueError("--probe-passes works with --method gather, --sampling point, --layout uniform and "
                         "--basis sh2 or sh:N only");
    if (p.get<bool>("sh-window") && !isSh2(request.basis)) throw ValueError("--sh-window applies to --basis sh2 only");
    if (p.find<bool>("extra-cache-paths").value_or(false) && p.find<std::string>("probe-cache") != std::optional<std::string>("surface"))
        throw ValueError("--extra-cache-paths feeds the surface probe cache: it needs --probe-cache surface");
    Pass::validate(request);
}

std::size_t GatherPass::bytesPerNode(const BakeRequest& r) const {
    // Float values plus OpenVDB's copy while writing (and, for sh:N, the probe passes' SH order-2
    // cache), and --probe-cache surface's bins (about one cell per node: a pointer each, and at
    // most the bins themselves; they are allocated only where samples land, on surfaces).
    const bool surfaceBins = r.params.get<std::string>("probe-cache") == "surface";
    std::size_t extra = surfaceBins ? SurfaceBins::kBytesPerGridCell + SurfaceBins::kBytesPerCell : 0;
    const std::size_t values = isSh2(r.basis) ? sh::kCoeffs * 3 : makeBasis(r.basis)->floatsPerNode();
    // The guide's map of pass 0's light per direction (a sum and a count per cell: 1 KiB per
    // node, more than the values), and the blend's copy of pass 0's values.
    if (r.params.find<bool>("guide-probe-directions").value_or(false)) {
        extra += DirectionGuide::kCells * (sizeof(float) + sizeof(uint32_t));
        // The probe pass by its error keeps every node's density between its two rounds.
        if (r.params.find<bool>("probe-pass-by-error").value_or(false)) extra += DirectionGuide::kCells * sizeof(float);
    }
    if (r.params.find<bool>("blend-first-pass").value_or(false)) extra += values * sizeof(float);
    if (!isSh2(r.basis)) return (2 * values + sh::kCoeffs * 3) * sizeof(float) + extra;
    return 2 * values * sizeof(float) + extra;
}

std::string GatherPass::untileable(const BakeRequest& r) const {
    return pointGatherUntileable(r);
}

std::string pointGatherUntileable(const BakeRequest& r) {
    const PassParameters& p = r.params;
    if (p.has("invalidate-backface")) return "--invalidate-backface cannot be tiled (its dilation crosses tile borders)";
    if (p.get<bool>("sh-window"))
        return "--sh-window cannot be tiled yet (the window would have to follow the seams at merge)";
    // These choose rays by every node's error at once (the guide and the blend tile: stage 0
    // carries what they read, stage_carry.h).
    for (const char* name : {"extra-cache-paths", "first-pass-by-error"})
        if (p.find<bool>(name).value_or(false))
            return std::string("--") + name + " cannot be tiled (it needs every node's first pass in one bake)";
    if (p.find<bool>("probe-pass-by-error").value_or(false))
        return "--probe-pass-by-error cannot be tiled (it needs every node's probe pass in one bake)";
    // Each probe-to-probe pass reads every node of the pass before: one stage per pass.
    const int passes = p.find<int>("probe-passes").value_or(0);
    if (passes > 1 && p.find<bool>("guide-probe-directions").value_or(false))
        return "--guide-probe-directions tiles with one probe pass only (stage 1 reads pass 0's map)";
    if (passes > 0 && !r.stage)
        return "probe-to-probe passes are tiled in stages (each pass reads every node of the pass before): bake "
               "every tile with --stage 0, merge them, then every tile with --stage 1 --stage-input STAGE0.vdb, ... up "
               "to --stage " + std::to_string(passes) + ", and merge the last stage ('vdblight slurm' writes "
               "this chain; docs/scaling.md), or add --probe-passes 0";
    return "";
}

Volume GatherPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    GatherOptions options = gatherOptions(c, r);
    if (!isSh2(r.basis)) options.basis = makeBasis(r.basis);
    LevelTopology shape;
    shape.grid = grid;
    options.only = selectTile(c, {shape});
    if (const std::optional<double> backface = r.params.find<double>("invalidate-backface"))
        return bakeShGatherInvalidated(c.scene, c.tracer, grid, options, *backface, c.interrupter, &report.stats);
    return bakeShGather(c.scene, c.tracer, grid, options, c.interrupter, &report.stats);
}

const Pass& gatherPass() {
    static const GatherPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
