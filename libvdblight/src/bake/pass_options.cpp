// The option declarations the passes share, and what every pass does alike: the range and
// word checks of Pass::validate, the default Pass::finish.
#include "pass_options.h"

#include <cmath>
#include <sstream>
#include <type_traits>

#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {
std::string numberText(double v) {
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15) {
        std::ostringstream s;
        s << int64_t(v);
        return s.str();
    }
    return std::to_string(v);
}

std::string rangeText(const PassOption& o) {
    if (!o.range.empty()) return o.range;
    if (o.minExclusive) return "in (" + numberText(o.min) + ", " + numberText(o.max) + "]";
    if (std::isinf(o.max)) return "at least " + numberText(o.min);
    return "between " + numberText(o.min) + " and " + numberText(o.max);
}
}  // namespace

void Pass::validate(const BakeRequest& request) const {
    for (const PassOption& o : options()) {
        const PassValue* given = request.params.value(o.name);
        if (!given) continue;
        if (const double* v = std::get_if<double>(given)) {
            if (o.zeroIsUnset && *v == 0) continue;
            const bool aboveMin = o.minExclusive ? *v > o.min : *v >= o.min;
            if (!(aboveMin && *v <= o.max))  // NaN fails too
                throw ValueError("--" + o.name + " must be " + rangeText(o) + ", got " + numberText(*v));
        } else if (const std::string* w = std::get_if<std::string>(given); w && !o.choices.empty()) {
            bool known = false;
            for (const std::string& c : o.choices) known = known || c == *w;
            if (!known)
                throw ValueError("--" + o.name + " must be " + bake_detail::joinChoices(o.choices) + ", got '" + *w + "'");
        }
    }
}

void Pass::finish(Volume&, WriteOptions&, const BakeRequest&) const {}

namespace bake_detail {

bool isSh2(const std::string& basis) { return makeBasis(basis)->desc().isSh2(); }  // the registry (basis.h)

bool isRealSh(const std::string& basis) { return makeBasis(basis)->desc().isRealSh(); }

bool isBinsOrMoment(const std::string& basis) {
    bins::BasisSpec spec;
    return bins::specFromVolume(makeBasis(basis)->desc(), spec);
}

std::string joinChoices(const std::vector<std::string>& words) {
    std::string text;
    for (std::size_t i = 0; i < words.size(); ++i)
        text += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    return text;
}

bool isWholeNumber(double v) { return v == std::floor(v) && std::fabs(v) < 9e18; }

double parseOptionNumber(const std::string& name, const std::string& text, bool integer) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size()) throw ValueError("--" + name + " must be a number, got '" + text + "'");
    if (integer && !isWholeNumber(v)) throw ValueError("--" + name + " must be a whole number, got '" + text + "'");
    return v;
}

PassOption describeOption(std::string name, std::string help, std::string defaultValue, double min, double max,
                          std::string needs, std::string range) {
    PassOption o;
    o.name = std::move(name);
    o.help = std::move(help);
    o.defaultValue = std::move(defaultValue);
    o.min = min;
    o.max = max;
    o.needs = std::move(needs);
    o.range = std::move(range);
    return o;
}

PassOption flagOption(std::string name, std::string help, std::string needs) {
    PassOption o = describeOption(std::move(name), std::move(help), "off", 0, 1, std::move(needs));
    o.flag = true;
    return o;
}

PassOption wordOption(std::string name, std::string help, std::string defaultValue, std::vector<std::string> choices,
                      std::string needs) {
    PassOption o = describeOption(std::move(name), std::move(help), std::move(defaultValue), 0, 0, std::move(needs));
    o.choices = std::move(choices);
    return o;
}

bool givenToRefuse(const PassOption& option, const PassParameters& params) {
    const PassValue* v = params.value(option.name);
    if (!v) return false;
    if (const double* number = std::get_if<double>(v)) return !(option.zeroIsUnset && *number == 0);
    if (const bool* on = std::get_if<bool>(v)) return *on;
    return !std::get<std::string>(*v).empty();
}

std::string presetNumbers(const std::string& option, const std::string& method) {
    return presetValues([&](const BakeRequest& r) { return numberText(r.params.get<double>(option)); }, method);
}

PassOption raysOption(const std::string& help) {
    return numberOption<uint32_t>("rays", help,
                                  presetNumbers("rays") + " for the uniform SH point gather; " +
                                      presetNumbers("rays", "photons") + " for the other passes",
                                  1, double(1u << 30));
}

PassOption depthMomentsOption() {
    PassOption o = flagOption("depth-moments",
                      "also store per-node depth moments, so that lookups do not interpolate across walls "
                      "(docs/methods.md, visibility-aware interpolation). Default where the presets apply (the uniform "
                      "SH point gather, and --method photons): " +
                          presetValues([](const BakeRequest& r) {
                              return std::string(r.params.get<bool>("depth-moments") ? "on" : "off");
                          }) +
                          "; off for the other passes; --no-depth-moments turns it off",
                      "--depth-moments does not apply to this pass");
    o.negatable = true;  // the presets' default may be on
    o.defaultValue = "the --quality preset's";
    return o;
}

PassOption depthRaysOption() {
    return numberOption<uint32_t>("depth-rays", "--depth-moments: first-hit rays per node",
                                  "as many as --rays (256 with --method photons)", 1, double(1u << 20),
                                  "--depth-rays needs --depth-moments");
}

PassOption shWindowOption() {
    return flagOption("sh-window",
                      "window the SH bands (1, 0.584, 0.135) so that irradiance is never negative (blurs; "
                      "docs/methods.md)",
                      "--sh-window applies to --method gather with --basis sh2 only");
}

PassOption probePassesOption() {
    PassOption o = numberOption<int>("probe-passes",
                                "after a first pass of full paths, this many passes that end each gathered path at "
                                "its first hit with the previous pass's reflected light (probe-to-probe bounces, "
                                "DDGI-style; less noise where light comes through openings, some bias; "
                                "docs/methods.md)",
                                presetNumbers("probe-passes"), 0, 8,
                                "--probe-passes works with --method gather, --sampling point, --layout uniform and "
                                "--basis sh2 only");
    o.zeroIsUnset = true;  // 0 passes is what every other pass does: only more than 0 is refused elsewhere
    return o;
}

GatherOptions gatherOptions(const BakeContext& c, const BakeRequest& r) {
    const PassParameters& p = r.params;
    GatherOptions o;
    o.raysPerNode = p.get<uint32_t>("rays");
    o.seed = c.seed;
    o.threads = c.threads;
    o.transport = c.transport;
    o.probePasses = p.get<int>("probe-passes");
    o.surfaceProbeCache = p.find<std::string>("probe-cache") == std::optional<std::string>("surface");
    o.nodeFilterPasses = p.find<int>("node-filter").value_or(0);
    o.nodeFilterByNoise = true;
    o.guideProbeDirections = p.find<bool>("guide-probe-directions").value_or(false);
    o.blendFirstPass = p.find<bool>("blend-first-pass").value_or(false);
    o.extraCachePaths = p.find<bool>("extra-cache-paths").value_or(false);
    o.extraCachePathsPerNode = p.find<uint32_t>("extra-cache-paths-per-node").value_or(o.extraCachePathsPerNode);
    o.transport.cacheEndLightSamples = int(p.find<uint32_t>("probe-light-samples").value_or(1));
    o.firstPassByError = p.find<bool>("first-pass-by-error").value_or(false);
    o.probePassByError = p.find<bool>("probe-pass-by-error").value_or(false);
    // The point gather records depth moments from its own first rays (no extra rays).
    const std::optional<uint32_t> depthRays = p.find<uint32_t>("depth-rays");
    o.depthMoments = p.get<bool>("depth-moments") && (!depthRays || *depthRays == o.raysPerNode);
    o.stage = c.stage;
    o.stageInput = c.stageInput;
    return o;
}

LevelsPlacement levelsPlacement(const BakeRequest& r) {
    LevelsPlacement p;
    p.kind = parseLayoutKind(r.layout);
    p.refine = r.params.get<int>("refine");
    p.levels = r.params.get<int>("levels");
    p.refineDistance = r.params.get<double>("refine-distance");
    return p;
}

}  // namespace bake_detail
}  // namespace vdblight
