// What a BakeRequest means (bake_volume.h): the --quality presets, the pass the options
// select, and the rules between options that no single pass owns (layout, basis, tiles,
// stages, direct light, depth moments). Each pass checks its own options (pass.h).
#include <algorithm>
#include <cmath>

#include "extra_cache_paths.h"
#include "pass_options.h"
#include "vdblight/bake/bake.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {
/// What --quality means for the point gather (docs/methods.md, "The default bake", issue 15).
/// `preview` (issue 32): about kPreviewNodes nodes, kPreviewRays rays of full paths + one probe
/// pass of as many that reads the surface probe cache, depth moments, SH order 4, and one pass
/// of the filter across nodes (node_filter.h) weighted by the depth moments and the nodes' error
/// estimates: sub-second bakes to iterate on a scene, measured against the accuracy benchmark's
/// ground truth (docs/time_to_accuracy.md; until issue 32: 16 nodes on the longest axis, 256
/// rays of full paths, no probe pass, no depth moments, SH order 2: 48.7 % RMS in the two rooms).
/// Nodes rather than rays since issue 32's third session: the preview's error was mostly
/// interpolation between nodes (the same bake on the default's ~16384 nodes: office 5.2 -> 2.5 %,
/// two rooms 7.4 -> 4.3 %; with 8 x the rays instead: 4.0 and 5.3 %), so 8192 nodes at 64 rays
/// replace 2048 at 128: twice the rays, within the sub-second budget, the best balance of
/// nodes and rays measured over seeds (docs/time_to_accuracy.md, "Nodes rather than rays").
/// Its probe pass's directions are guided by pass 0 (direction_guide.h), pass 0's values are
/// blended in (volume/first_pass_blend.h), and the nodes where pass 0 is noisiest trace more paths for the
/// surface cache (extra_cache_paths.h: a room lit through a door, two rooms 7.0 -> 5.5 %),
/// and pass 0 spends a quarter of its rays everywhere, the rest by its own error
/// (first_pass_by_error.h; two rooms 5.5 -> 4.8 % over seeds 1, 3, 5, the others equal).
/// The photon pass keeps 16 nodes on the longest axis, 1 M photons and no depth moments there.
/// `default`: about kDefaultNodes nodes in the scene box (node_budget.h: the spacing
/// follows the scene's volume, 16..64 nodes on its longest axis), kDefaultRays rays of full
/// paths, then one probe-to-probe pass of as many rays that ends paths at their first hit
/// with the first pass's reflected light (GatherOptions::probePasses), depth moments from
/// the gather's own first hits so that lookups do not interpolate across walls
/// (depth_moments.h), and SH order 4 stored (kDefaultBasis: SH order 2 cannot hold a bright
/// opening seen from a dark room). The measured choice against the accuracy benchmark's
/// ground truth (docs/measurements/default_bake.md, "SH order 4 in the point gather").
/// Since issue 32's session 22 its probe pass is guided by pass 0 and pass 0 is blended in, as
/// in the preview, tiled bakes included (stage_carry.h): office 2.0 -> 1.6 %, two rooms 3.4 ->
/// 2.6 % for 2 % more time (docs/time_to_accuracy.md); the preview's other two levers add
/// nothing at this budget and do not tile. `high` takes them too (office 1.7 -> 1.5 %, two rooms
/// 2.8 -> 2.5 %, the others equal).
/// `fast` (issue 32 item 1, session 23): the default's grid and probe pass at kFastRays rays,
/// with one pass of the filter across nodes, pass 0's rays by its error and, since session 24,
/// kFastExtraCachePaths extra cache paths per noisy node (a tiled bake goes without these two,
/// as the preview's) and, since session 25, kProbeLightSamples light samples at each probe-pass
/// path's end (as the default): 22-24 % of the default's time for office 1.9-2.0 %, Cornell
/// 1.3 %, two rooms 3.0-3.2 %, outdoor 1.0-1.2 % over seeds 1, 3, 5 (means over ten seeds 2.05,
/// 1.27, 3.14, 1.07 %), against the default's RMS before issue 32 (2.2, 1.3, 3.3, 6.1 %)
/// (docs/time_to_accuracy.md, "A quarter of the default's time" and "Light samples at the
/// probe pass's path end"). At 256 rays the same took 25-26 %; without the filter, office 2.8 %.
/// Since session 26 its probe pass also spends a quarter of its rays everywhere first and the
/// rest by its own error, as pass 0 (ten seeds: office 2.05 -> 2.02 %, Cornell 1.27 -> 1.26 %,
/// two rooms 3.14 -> 3.04 %, the seeds over a target 7 -> 4; 1-3 % more time; the preview's
/// two rooms and the default's did not gain: docs/time_to_accuracy.md, "The probe pass's rays
/// by its error").
/// `high`: the default with twice the rays (kHighRays). Until issue 15's tenth session it was
/// error-targeted (3 %, 64..2048 rays) with two probe passes in SH order 2; with SH order 4 the
/// fixed budget measured lower RMS in every scene in less time (docs/methods.md, "The default
/// bake"), and the error target stays an option (--target-error, SH order 2). Explicit
/// resolution, spacing, rays, target error, probe passes, depth moments and basis override
/// the preset's. The presets apply where the point gather on a uniform SH grid runs; the photon
/// pass takes the default's grid too (except with `preview`): on 16 nodes its six vectors'
/// interpolation dominated (office 37.7 % RMS against 11.1 % on the default's grid, issue 15
/// item 5), and its depth moments (from 256 first-hit rays per node: office 11.1 -> 9.8 %,
/// nowhere worse, docs/methods.md "Visibility-aware interpolation"). Other passes take 16
/// nodes on the longest axis and a fixed 256 rays.
constexpr uint64_t kDefaultNodes = 16384;
constexpr uint64_t kPreviewNodes = 8192;
constexpr uint32_t kPreviewRays = 64;
constexpr uint32_t kDefaultRays = 1024;
constexpr uint32_t kFastRays = 224;
constexpr uint32_t kHighRays = 2048;
constexpr const char* kDefaultBasis = "sh:4";
constexpr uint32_t kPlainRays = 256;
/// Emitter samples at each probe-pass path's end in `fast`, `default` and `high` (issue 32,
/// session 25; TransportOptions::cacheEndLightSamples): over ten seeds `fast`'s office 2.32 ->
/// 2.05 % RMS (2 samples 2.12, 4: 1.99), Cornell 1.31 -> 1.27 %, the two rooms and outdoors
/// unchanged (their light reaches the probe pass's hits through a door, or from the sun), for
/// about 6 % more time; the default's office 1.63 -> 1.43 %, Cornell 1.00 -> 0.94 %, for 7 %.
/// The preview keeps one: its office gained as much (3.99 -> 3.29 %) but its two rooms, its
/// target, did not, and its time is at the 1 s budget's edge.
constexpr uint32_t kProbeLightSamples = 3;
struct QualityPreset {
    int probePasses;
    uint64_t nodes;      ///< 0: 16 nodes on the longest axis
    uint32_t rays;       ///< rays per node and pass of a fixed budget
    bool depthMoments;
    uint64_t photons;    ///< the photon pass's count (1 M: 3.4 % noise on the default's grid, 13.1 %
                         ///< RMS against 4 M's 9.5 % in the two rooms; vdblight_bench_accuracy
                         ///< --config photons_16k)
    const char* basis;   ///< what the point gather stores when --basis is not given
    int nodeFilter;      ///< passes of the filter across nodes (point gather)
    bool photonGrid;     ///< the photon pass takes the preset's grid and depth moments
    bool guideProbeDirections = false;  ///< the probe pass's directions from pass 0's map (direction_guide.h)
    bool blendFirstPass = false;        ///< pass 0's values blended into the probe pass's (volume/first_pass_blend.h)
    uint32_t extraCachePaths = 0;       ///< more paths per node for the surface cache where pass 0 is noisiest, 0: none (extra_cache_paths.h)
    bool firstPassByError = false;      ///< pass 0's rays per node by its own error (first_pass_by_error.h)
    uint32_t probeLightSamples = 1;     ///< emitter samples at each probe-pass path's end (TransportOptions::cacheEndLightSamples)
    bool probePassByError = false;      ///< the probe pass's rays per node by its own error (first_pass_by_error.h)
};
QualityPreset qualityPreset(const std::string& quality) {
    if (quality == "preview")
        return {1, kPreviewNodes, kPreviewRays, true, 1'000'000, kDefaultBasis, 1, false, true, true, bake_detail::kExtraCachePaths, true};
    if (quality == "fast")
        return {1, kDefaultNodes, kFastRays, true, 4'000'000, kDefaultBasis, 1, true, true, true, bake_detail::kFastExtraCachePaths,
                true, kProbeLightSamples, true};
    if (quality == "default")
        return {1, kDefaultNodes, kDefaultRays, true, 4'000'000, kDefaultBasis, 0, true, true, true, 0, false, kProbeLightSamples};
    if (quality == "high")
        return {1, kDefaultNodes, kHighRays, true, 4'000'000, kDefaultBasis, 0, true, true, true, 0, false, kProbeLightSamples};
    throw ValueError("--quality must be " + bake_detail::joinChoices(qualityNames()) + ", got '" + quality + "'");
}

// The presets read and fill the passes' options without their declarations (value, preset:
// PassParameters), since the declarations' help quotes the presets (presetValues).
std::optional<double> givenNumber(const BakeRequest& r, const char* name) {
    const PassValue* v = r.params.value(name);
    return v ? std::optional<double>(std::get<double>(*v)) : std::nullopt;
}
bool givenOn(const BakeRequest& r, const char* name) {
    const PassValue* v = r.params.value(name);
    return v && std::get<bool>(*v);
}
std::string givenWord(const BakeRequest& r, const char* name) {
    const PassValue* v = r.params.value(name);
    return v ? std::get<std::string>(*v) : std::string();
}

/// The uniform SH point gather (SH order 2, or real SH of another order: sh:N), where the
/// presets' grid, rays, probe passes and depth moments apply (the error target: sh2 only, the
/// error-targeted pass stores SH order 2).
bool targetable(const BakeRequest& r) {
    return r.method == "gather" && r.sampling == "point" && !r.params.value("invalidate-backface") &&
           parseLayoutKind(r.layout) == LayoutKind::Uniform && bake_detail::isRealSh(r.basis);
}

std::string selectPassName(const BakeRequest& r) {
    if (!r.pass.empty()) return r.pass;
    if (r.method == "photons") return "photons";
    // sh:N goes through the point gather where it can (uniform grid, point sampling, a fixed
    // budget), every other basis and layout through the bins / generic basis gathers.
    const bool pointGatherSh = bake_detail::isRealSh(r.basis) && parseLayoutKind(r.layout) == LayoutKind::Uniform &&
                               r.sampling == "point" && !r.params.value("target-error");
    if (!bake_detail::isSh2(r.basis) && !pointGatherSh) return "bins";
    if (parseLayoutKind(r.layout) != LayoutKind::Uniform) return "levels";
    if (r.params.value("target-error")) return "adaptive";
    if (r.sampling == "antialiased") return "antialiased";
    return "gather";
}

void checkChoice(const std::string& option, const std::string& value, const std::vector<std::string>& choices) {
    if (std::find(choices.begin(), choices.end(), value) == choices.end())
        throw ValueError("--" + option + " must be " + bake_detail::joinChoices(choices) + ", got '" + value + "'");
}

/// Tiles and stages of a tiled bake (tiles.h), after the preset (which may add probe passes).
void checkTiles(const BakeRequest& given, const BakeRequest& r, const Pass& pass) {
    if (given.tiles.has_value() != given.tile.has_value()) throw ValueError("--tiles and --tile go together");
    if (given.tiles) {
        if (*r.tiles < 1) throw ValueError("--tiles must be at least 1, got " + std::to_string(*r.tiles));
        if (*r.tile < 0 || *r.tile >= *r.tiles)
            throw ValueError("--tile must be between 0 and " + std::to_string(*r.tiles - 1) + ", got " +
                             std::to_string(*r.tile));
        // The selected pass, and the passes other options name: a request that asks for two
        // (antialiased sampling on a bilevel layout) is refused for tiling first, as before.
        std::vector<const Pass*> named = {&pass};
        if (r.method == "photons") named.push_back(&findPass("photons"));
        if (r.sampling == "antialiased") named.push_back(&findPass("antialiased"));
        if (r.params.has("invalidate-backface")) named.push_back(&findPass("gather"));
        for (const Pass* p : named) {
            const std::string why = p->untileable(r);
            if (!why.empty()) throw ValueError(why);
        }
    }
    const int passes = r.params.get<int>("probe-passes");
    if (given.stage) {
        if (!given.tiles)
            throw ValueError("--stage needs --tiles and --tile (one stage of a tiled bake; --tiles 1 --tile 0 for all nodes)");
        if (passes == 0)
            throw ValueError("--stage needs probe-to-probe passes (a bake without them has one stage: leave --stage out)");
        if (*r.stage < 0 || *r.stage > passes)
            throw ValueError("--stage must be between 0 and " + std::to_string(passes) +
                             " (one stage per pass: the first pass and " + std::to_string(passes) +
                             " probe-to-probe passes), got " + std::to_string(*r.stage));
    }
    const int stage = r.stage.value_or(-1);
    if ((stage > 0) != !r.stageInput.empty())
        throw ValueError(stage > 0 ? "--stage " + std::to_string(stage) + " needs --stage-input (the merged tiles of stage " +
                                         std::to_string(stage - 1) + ")"
                                   : std::string("--stage-input needs --stage 1 or later"));
}

/// Direct light out of the basis: the passes that take it, and the option that stops it.
void checkDirect(const BakeRequest& r, const Pass& pass) {
    // Automatic (empty): occlusion where it applies, baked elsewhere; the light count is
    // checked either way.
    if (!r.direct.empty() && parseDirectMode(r.direct) == DirectMode::Baked) return;
    checkDirectLightCounts(r.directLights, r.splitLights);
    if (r.direct.empty()) return;
    const bool shWindow = r.params.get<bool>("sh-window");
    if (pass.takesDirectLight() && !shWindow) return;
    const std::string other = r.method != "gather"           ? "--method photons"
                              : r.sampling != "point"        ? "--sampling antialiased"
                              : r.layout != "uniform"        ? "--layout bilevel/adaptive"
                              : !bake_detail::isSh2(r.basis) ? "--basis other than sh2"
                              : shWindow                     ? "--sh-window"
                                                             : "pass " + pass.name();
    throw ValueError("--direct " + r.direct + " is implemented for the uniform SH point gather only, not with " + other);
}
}  // namespace

BakeRequest resolveBakeRequest(const BakeRequest& given) {
    if (given.basis.empty()) {
        // No --basis: the preset's basis where the request ends in the presets' point gather
        // with a fixed budget (the pass that stores sh:N with probe passes and direct light),
        // SH order 2 everywhere else (other passes, an error target, --sh-window, back-face
        // invalidation).
        BakeRequest sh2 = given;
        sh2.basis = "sh2";
        const BakeRequest r = resolveBakeRequest(sh2);
        const std::string preset = qualityPreset(given.quality).basis;
        if (!targetable(r) || r.params.value("target-error") || givenOn(r, "sh-window") || preset == "sh2") return r;
        BakeRequest other = given;
        other.basis = preset;
        return resolveBakeRequest(other);
    }
    BakeRequest r = given;
    const QualityPreset preset = qualityPreset(r.quality);
    const bool presetApplies = targetable(r);
    PassParameters& p = r.params;
    const bool target = p.value("target-error") != nullptr;
    if (target) {
        if (!p.value("min-rays")) p.preset("min-rays", double(bake_detail::kTargetMinRays));
        if (!p.value("max-rays"))
            p.preset("max-rays", std::max(double(bake_detail::kTargetMaxRays), *givenNumber(r, "min-rays")));
    }
    if (!p.value("probe-passes")) p.preset("probe-passes", double(presetApplies ? preset.probePasses : 0));
    const bool photonGrid = selectPassName(r) == "photons" && preset.photonGrid;
    if ((presetApplies || photonGrid) && !r.spacing && !r.resolution && !r.nodes && preset.nodes > 0) r.nodes = preset.nodes;
    if (!p.value("rays")) p.preset("rays", double(presetApplies && !target ? preset.rays : kPlainRays));
    if (!p.value("photons")) p.preset("photons", double(preset.photons));
    if (!p.value("depth-moments")) p.preset("depth-moments", (presetApplies || photonGrid) && preset.depthMoments);
    // The probe pass's cache: the surface bins where the bake runs exactly one probe pass (the
    // presets' point gather), the nodes otherwise (docs/methods.md, "The surface probe cache").
    if (givenWord(r, "probe-cache").empty())
        p.preset("probe-cache", std::string(*givenNumber(r, "probe-passes") == 1 && selectPassName(r) == "gather"
                                                ? "surface"
                                                : "nodes"));
    if (!p.value("node-filter"))
        p.preset("node-filter", double(presetApplies && selectPassName(r) == "gather" ? preset.nodeFilter : 0));
    // The guide and the blend tile in stages (stage 0 carries pass 0's map, values and errors:
    // stage_carry.h); the extra cache paths and pass 0's two rounds choose nodes by every
    // node's pass-0 error at once, so a tiled bake goes without them.
    const bool gather = presetApplies && selectPassName(r) == "gather";
    const bool untiledGather = gather && !r.tiles;
    const double probePasses = *givenNumber(r, "probe-passes");
    if (!p.value("guide-probe-directions"))
        p.preset("guide-probe-directions",
                 ((untiledGather && probePasses > 0) || (gather && probePasses == 1)) && preset.guideProbeDirections);
    if (!p.value("blend-first-pass"))
        p.preset("blend-first-pass", gather && probePasses == 1 && preset.blendFirstPass);
    if (!p.value("extra-cache-paths"))
        p.preset("extra-cache-paths", untiledGather && probePasses == 1 && givenWord(r, "probe-cache") != "nodes" &&
                                          preset.extraCachePaths > 0);
    if (!p.value("extra-cache-paths-per-node"))
        p.preset("extra-cache-paths-per-node",
                 double(preset.extraCachePaths > 0 ? preset.extraCachePaths : bake_detail::kExtraCachePaths));
    if (!p.value("first-pass-by-error"))
        p.preset("first-pass-by-error", untiledGather && probePasses == 1 && preset.firstPassByError);
    if (!p.value("probe-pass-by-error"))
        p.preset("probe-pass-by-error", untiledGather && probePasses == 1 && preset.probePassByError);
    if (!p.value("probe-light-samples"))
        p.preset("probe-light-samples", double(gather && probePasses > 0 ? preset.probeLightSamples : 1));
    r.pass = selectPassName(r);
    return r;
}

const std::vector<std::string>& qualityNames() {
    static const std::vector<std::string> names = {"preview", "fast", "default", "high"};
    return names;
}

namespace bake_detail {
std::string presetValues(const std::function<std::string(const BakeRequest&)>& field, const std::string& method) {
    std::vector<std::string> values;
    for (const std::string& q : qualityNames()) {
        BakeRequest given;
        given.quality = q;
        given.method = method;
        values.push_back(field(resolveBakeRequest(given)));
    }
    if (std::all_of(values.begin(), values.end(), [&](const std::string& v) { return v == values[0]; })) return values[0];
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i)
        text += (i ? ", " : "") + values[i] + (i ? " with " : " with --quality ") + qualityNames()[i];
    return text;
}
}  // namespace bake_detail

std::string describeQuality(const std::string& quality) {
    BakeRequest given;
    given.quality = quality;
    const BakeRequest r = resolveBakeRequest(given);  // throws for an unknown preset
    BakeRequest photons = given;
    photons.method = "photons";
    const BakeRequest p = resolveBakeRequest(photons);
    const Pass& pass = findPass(r.pass);
    std::string text = r.nodes ? "about " + std::to_string(*r.nodes) + " nodes in the scene box (" +
                                     std::to_string(kBudgetMinNodesOnLongestAxis) + ".." +
                                     std::to_string(kBudgetMaxNodesOnLongestAxis) + " on its longest axis)"
                               : std::to_string(kDefaultResolution) + " nodes on the longest axis";
    const PassParameters& o = r.params;
    const std::string rays = std::to_string(o.get<uint32_t>("rays"));
    text += ", " + rays + " rays per node of full paths";
    const int passes = o.get<int>("probe-passes");
    if (passes > 0)
        text += " + " + std::to_string(passes) + " probe-to-probe pass" + (passes > 1 ? "es" : "") + " of " + rays +
                (o.get<std::string>("probe-cache") == "surface" ? " (surface probe cache)" : "");
    text += ", basis " + r.basis;
    text += o.get<bool>("depth-moments") ? ", depth moments" : ", no depth moments";
    const int filter = o.get<int>("node-filter");
    if (filter > 0) text += ", " + std::to_string(filter) + " pass of the filter across nodes";
    if (o.get<bool>("guide-probe-directions")) text += ", probe directions guided by the first pass";
    if (o.get<bool>("blend-first-pass")) text += ", the first pass's values blended in";
    if (o.get<bool>("extra-cache-paths"))
        text += ", " + std::to_string(o.get<uint32_t>("extra-cache-paths-per-node")) +
                " more first-pass paths per node for the surface cache where it is noisiest";
    if (o.get<bool>("first-pass-by-error")) text += ", the first pass's rays per node by its own noise";
    if (o.get<bool>("probe-pass-by-error")) text += ", the probe pass's rays per node by its own noise";
    if (const uint32_t samples = o.get<uint32_t>("probe-light-samples"); samples > 1)
        text += ", " + std::to_string(samples) + " light samples at each probe-pass path's end";
    const bool occlusion = r.direct.empty() && pass.takesDirectLight() && !o.get<bool>("sh-window");
    text += occlusion ? ", direct light of up to " + std::to_string(r.directLights) +
                            " lights exact with baked visibility (--direct occlusion) where the scene has lights"
                      : ", direct light baked into the basis";
    text += "; --method photons: " + std::to_string(p.params.get<uint64_t>("photons") / 1000000) + " M photons" +
            (p.nodes ? std::string(" on this grid") : " on " + std::to_string(kDefaultResolution) + " nodes on the longest axis") +
            (p.params.get<bool>("depth-moments") ? " with depth moments" : "");
    return text;
}

const Pass& checkBakeRequest(const BakeRequest& given) {
    checkChoice("method", given.method, {"gather", "photons"});
    checkChoice("sampling", given.sampling, {"point", "antialiased"});
    const LayoutKind kind = parseLayoutKind(given.layout);
    if (!given.basis.empty()) (void)bake_detail::isSh2(given.basis);  // throws for an unknown basis
    const BakeRequest r = resolveBakeRequest(given);  // throws for an unknown quality
    const bool sh2 = bake_detail::isSh2(r.basis);
    const Pass& pass = findPass(r.pass);
    // What the request asked for, with the basis the preset chose where it named none: the
    // passes check explicit options against it.
    BakeRequest asked = given;
    asked.basis = r.basis;

    const PassParameters& givenParams = given.params;
    const PassParameters& resolved = r.params;
    const bool backface = givenParams.has("invalidate-backface");
    if (givenParams.has("target-error") && givenParams.has("rays"))
        throw ValueError("--target-error and --rays exclude each other (an error target or a fixed budget)");
    if (givenOn(given, "depth-moments") && !pass.takesDepthMoments())
        throw ValueError("--depth-moments does not apply to pass " + pass.name());
    if (givenParams.has("depth-rays") && !resolved.get<bool>("depth-moments"))
        throw ValueError("--depth-rays needs --depth-moments");
    checkTiles(asked, r, pass);
    // After the preset's passes (preview: 0).
    if (resolved.get<std::string>("probe-cache") == "surface" && resolved.get<int>("probe-passes") != 1)
        throw ValueError("--probe-cache surface needs exactly one probe pass (--probe-passes 1, the default's)");
    const bool shWindow = resolved.get<bool>("sh-window");
    if (shWindow && !pass.takesShWindow())
        throw ValueError("--sh-window applies to --method gather with --basis sh2 only");
    if (!sh2 && (r.method != "gather" || r.sampling != "point" || backface))
        throw ValueError("--basis " + (bake_detail::isBinsOrMoment(r.basis) ? std::string("bins/moment") : r.basis) +
                         " works with --method gather and --sampling point only");
    if (kind == LayoutKind::Uniform && givenParams.has("refine"))
        throw ValueError("--refine needs --layout bilevel or adaptive");
    if (kind != LayoutKind::Adaptive && givenParams.has("levels")) throw ValueError("--levels needs --layout adaptive");
    if (kind != LayoutKind::Uniform && (r.sampling != "point" || backface || r.method != "gather"))
        throw ValueError("--layout bilevel/adaptive works with --method gather and --sampling point only");
    if (givenParams.has("refine-distance") && kind == LayoutKind::Uniform)
        throw ValueError("--refine-distance needs --layout bilevel or adaptive");
    if (resolved.get<bool>("cull-solids") && (kind == LayoutKind::Uniform || !sh2))
        throw ValueError("--cull-solids needs --layout bilevel or adaptive and --basis sh2");
    // Zero or negative values are refused here: unset is the default.
    if (given.spacing && !(*given.spacing > 0))
        throw ValueError("--spacing must be positive, got " + std::to_string(*given.spacing));
    if (given.resolution && *given.resolution < 1)
        throw ValueError("--resolution must be at least 1, got " + std::to_string(*given.resolution));
    if (given.spacing && given.resolution) throw ValueError("--spacing and --resolution exclude each other");
    if (r.method == "photons" && (r.sampling != "point" || !givenWord(r, "domain").empty() || backface))
        throw ValueError("--sampling, --domain and --invalidate-backface apply to --method gather only");
    if (r.threads < 0) throw ValueError("--threads must be at least 0 (0 = all cores), got " + std::to_string(r.threads));

    // The pass's own options, then options it does not take.
    pass.validate(asked);
    std::vector<std::string> declared;
    for (const PassOption& o : pass.options()) declared.push_back(o.name);
    for (const Pass* other : passRegistry())
        for (const PassOption& o : other->options()) {
            if (o.needs.empty() || std::find(declared.begin(), declared.end(), o.name) != declared.end()) continue;
            if (bake_detail::givenToRefuse(o, asked.params)) throw ValueError(o.needs);
        }
    checkDirect(r, pass);
    return pass;
}

int tiledBakeStages(const BakeRequest& request) {
    BakeRequest staged = resolveBakeRequest(request);
    if (staged.params.has("depth-rays") && !staged.params.get<bool>("depth-moments"))
        throw ValueError("--depth-rays needs --depth-moments");
    staged.stage = 0;
    const std::string why = findPass(staged.pass).untileable(staged);
    if (!why.empty()) throw ValueError(why);
    return staged.params.get<int>("probe-passes") + 1;
}

}  // namespace vdblight
