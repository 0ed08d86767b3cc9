// Declaring a pass's options (PassOption, bake/bake.h) in one line each: the name and type,
// its range or words, and the refusal when another pass is given it. (Internal to the bake
// module; the passes' files use it.)
#pragma once

#include <functional>

#include <limits>
#include <type_traits>
#include <optional>
#include <string>
#include <vector>

#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"

namespace vdblight::bake_detail {

constexpr double kNoMax = std::numeric_limits<double>::infinity();

/// `text` as a number for option `name` (ValueError: one line naming the option).
double parseOptionNumber(const std::string& name, const std::string& text, bool integer);
bool isWholeNumber(double v);

/// An option's description (name, help, default, range, refusal elsewhere).
PassOption describeOption(std::string name, std::string help, std::string defaultValue, double min, double max,
                          std::string needs = {}, std::string range = {});

/// A number of type T (whole for integer types, not negative for unsigned ones).
template <typename T>
PassOption numberOption(std::string name, std::string help, std::string defaultValue, double min, double max,
                        std::string needs = {}, std::string range = {}) {
    PassOption o = describeOption(std::move(name), std::move(help), std::move(defaultValue), min, max, std::move(needs),
                                  std::move(range));
    o.integer = std::is_integral_v<T>;
    o.nonNegative = std::is_unsigned_v<T>;
    return o;
}

/// An on/off flag, off by default (given = on).
PassOption flagOption(std::string name, std::string help, std::string needs = {});

/// A word among `choices` (given = set).
PassOption wordOption(std::string name, std::string help, std::string defaultValue, std::vector<std::string> choices,
                      std::string needs = {});

/// The declared options every pass that gathers SH or bins at nodes shares.
PassOption raysOption(const std::string& help);
PassOption depthMomentsOption();
PassOption depthRaysOption();
PassOption shWindowOption();
PassOption probePassesOption();

/// The basis text names SH order 2 (bins.h parses it; ValueError for an unknown basis).
bool isSh2(const std::string& basis);
/// True for real SH of any order (sh2, sh:N): what the uniform point gather stores
/// (GatherOptions::basis), probe passes, depth moments and direct light included.
bool isRealSh(const std::string& basis);
/// Greger bins or moments (bins.h), which keep their own gather (bakeBins).
bool isBinsOrMoment(const std::string& basis);

/// An error target's ray caps when --min-rays / --max-rays are not given (bake_adaptive.h).
constexpr uint32_t kTargetMinRays = 64, kTargetMaxRays = 2048;

/// "a, b or c".
std::string joinChoices(const std::vector<std::string>& words);

/// What a field of the resolved request is under each --quality preset (resolveBakeRequest
/// of a request with only `method` and the preset given), for --help: "V" if every preset
/// gives V, else "V1 with --quality preview, V2 with default, V3 with high". The help of the
/// presets' options comes from here, so that it cannot drift from the code (issue 29).
std::string presetValues(const std::function<std::string(const BakeRequest&)>& field, const std::string& method = "gather");
/// presetValues of a number option ("1024 with --quality preview, ...").
std::string presetNumbers(const std::string& option, const std::string& method = "gather");

/// The tile selection of a context as a function of the levels (null without tiles).
inline const NodeMask* selectTile(const BakeContext& c, const std::vector<LevelTopology>& levels) {
    return c.selectTile ? c.selectTile(levels) : nullptr;
}

/// Whether the option is given in a way another pass refuses: a number (but a zeroIsUnset
/// option's 0), a flag switched on, a word.
bool givenToRefuse(const PassOption& option, const PassParameters& params);

/// The point gather's options from a resolved request (bake.h): shared by gather and levels.
GatherOptions gatherOptions(const BakeContext& c, const BakeRequest& r);

/// The multi-level placement of a resolved request (layout_levels.h).
LevelsPlacement levelsPlacement(const BakeRequest& r);

}  // namespace vdblight::bake_detail
