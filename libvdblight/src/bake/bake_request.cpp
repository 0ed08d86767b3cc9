// What a BakeRequest means (bake_volume.h): the --quality presets, the pass the options
// select, and the rules between options that no single pass owns (layout, basis, tiles,
// stages, direct light, depth moments). Each pass checks its own options (pass.h).
#include <algorithm>
#include <cmath>

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
/// The photon pass keeps 16 nodes on the longest axis, 1 M photons and no depth moments there.
/// `default`: about kDefaultNodes nodes in the scene box (node_budget.h: the spacing
/// follows the scene's volume, 16..64 nodes on its longest axis), kDefaultRays rays of full
/// paths, then one probe-to-probe pass of as many rays that ends paths at their first hit
/// with the first pass's reflected light (GatherOptions::probePasses), depth moments from
/// the gather's own first hits so that lookups do not interpolate across walls
/// (depth_moments.h), and SH order 4 stored (kDefaultBasis: SH order 2 cannot hold a bright
/// opening seen from a dark room). The measured choice against the accuracy benchmark's
/// ground truth (docs/measurements/default_bake.md, "SH order 4 in the point gather").
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
constexpr uint64_t kPreviewNodes = 2048;
constexpr uint32_t kPreviewRays = 128;
constexpr uint32_t kDefaultRays = 1024;
constexpr uint32_t kHighRays = 2048;
constexpr const char* kDefaultBasis = "sh:4";
constexpr uint32_t kPlainRays = 256;
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
};
QualityPreset qualityPreset(const std::string& quality) {
    if (quality == "preview") return {1, kPreviewNodes, kPreviewRays, true, 1'000'000, kDefaultBasis, 1, false};
    if (quality == "default") return {1, kDefaultNodes, kDefaultRays, true, 4'000'000, kDefaultBasis, 0, true};
    if (quality == "high") return {1, kDefaultNodes, kHighRays, true, 4'000'000, kDefaultBasis, 0, true};
    throw ValueError("--quality must be " + bake_detail::joinChoices(qualityNames()) + ", got '" + quality + "'");
}

/// The uniform SH point gather (SH order 2, or real SH of another order: sh:N), where the
/// presets' grid, rays, probe passes and depth moments apply (the error target: sh2 only, the
/// error-targeted pass stores SH order 2).
bool targetable(const BakeRequest& r) {
    return r.method == "gather" && r.sampling == "point" && !r.invalidateBackface &&
           parseLayoutKind(r.layout) == LayoutKind::Uniform && bake_detail::isRealSh(r.basis);
}

std::string selectPassName(const BakeRequest& r) {
    if (!r.pass.empty()) return r.pass;
    if (r.method == "photons") return "photons";
    // sh:N goes through the point gather where it can (uniform grid, point sampling, a fixed
    // budget), every other basis and layout through the bins / generic basis gathers.
    const bool pointGatherSh = bake_detail::isRealSh(r.basis) && parseLayoutKind(r.layout) == LayoutKind::Uniform &&
                               r.sampling == "point" && !r.targetError;
    if (!bake_detail::isSh2(r.basis) && !pointGatherSh) return "bins";
    if (parseLayoutKind(r.layout) != LayoutKind::Uniform) return "levels";
    if (r.targetError) return "adaptive";
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
        if (r.invalidateBackface) named.push_back(&findPass("gather"));
        for (const Pass* p : named) {
            const std::string why = p->untileable(r);
            if (!why.empty()) throw ValueError(why);
        }
    }
    const int passes = r.probePasses.value_or(0);
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
    if (r.directLights < 1 || r.directLights > 16)
        throw ValueError("--direct-lights must be between 1 and 16, got " + std::to_string(r.directLights));
    if (r.direct.empty()) return;
    if (pass.takesDirectLight() && !r.shWindow) return;
    const std::string other = r.method != "gather"           ? "--method photons"
                              : r.sampling != "point"        ? "--sampling antialiased"
                              : r.layout != "uniform"        ? "--layout bilevel/adaptive"
                              : !bake_detail::isSh2(r.basis) ? "--basis other than sh2"
                              : r.shWindow                   ? "--sh-window"
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
        if (!targetable(r) || r.targetError || r.shWindow || preset == "sh2") return r;
        BakeRequest other = given;
        other.basis = preset;
        return resolveBakeRequest(other);
    }
    BakeRequest r = given;
    const QualityPreset preset = qualityPreset(r.quality);
    const bool presetApplies = targetable(r);
    if (r.targetError) {
        if (!r.minRays) r.minRays = bake_detail::kTargetMinRays;
        if (!r.maxRays) r.maxRays = std::max(bake_detail::kTargetMaxRays, *r.minRays);
    }
    if (!r.probePasses) r.probePasses = presetApplies ? preset.probePasses : 0;
    const bool photonGrid = selectPassName(r) == "photons" && preset.photonGrid;
    if ((presetApplies || photonGrid) && !r.spacing && !r.resolution && !r.nodes && preset.nodes > 0) r.nodes = preset.nodes;
    if (!r.rays) r.rays = presetApplies && !r.targetError ? preset.rays : kPlainRays;
    if (!r.photons) r.photons = preset.photons;
    if (!r.depthMoments) r.depthMoments = (presetApplies || photonGrid) && preset.depthMoments;
    // The probe pass's cache: the surface bins where the bake runs exactly one probe pass (the
    // presets' point gather), the nodes otherwise (docs/methods.md, "The surface probe cache").
    if (r.probeCache.empty()) r.probeCache = *r.probePasses == 1 && selectPassName(r) == "gather" ? "surface" : "nodes";
    if (!r.nodeFilter) r.nodeFilter = presetApplies && selectPassName(r) == "gather" ? preset.nodeFilter : 0;
    if (!r.refine) r.refine = 3;
    if (!r.levels) r.levels = 3;
    if (!r.refineDistance) r.refineDistance = 0.0;
    r.pass = selectPassName(r);
    return r;
}

const std::vector<std::string>& qualityNames() {
    static const std::vector<std::string> names = {"preview", "default", "high"};
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
    text += ", " + std::to_string(*r.rays) + " rays per node of full paths";
    const int passes = r.probePasses.value_or(0);
    if (passes > 0)
        text += " + " + std::to_string(passes) + " probe-to-probe pass" + (passes > 1 ? "es" : "") + " of " +
                std::to_string(*r.rays) + (r.probeCache == "surface" ? " (surface probe cache)" : "");
    text += ", basis " + r.basis;
    text += *r.depthMoments ? ", depth moments" : ", no depth moments";
    if (*r.nodeFilter > 0) text += ", " + std::to_string(*r.nodeFilter) + " pass of the filter across nodes";
    const bool occlusion = r.direct.empty() && pass.takesDirectLight() && !r.shWindow;
    text += occlusion ? ", direct light of up to " + std::to_string(r.directLights) +
                            " lights exact with baked visibility (--direct occlusion) where the scene has lights"
                      : ", direct light baked into the basis";
    text += "; --method photons: " + std::to_string(*p.photons / 1000000) + " M photons" +
            (p.nodes ? std::string(" on this grid") : " on " + std::to_string(kDefaultResolution) + " nodes on the longest axis") +
            (*p.depthMoments ? " with depth moments" : "");
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

    if (given.targetError && given.rays)
        throw ValueError("--target-error and --rays exclude each other (an error target or a fixed budget)");
    if (given.depthMoments.value_or(false) && !pass.takesDepthMoments())
        throw ValueError("--depth-moments does not apply to pass " + pass.name());
    if (given.depthRays && !*r.depthMoments) throw ValueError("--depth-rays needs --depth-moments");
    checkTiles(asked, r, pass);
    if (r.probeCache == "surface" && *r.probePasses != 1)  // after the preset's passes (preview: 0)
        throw ValueError("--probe-cache surface needs exactly one probe pass (--probe-passes 1, the default's)");
    if (r.shWindow && !pass.takesShWindow()) throw ValueError("--sh-window applies to --method gather with --basis sh2 only");
    if (!sh2 && (r.method != "gather" || r.sampling != "point" || r.invalidateBackface))
        throw ValueError("--basis " + (bake_detail::isBinsOrMoment(r.basis) ? std::string("bins/moment") : r.basis) +
                         " works with --method gather and --sampling point only");
    if (kind == LayoutKind::Uniform && given.refine) throw ValueError("--refine needs --layout bilevel or adaptive");
    if (kind != LayoutKind::Adaptive && given.levels) throw ValueError("--levels needs --layout adaptive");
    if (kind != LayoutKind::Uniform && (r.sampling != "point" || r.invalidateBackface || r.method != "gather"))
        throw ValueError("--layout bilevel/adaptive works with --method gather and --sampling point only");
    if (given.refineDistance && kind == LayoutKind::Uniform)
        throw ValueError("--refine-distance needs --layout bilevel or adaptive");
    if (r.cullSolids && (kind == LayoutKind::Uniform || !sh2))
        throw ValueError("--cull-solids needs --layout bilevel or adaptive and --basis sh2");
    // Zero or negative values are refused here: unset is the default.
    if (given.spacing && !(*given.spacing > 0))
        throw ValueError("--spacing must be positive, got " + std::to_string(*given.spacing));
    if (given.resolution && *given.resolution < 1)
        throw ValueError("--resolution must be at least 1, got " + std::to_string(*given.resolution));
    if (given.spacing && given.resolution) throw ValueError("--spacing and --resolution exclude each other");
    if (r.method == "photons" && (r.sampling != "point" || !r.domain.empty() || r.invalidateBackface))
        throw ValueError("--sampling, --domain and --invalidate-backface apply to --method gather only");
    if (r.threads < 0) throw ValueError("--threads must be at least 0 (0 = all cores), got " + std::to_string(r.threads));

    // The pass's own options, then options it does not take.
    pass.validate(asked);
    std::vector<std::string> declared;
    for (const PassOption& o : pass.options()) declared.push_back(o.name);
    for (const Pass* other : passRegistry())
        for (const PassOption& o : other->options()) {
            if (o.needs.empty() || std::find(declared.begin(), declared.end(), o.name) != declared.end()) continue;
            const bool given_ = (o.number && o.number(asked)) || (o.word && o.word(asked));
            if (given_) throw ValueError(o.needs);
        }
    checkDirect(r, pass);
    return pass;
}

int tiledBakeStages(const BakeRequest& request) {
    BakeRequest staged = resolveBakeRequest(request);
    if (staged.depthRays && !*staged.depthMoments) throw ValueError("--depth-rays needs --depth-moments");
    staged.stage = 0;
    const std::string why = findPass(staged.pass).untileable(staged);
    if (!why.empty()) throw ValueError(why);
    return *staged.probePasses + 1;
}

}  // namespace vdblight
