// The bake: the Pass interface (below) and bakeVolume / bakeToFile, the one entry point of
// every bake (second part).
//
// The Pass interface: one kind of bake (point gather, error-targeted gather, anti-aliased
// gather, multi-level gather, bins, photons) behind one small contract, so that
// bakeVolume (bake/bake.h) and `vdblight bake` treat every pass alike.
//
// A pass
//  - declares the options it takes (PassOption: name, meaning, default, accepted range or
//    words) and reads them from the request's PassParameters;
//  - validates a request (typed exceptions with one-line messages, before anything is
//    loaded or allocated);
//  - estimates the bytes per node it needs, which the grid placement uses to refuse a bake
//    that would not fit in memory before allocating it;
//  - writes the summary `vdblight bake` prints of what it baked (summary and its parts);
//  - runs on a BakeContext shared by every pass (scene, tracer, transport, seed, threads,
//    interrupter, the tile being baked) and writes its metadata through the bake module's
//    one metadata writer (bake/pass_metadata.h).
// The passes are listed once, in passRegistry() (bake/pass_registry.cpp); adding one is a
// file in libvdblight/src/bake/ and one line there (docs/architecture.md, "Adding a pass").
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "vdblight/bake/each_pass.h"
#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/core/math.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;
struct BakeRequest;
struct BakeReport;
struct BakeSummaryInput;

/// One option of a pass, named as on the command line (`--name`): its value lives in the
/// request's PassParameters under that name.
struct PassOption {
    enum class Kind { Number, Word, Flag };
    std::string name;          ///< "rays": `vdblight bake --rays`
    std::string help;          ///< what it means, one sentence
    /// The default, as text ("256", "interior", "off"). A number, one of the words or a flag's
    /// "off" is also the value PassParameters::get answers when the option is not given; other
    /// text ("the --quality preset's") is a default resolveBakeRequest fills in.
    std::string defaultValue;
    /// Numbers: the accepted range [min, max] (minExclusive: (min, max]); checked by
    /// Pass::validate with the message "--name must be <range>, got <value>".
    double min = 0, max = 0;
    bool minExclusive = false;
    std::string range;  ///< the range in words ("at least 2"); empty: "between min and max"
    bool integer = false;      ///< numbers: whole numbers only
    bool nonNegative = false;  ///< numbers: text with a minus sign is refused as it is read
    /// Numbers: 0 is what passes without the option do (--probe-passes 0), so 0 counts as
    /// not given: another pass does not refuse it.
    bool zeroIsUnset = false;
    /// Words: the accepted values (empty for numbers and flags).
    std::vector<std::string> choices;
    bool flag = false;       ///< an on/off switch (`--name`)
    bool negatable = false;  ///< a flag that may also be switched off (`--no-name`): its default is not "off"
    /// The one-line refusal when the option is given to a pass that does not declare it
    /// ("--fit needs --sampling antialiased"); empty: other passes ignore it.
    std::string needs;

    Kind kind() const { return flag ? Kind::Flag : choices.empty() ? Kind::Number : Kind::Word; }
};

/// A pass option's value as given: a number, a flag or a word.
using PassValue = std::variant<double, bool, std::string>;

/// The options of the passes in a request, by name (pbrt-v4's ParameterDictionary, Mitsuba's
/// Properties): the request carries them, and each pass reads those it declares
/// (Pass::options) into its own options struct, so that a new pass needs no new field here.
///
///   request.params.set("rays", 64).set("domain", "all").set("compact", true);
///   const uint32_t rays = request.params.get<uint32_t>("rays");
///
/// Names and kinds are checked against the passes' declarations (passOptionTable): a name no
/// pass declares, or a value of another kind (a word for a number), is a ValueError.
class PassParameters {
public:
    /// Numbers (any arithmetic type but bool).
    template <typename T, std::enable_if_t<std::is_arithmetic_v<T> && !std::is_same_v<T, bool>, int> = 0>
    PassParameters& set(const std::string& name, T value) {
        return setValue(name, double(value));
    }
    PassParameters& set(const std::string& name, bool on) { return setValue(name, on); }
    PassParameters& set(const std::string& name, std::string word) { return setValue(name, std::move(word)); }
    PassParameters& set(const std::string& name, const char* word) { return setValue(name, std::string(word)); }
    /// As a command line gives it: numbers parsed (ValueError naming the option for text that
    /// is not one), words as given, flags "true" / "false". An empty word unsets the option.
    PassParameters& setText(const std::string& name, const std::string& text);
    PassParameters& unset(const std::string& name);
    /// Set (given, or filled in by resolveBakeRequest).
    bool has(const std::string& name) const { return values_.count(name) > 0; }

    /// The value as set, else the declared default (PassOption::defaultValue); T an arithmetic
    /// type for numbers, bool for flags, std::string for words. ValueError for an unknown name,
    /// another kind, or an option with neither a value nor a default of its own (one that
    /// resolveBakeRequest fills in, asked of a request that was not resolved).
    template <typename T>
    T get(const std::string& name) const {
        return convert<T>(name, *lookup(name, kindOf<T>(), true));  // with a default: never empty
    }
    /// The value as set, or nullopt (no default); the same checks of the name and kind.
    template <typename T>
    std::optional<T> find(const std::string& name) const {
        const std::optional<PassValue> v = lookup(name, kindOf<T>(), false);
        return v ? std::optional<T>(convert<T>(name, *v)) : std::nullopt;
    }

    /// For the presets only (resolveBakeRequest), which run while the declarations are being
    /// built (their help quotes the presets): the value as set (null if not) and setting one,
    /// without looking at the declarations.
    const PassValue* value(const std::string& name) const;
    void preset(const std::string& name, PassValue value) { values_[name] = std::move(value); }

private:
    template <typename T>
    static PassOption::Kind kindOf() {
        if constexpr (std::is_same_v<T, bool>) return PassOption::Kind::Flag;
        else if constexpr (std::is_same_v<T, std::string>) return PassOption::Kind::Word;
        else return PassOption::Kind::Number;
    }
    /// A number as T; ValueError for one T cannot hold (-4 asked for as uint32_t: Pass::validate
    /// refuses it first where the range is declared).
    template <typename T>
    static T convert(const std::string& name, const PassValue& v) {
        if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>) {
            return std::get<T>(v);
        } else {
            const double number = std::get<double>(v);
            if (std::is_integral_v<T> && !(number >= double(std::numeric_limits<T>::lowest()) &&
                                           number <= double(std::numeric_limits<T>::max())))
                outOfRange(name, number);
            return T(number);
        }
    }
    [[noreturn]] static void outOfRange(const std::string& name, double value);
    PassParameters& setValue(const std::string& name, PassValue value);
    std::optional<PassValue> lookup(const std::string& name, PassOption::Kind kind, bool withDefault) const;

    std::map<std::string, PassValue> values_;
};

/// What every pass runs on. Built once per bake by bakeVolume.
struct BakeContext {
    const Scene& scene;
    const Tracer& tracer;
    /// The request's transport, with the direct-light plan's receiver filter (bake/each_pass.h).
    TransportOptions transport;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    Interrupter* interrupter = nullptr;
    /// A tile of a bake (volume/tiles.h): called once the pass knows its levels, returns the nodes
    /// to bake (null: every node). Empty function: not tiled.
    std::function<const NodeMask*(const std::vector<LevelTopology>&)> selectTile;
    /// A staged bake with probe passes (volume/tiles.h): -1 = every pass; else this pass only, from
    /// `stageInput` (the merged stage before) when stage > 0.
    int stage = -1;
    const Volume* stageInput = nullptr;
};

class Pass {
public:
    virtual ~Pass() = default;

    /// Registry name: "gather", "adaptive", "antialiased", "levels", "bins", "photons".
    virtual std::string name() const = 0;
    /// One line: what the pass does (for --help and docs).
    virtual std::string description() const = 0;
    /// The options the pass takes.
    virtual std::vector<PassOption> options() const = 0;
    /// Throws ValueError (one line) for a given option outside its declared range or words,
    /// and for combinations the pass cannot bake. The base checks the declared ranges and
    /// words; passes add their own rules first and call it.
    virtual void validate(const BakeRequest& request) const;
    /// Bytes per node while baking and writing (a resolved request, resolveBakeRequest),
    /// before anything is allocated: placeUniformGrid refuses grids that would not fit.
    virtual std::size_t bytesPerNode(const BakeRequest& request) const = 0;
    /// Why a bake with these options cannot be split into tiles, or "" if it can.
    virtual std::string untileable(const BakeRequest& request) const = 0;
    /// The shared features a pass may take: direct light out of the basis (bake/each_pass.h),
    /// the SH window (sh_window.h), depth moments (bake/each_pass.h).
    virtual bool takesDirectLight() const { return false; }
    virtual bool takesShWindow() const { return false; }
    virtual bool takesDepthMoments() const { return true; }
    /// Bakes the volume on `grid` (level 0; passes with levels place them over it) for a
    /// resolved request. Fills report.stats and the pass's own parts of the report.
    virtual Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
                       BakeReport& report) const = 0;
    /// The last step before writing (photons --compact: the compact form, half floats).
    virtual void finish(Volume& volume, WriteOptions& write, const BakeRequest& request) const;

    /// What `vdblight bake` prints after this pass baked a file or a tile of it (bakeSummary,
    /// below): lines ending in '\n'. The base writes the node gathers' summary
    /// (bake/bake_summary.cpp) with the parts below, which passes override; the photon pass
    /// writes its own.
    virtual std::string summary(const BakeSummaryInput& in) const;
    /// Lines before the shared ones: what the pass did before the file was written (the error
    /// target reached, the levels and the nodes culled). None by default.
    virtual std::string summaryLead(const BakeSummaryInput&) const { return {}; }
    /// The rays per node of the summary's "Baked" line ("1024", "error-targeted").
    virtual std::string summaryRays(const BakeSummaryInput& in) const;
    /// Appended to the line's rays per second (" (sampling antialiased, domain interior)").
    virtual std::string summaryRayNote(const BakeSummaryInput&) const { return {}; }
    /// What the file holds, after "Wrote OUT": "(basis sh:4: ..., 25 Vec3f grids)".
    virtual std::string summaryStored(const BakeSummaryInput& in) const;
};

/// Every pass, in the order `vdblight bake --help` lists them.
const std::vector<const Pass*>& passRegistry();
/// The pass of that name; ValueError naming the known ones otherwise.
const Pass& findPass(const std::string& name);

/// An option as a command line offers it: declared by one or more passes, once per name.
struct PassOptionEntry {
    PassOption option;                ///< the first declaration (its help, default, range)
    std::vector<std::string> passes;  ///< the passes that declare it, in the registry's order
    std::string help;                 ///< option.help + " [pass gather]" or " [passes gather, levels]"
};
/// Every option the passes declare, in the order of the registry: what `vdblight bake` offers
/// and lists in --help, so that a new pass's options need no edit of the command line.
std::vector<PassOptionEntry> passOptionTable();

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// bakeVolume: the one entry point of a bake, the same one `vdblight bake` calls, so that a
// library caller and the command line get the same file for the same request (tested:
// tests/bake_volume_test.cpp).
//
// It does what a bake needs around its pass (bake/bake.h): picks the pass the options select,
// applies the --quality preset, checks every option and combination (ValueError, one line,
// before anything is allocated), places the grid with the pass's memory estimate (refusing
// grids that would not fit), plans the direct light out of the basis, runs the pass, adds
// depth moments and light visibility, places the volume in the world (the scene's origin),
// writes the provenance metadata and, for bakeToFile, writes the file or one tile of it.
//
//   BakeRequest request;              // the defaults of `vdblight bake`
//   request.resolution = 16;
//   request.quality = "preview";
//   request.params.set("rays", 64);   // a pass's own option, named as on the command line
//   bakeToFile(scene, request, "room.vdb");

namespace vdblight {

/// Everything a bake is asked to do: the options of `vdblight bake`, with its defaults. An
/// empty optional means "not given": the pass's default or the --quality preset's.
struct BakeRequest {
    /// Registry name (bake/bake.h); empty: the pass the options below select, as the command
    /// line does (photons for method "photons", bins for a bins/moment basis, levels for a
    /// bilevel/adaptive layout, adaptive for an error target, antialiased for that
    /// sampling, gather otherwise).
    std::string pass;
    std::string method = "gather";    ///< gather | photons
    std::string sampling = "point";   ///< point | antialiased
    std::string layout = "uniform";   ///< uniform | bilevel | adaptive
    /// sh2 | sh:N | bins:R | moment:n[:R] (basis/basis.h); empty: the --quality preset's (sh:4 for
    /// the point gather at `default`, sh2 for every other pass and preset).
    std::string basis;
    /// preview | default | high: node budget, rays, error target, probe passes and depth
    /// moments of the uniform SH point gather (docs/methods.md, "The default bake").
    std::string quality = "default";

    // Shared by every pass (BakeContext).
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    TransportOptions transport;

    // Where the nodes go (layout/layout.h); the bilevel/adaptive levels are the options of the
    // passes that place them (params: refine, levels, refine-distance).
    std::optional<double> spacing;     ///< distance between nodes
    std::optional<int> resolution;     ///< nodes along the longest axis (default 16)
    std::optional<uint64_t> nodes;     ///< about this many nodes by volume (the preset's)
    std::optional<Bounds> bounds;      ///< node box in world coordinates (default: inset scene box)

    /// The passes' own options (Pass::options), by name as on the command line:
    /// `params.set("rays", 64)`. Unset: the pass's default or the --quality preset's.
    PassParameters params;

    // Direct light out of the basis, a step of bakeVolume around every pass (the passes that
    // take it: Pass::takesDirectLight; the others bake it into the basis).
    /// baked | runtime | occlusion (bake/each_pass.h); empty: occlusion where the pass takes
    /// direct light and the scene has lights, baked otherwise.
    std::string direct;
    int directLights = 4;                  ///< occlusion: lights with a visibility channel
    bool shadowEdges = true;               ///< occlusion: their shadow edges too (DirectOptions::shadowEdges)
    int splitLights = 1;                   ///< occlusion: each quad light as K x K pieces (DirectOptions::splitLights)

    // The file.
    bool halfFloat = false;
    bool reproducible = true;  ///< leave run-specific metadata out (volume/vdb_io.h)
    /// One tile of a bake (volume/tiles.h, bakeToFile only): `tiles` > 0 and 0 <= tile < tiles.
    std::optional<int> tiles, tile;
    std::optional<int> stage;         ///< one stage of a bake with probe passes
    std::string stageInput;           ///< stage > 0: the merged tiles of the stage before
    /// Tiles: the canonical text of every option that changes the result, the same for
    /// every tile of one bake (the command line's: each option as given); required with tiles.
    std::string tileParameters;

    // Provenance, written as vdblight:scene_file and vdblight:sky.
    std::string sceneFile;  ///< empty: "(in memory)"
    std::string sky;        ///< empty: the scene's constant sky "r,g,b" (or "map")
};

/// The shape of a bilevel / adaptive layout, for summaries.
struct LayoutSummary {
    int levels = 1;
    int refine = 1;
    uint64_t nodes = 0;              ///< stored nodes of every level
    double denseEquivalentNodes = 0; ///< a dense grid at the finest spacing
    uint64_t culledNodes = 0;        ///< left out inside solids (bake/each_pass.h)
};

/// What a bake did, for summaries (the command line prints them).
struct BakeReport {
    const Pass* pass = nullptr;
    BakeRequest resolved;           ///< the request with every default and preset filled in
    GridSpec grid;                  ///< level 0
    LevelsBakeStats stats;          ///< nodes, rays, time, per-node error, seam nodes
    std::optional<AdaptiveStats> adaptive;      ///< error-targeted bakes
    std::optional<LayoutSummary> layout;        ///< bilevel/adaptive
    std::optional<SolidCullStats> cull;         ///< cullSolids
    DirectPlan direct;                          ///< the lights kept out of the basis
    std::optional<DepthStats> depth;            ///< depth moments from their own pass
    std::optional<PhotonStats> photons;
    WriteOptions write;                         ///< how the volume is (to be) written
    // Tiles (bakeToFile).
    bool skipped = false;      ///< the tile was on disk already, with the same scene and parameters
    uint64_t tileNodes = 0;    ///< nodes of the tile
    bool lastStage = true;     ///< false: a probe stage file for the next stage
    /// A tile of a photon bake: the sums of its batches (volume/tiles.h), which bakeToFile
    /// writes with writePhotonTile; the returned volume then holds the grid and metadata only.
    std::shared_ptr<PhotonSums> photonSums;
};

/// What the summary of a bake reads (bakeSummary).
struct BakeSummaryInput {
    const Scene& scene;
    std::string sceneSource;     ///< how the scene file was read (describeSceneSource, scene_load.h)
    std::string output;          ///< the file written
    const BakeRequest& request;  ///< as given (the tile numbers of a skipped tile)
    const BakeReport& report;
    const Volume& volume;        ///< bakeToFile's answer
};

/// What `vdblight bake` prints after bakeToFile, lines ending in '\n': the tile skipped, or
/// the summary of the pass that baked (Pass::summary: grid, rays, time, the file's contents,
/// the noise estimate, or a tile and what to do with it next).
std::string bakeSummary(const BakeSummaryInput& in);

/// The stages of a tiled bake with these options (its probe passes + 1), after the presets;
/// ValueError when they cannot be tiled (for `vdblight slurm`, before any script is written).
int tiledBakeStages(const BakeRequest& request);

/// The request with the --quality preset and every default applied (optionals filled where
/// the pass uses them, `pass` set to the selected pass). Does not validate.
BakeRequest resolveBakeRequest(const BakeRequest& request);

/// The --quality presets, in order of cost: preview, fast, default, high.
const std::vector<std::string>& qualityNames();

/// What a --quality preset bakes with the point gather (and the photon pass), in one line for
/// --help and the README, read off resolveBakeRequest's answer for that preset, so that the
/// help cannot drift from the code (issue 29): grid, rays and probe passes, stored basis,
/// depth moments, direct light, photons. Throws ValueError for an unknown preset.
std::string describeQuality(const std::string& quality);

/// Checks every option and combination (the shared rules, then the selected pass's
/// Pass::validate) and returns the pass that will run. Throws ValueError with one line.
/// Cheap: call it before loading the scene to refuse bad options early.
const Pass& checkBakeRequest(const BakeRequest& request);

/// Bakes a complete volume (no tiles): checked, placed in the world, with every metadata
/// key a file of `vdblight bake` has. Throws ValueError, SceneError, Cancelled.
Volume bakeVolume(const Scene& scene, const BakeRequest& request, Interrupter* interrupter = nullptr,
                  BakeReport* report = nullptr);

/// bakeVolume, then writes `path` atomically (the volume, or with tiles one tile file; a
/// tile already on disk with the same scene and parameters is skipped: report->skipped).
/// Returns the volume written (empty when skipped).
Volume bakeToFile(const Scene& scene, const BakeRequest& request, const std::string& path,
                  Interrupter* interrupter = nullptr, BakeReport* report = nullptr);

}  // namespace vdblight
