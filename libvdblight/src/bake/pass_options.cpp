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
        if (o.number) {
            const std::optional<double> v = o.number(request);
            if (!v) continue;
            const bool aboveMin = o.minExclusive ? *v > o.min : *v >= o.min;
            if (!(aboveMin && *v <= o.max))  // NaN fails too
                throw ValueError("--" + o.name + " must be " + rangeText(o) + ", got " + numberText(*v));
        } else if (o.word && !o.choices.empty()) {
            const std::optional<std::string> w = o.word(request);
            if (!w) continue;
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

double parseOptionNumber(const std::string& name, const std::string& text, bool integer) {
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size()) throw ValueError("--" + name + " must be a number, got '" + text + "'");
    if (integer && !(v == std::floor(v) && std::fabs(v) < 9e18))
        throw ValueError("--" + name + " must be a whole number, got '" + text + "'");
    return v;
}

namespace {
void setFlagText(bool& value, const std::string& name, const std::string& text) {
    if (text == "true" || text == "1") value = true;
    else if (text == "false" || text == "0") value = false;
    else throw ValueError("--" + name + " is on or off (true or false), got '" + text + "'");
}
}  // namespace

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

namespace {
/// A flag in a bool field (default off) or a std::optional<bool> one (default: the preset's,
/// so it may be switched off too).
template <typename Field>
PassOption flagOf(std::string name, std::string help, Field BakeRequest::*field, std::string needs) {
    constexpr bool negatable = !std::is_same_v<Field, bool>;
    PassOption o = describeOption(std::move(name), std::move(help), negatable ? "the --quality preset's" : "off", 0, 1,
                                  std::move(needs));
    o.flag = true;
    o.negatable = negatable;
    o.number = [field](const BakeRequest& r) -> std::optional<double> {
        bool on = false;
        if constexpr (negatable) on = (r.*field).value_or(false);
        else on = r.*field;
        return on ? std::optional<double>(1.0) : std::nullopt;
    };
    o.setNumber = [field](BakeRequest& r, double v) { r.*field = v != 0; };
    o.setText = [field, n = o.name](BakeRequest& r, const std::string& text) {
        bool on = false;
        setFlagText(on, n, text);
        r.*field = on;
    };
    return o;
}
}  // namespace

PassOption flagOption(std::string name, std::string help, bool BakeRequest::*field, std::string needs) {
    return flagOf(std::move(name), std::move(help), field, std::move(needs));
}

PassOption flagOption(std::string name, std::string help, std::optional<bool> BakeRequest::*field, std::string needs) {
    return flagOf(std::move(name), std::move(help), field, std::move(needs));
}

PassOption wordOption(std::string name, std::string help, std::string defaultValue, std::vector<std::string> choices,
                      std::string BakeRequest::*field, std::string needs) {
    PassOption o = describeOption(std::move(name), std::move(help), std::move(defaultValue), 0, 0, std::move(needs));
    o.choices = std::move(choices);
    o.setText = [field](BakeRequest& r, const std::string& text) { r.*field = text; };
    o.word = [field](const BakeRequest& r) -> std::optional<std::string> {
        if ((r.*field).empty()) return std::nullopt;
        return r.*field;
    };
    return o;
}

PassOption raysOption(const std::string& help) {
    return numberOption("rays", help,
                        presetValues([](const BakeRequest& r) { return std::to_string(*r.rays); }) +
                            " for the uniform SH point gather; " +
                            presetValues([](const BakeRequest& r) { return std::to_string(*r.rays); }, "photons") +
                            " for the other passes",
                        1, double(1u << 30), &BakeRequest::rays);
}

PassOption depthMomentsOption() {
    return flagOption("depth-moments",
                      "also store per-node depth moments, so that lookups do not interpolate across walls "
                      "(docs/methods.md, visibility-aware interpolation). Default where the presets apply (the uniform "
                      "SH point gather, and --method photons): " +
                          presetValues([](const BakeRequest& r) { return std::string(*r.depthMoments ? "on" : "off"); }) +
                          "; off for the other passes; --no-depth-moments turns it off",
                      &BakeRequest::depthMoments, "--depth-moments does not apply to this pass");
}

PassOption depthRaysOption() {
    return numberOption("depth-rays", "--depth-moments: first-hit rays per node", "as many as --rays (256 with --method photons)", 1, double(1u << 20),
                        &BakeRequest::depthRays, "--depth-rays needs --depth-moments");
}

PassOption shWindowOption() {
    return flagOption("sh-window",
                      "window the SH bands (1, 0.584, 0.135) so that irradiance is never negative (blurs; "
                      "docs/methods.md)",
                      &BakeRequest::shWindow, "--sh-window applies to --method gather with --basis sh2 only");
}

PassOption probePassesOption() {
    PassOption o = numberOption("probe-passes",
                                "after a first pass of full paths, this many passes that end each gathered path at "
                                "its first hit with the previous pass's reflected light (probe-to-probe bounces, "
                                "DDGI-style; less noise where light comes through openings, some bias; "
                                "docs/methods.md)",
                                presetValues([](const BakeRequest& r) { return std::to_string(*r.probePasses); }), 0, 8,
                                &BakeRequest::probePasses,
                                "--probe-passes works with --method gather, --sampling point, --layout uniform and "
                                "--basis sh2 only");
    // 0 passes is what every other pass does: only more than 0 is refused elsewhere.
    o.number = [](const BakeRequest& r) -> std::optional<double> {
        if (!r.probePasses || *r.probePasses == 0) return std::nullopt;
        return double(*r.probePasses);
    };
    return o;
}

GatherOptions gatherOptions(const BakeContext& c, const BakeRequest& r) {
    GatherOptions o;
    o.raysPerNode = *r.rays;
    o.seed = c.seed;
    o.threads = c.threads;
    o.transport = c.transport;
    o.probePasses = *r.probePasses;
    o.surfaceProbeCache = r.probeCache == "surface";
    o.nodeFilterPasses = r.nodeFilter.value_or(0);
    o.nodeFilterByNoise = true;
    o.guideProbeDirections = r.guideProbeDirections.value_or(false);
    o.blendFirstPass = r.blendFirstPass.value_or(false);
    // The point gather records depth moments from its own first rays (no extra rays).
    o.depthMoments = *r.depthMoments && (!r.depthRays || *r.depthRays == *r.rays);
    o.stage = c.stage;
    o.stageInput = c.stageInput;
    return o;
}

LevelsPlacement levelsPlacement(const BakeRequest& r) {
    LevelsPlacement p;
    p.kind = parseLayoutKind(r.layout);
    p.refine = *r.refine;
    p.levels = *r.levels;
    p.refineDistance = *r.refineDistance;
    return p;
}

}  // namespace bake_detail
}  // namespace vdblight
