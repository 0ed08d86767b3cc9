// The Pass interface: one kind of bake (point gather, error-targeted gather, anti-aliased
// gather, multi-level gather, bins, photons) behind one small contract, so that
// bakeVolume (bake_volume.h) and `vdblight bake` treat every pass alike.
//
// A pass
//  - declares the options it takes (PassOption: name, meaning, default, accepted range or
//    words), which BakeRequest fields they are;
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
#include <optional>
#include <string>
#include <vector>

#include "vdblight/layout.h"
#include "vdblight/level_topology.h"
#include "vdblight/light.h"
#include "vdblight/tiles.h"
#include "vdblight/vdb_io.h"
#include "vdblight/volume.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;
struct BakeRequest;
struct BakeReport;
struct BakeSummaryInput;

/// One option of a pass: a BakeRequest field, named as on the command line (`--name`).
struct PassOption {
    std::string name;          ///< "rays": `vdblight bake --rays`
    std::string help;          ///< what it means, one sentence
    std::string defaultValue;  ///< the default, as text ("256", "interior", "off")
    /// Numbers: the accepted range [min, max] (minExclusive: (min, max]); checked by
    /// Pass::validate with the message "--name must be <range>, got <value>".
    double min = 0, max = 0;
    bool minExclusive = false;
    std::string range;  ///< the range in words ("at least 2"); empty: "between min and max"
    /// Words: the accepted values (empty for numbers and flags).
    std::vector<std::string> choices;
    /// The request's value if it was given (nullopt: the pass's default). Numbers and flags
    /// set `number` (flags: 1 when on), words `word`.
    std::function<std::optional<double>(const BakeRequest&)> number;
    std::function<std::optional<std::string>(const BakeRequest&)> word;
    /// Sets the option in a request (numbers and flags), for tests and generic callers.
    std::function<void(BakeRequest&, double)> setNumber;
    /// Sets the option from its text, as a command line gives it (numbers: ValueError naming
    /// the option for text that is not one; words as given; flags: "true" / "false").
    std::function<void(BakeRequest&, const std::string&)> setText;
    bool flag = false;       ///< an on/off switch (`--name`)
    bool negatable = false;  ///< a flag that may also be switched off (`--no-name`): its default is not "off"
    /// The one-line refusal when the option is given to a pass that does not declare it
    /// ("--fit needs --sampling antialiased"); empty: other passes ignore it.
    std::string needs;
};

/// What every pass runs on. Built once per bake by bakeVolume.
struct BakeContext {
    const Scene& scene;
    const Tracer& tracer;
    /// The request's transport, with the direct-light plan's receiver filter (bake_direct.h).
    TransportOptions transport;
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    Interrupter* interrupter = nullptr;
    /// A tile of a bake (tiles.h): called once the pass knows its levels, returns the nodes
    /// to bake (null: every node). Empty function: not tiled.
    std::function<const NodeMask*(const std::vector<LevelTopology>&)> selectTile;
    /// A staged bake with probe passes (tiles.h): -1 = every pass; else this pass only, from
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
    /// The shared features a pass may take: direct light out of the basis (bake_direct.h),
    /// the SH window (sh_window.h), depth moments (bake_depth.h).
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
    /// bake_volume.h): lines ending in '\n'. The base writes the node gathers' summary
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
