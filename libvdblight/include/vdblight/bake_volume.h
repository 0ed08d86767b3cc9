// bakeVolume: the one entry point of a bake, the same one `vdblight bake` calls, so that a
// library caller and the command line get the same file for the same request (tested:
// tests/bake_volume_test.cpp).
//
// It does what a bake needs around its pass (pass.h): picks the pass the options select,
// applies the --quality preset, checks every option and combination (ValueError, one line,
// before anything is allocated), places the grid with the pass's memory estimate (refusing
// grids that would not fit), plans the direct light out of the basis, runs the pass, adds
// depth moments and light visibility, places the volume in the world (the scene's origin),
// writes the provenance metadata and, for bakeToFile, writes the file or one tile of it.
//
//   BakeRequest request;              // the defaults of `vdblight bake`
//   request.resolution = 16;
//   request.quality = "preview";
//   bakeToFile(scene, request, "room.vdb");
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdblight/bake_adaptive.h"
#include "vdblight/bake_depth.h"
#include "vdblight/bake_direct.h"
#include "vdblight/bake_levels.h"
#include "vdblight/math.h"
#include "vdblight/pass.h"
#include "vdblight/photons.h"
#include "vdblight/solid_cull.h"
#include "vdblight/vdb_io.h"

namespace vdblight {

/// Everything a bake is asked to do: the options of `vdblight bake`, with its defaults. An
/// empty optional means "not given": the pass's default or the --quality preset's.
struct BakeRequest {
    /// Registry name (pass.h); empty: the pass the options below select, as the command
    /// line does (photons for method "photons", bins for a bins/moment basis, levels for a
    /// bilevel/adaptive layout, adaptive for an error target, antialiased for that
    /// sampling, gather otherwise).
    std::string pass;
    std::string method = "gather";    ///< gather | photons
    std::string sampling = "point";   ///< point | antialiased
    std::string layout = "uniform";   ///< uniform | bilevel | adaptive
    /// sh2 | sh:N | bins:R | moment:n[:R] (basis.h); empty: the --quality preset's (sh:4 for
    /// the point gather at `default`, sh2 for every other pass and preset).
    std::string basis;
    /// preview | default | high: node budget, rays, error target, probe passes and depth
    /// moments of the uniform SH point gather (docs/methods.md, "The default bake").
    std::string quality = "default";

    // Shared by every pass (BakeContext).
    uint64_t seed = 1;
    int threads = 0;  ///< 0 = all hardware threads
    TransportOptions transport;

    // Where the nodes go (layout.h, node_budget.h).
    std::optional<double> spacing;     ///< distance between nodes
    std::optional<int> resolution;     ///< nodes along the longest axis (default 16)
    std::optional<uint64_t> nodes;     ///< about this many nodes by volume (the preset's)
    std::optional<Bounds> bounds;      ///< node box in world coordinates (default: inset scene box)
    std::optional<int> refine;         ///< bilevel/adaptive: K (default 3)
    std::optional<int> levels;         ///< adaptive: levels (default 3)
    std::optional<double> refineDistance;  ///< bilevel/adaptive: refine within this distance
    bool cullSolids = false;           ///< bilevel/adaptive with sh2 (solid_cull.h)

    // Pass options (declared by the passes: Pass::options()).
    std::optional<uint32_t> rays;          ///< rays per node and pass (antialiased: per cell)
    std::optional<double> targetError;     ///< error-targeted gather (bake_adaptive.h)
    std::optional<uint32_t> minRays, maxRays;
    std::optional<int> probePasses;        ///< probe-to-probe passes (GatherOptions)
    std::string probeCache;                ///< nodes | surface (GatherOptions::surfaceProbeCache); unset:
                                           ///< surface with exactly one probe pass, nodes otherwise
    std::optional<double> invalidateBackface;  ///< point gather with back-face invalidation
    std::string domain;                    ///< antialiased: all | interior (default)
    std::string fit;                       ///< antialiased: projection (default) | least-squares
    std::optional<uint64_t> photons;       ///< photons: emitted in total (default 4 M; --quality preview 1 M)
    bool compact = false;                  ///< photons: the compact colour + direction form
    bool shWindow = false;                 ///< SH passes: window the bands (sh_window.h)

    // Shared features the passes take or refuse (Pass::takes*).
    /// baked | runtime | occlusion (bake_direct.h); empty: occlusion where the pass takes
    /// direct light and the scene has lights, baked otherwise.
    std::string direct;
    int directLights = 4;                  ///< occlusion: lights with a visibility channel
    std::optional<bool> depthMoments;      ///< default: the preset's
    std::optional<uint32_t> depthRays;     ///< default: as many as the rays

    // The file.
    bool halfFloat = false;
    bool reproducible = true;  ///< leave run-specific metadata out (vdb_io.h)
    /// One tile of a bake (tiles.h, bakeToFile only): `tiles` > 0 and 0 <= tile < tiles.
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
    uint64_t culledNodes = 0;        ///< left out inside solids (solid_cull.h)
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
    /// A tile of a photon bake: the sums of its batches (photon_sums.h), which bakeToFile
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

/// The --quality presets, in order of cost: preview, default, high.
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
