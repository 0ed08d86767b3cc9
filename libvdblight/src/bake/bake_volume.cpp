// bakeVolume / bakeToFile (bake_volume.h): everything around a pass (pass.h) that makes a
// bake's file, in one place, so that the command line and a library caller write the
// same bytes.
#include "vdblight/bake/bake.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "pass_metadata.h"
#include "pass_options.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"
#include "bake/direction_guide.h"
#include "bake/sh_window.h"
#include "bake/stage_carry.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/trace/trace.h"
#include "core/world_frame.h"

namespace vdblight {

namespace {

/// The nodes of the stage input a tile of a staged point gather reads (tiles.h): with the
/// surface probe cache (the default's), its own window of nodes plus the guide's pooling reach
/// (stage_carry.h), so that the tile does not hold every node's pass 0 (docs/scaling.md, "Memory
/// of a tile"); every node otherwise (the node cache reads the reflected light anywhere).
NodeWindow stageInputWindow(const BakeRequest& r, const GridSpec& grid) {
    if (!r.tiles || r.pass != "gather" || r.params.get<std::string>("probe-cache") != "surface") return {};
    std::vector<VolumeLevel> levels(1);
    levels[0].grid = grid;
    if (*r.tiles < 1 || uint64_t(*r.tiles) > countBricks(levels)) return {};  // refused later, with its own message
    const NodeMask mask = tileNodeMask(levels, *r.tiles, *r.tile);
    setTileWindows(levels, &mask);  // the window the gather's tile will hold
    const std::size_t first = levels[0].windowFirst, end = first + levels[0].heldNodes();
    const std::size_t reach = bake_detail::stageReach(grid, bake_detail::DirectionGuide::kPoolRadius);
    const std::size_t from = first > reach ? first - reach : 0, to = std::min(grid.nodeCount(), end + reach);
    return {from, to - from};
}
/// One tile of a bake being baked (bakeToFile).
struct TileJob {
    TileId id;
    NodeMask mask;
    std::string sameBake;  ///< the hash every stage of one bake shares (tiles.h, "Staged bakes")
    ContentHash stageInput;  ///< stage > 0: the stage input's content hash (hashed once: parameters, damage check)
};

/// Every stage of one bake has the same options but --stage (and maybe --tiles): their hash
/// ties a stage file to the stages after it.
std::string sameBakeHash(const Scene& scene, const BakeRequest& r) {
    std::string others;
    std::istringstream lines(r.tileParameters);
    for (std::string line; std::getline(lines, line);)
        if (line.compare(0, 8, "--stage=") != 0 && line.compare(0, 8, "--tiles=") != 0) others += line + "\n";
    return tileParamsHash(scene.contentHash(), others);
}

std::string skyText(const Scene& scene, const BakeRequest& r) {
    if (!r.sky.empty()) return r.sky;
    if (scene.sky.map) return "map:" + scene.sky.map->path;
    std::ostringstream s;
    s << scene.sky.constant.x << "," << scene.sky.constant.y << "," << scene.sky.constant.z;
    return s.str();
}

/// The direct-light options of a resolved request for its pass; automatic: occlusion where
/// the pass takes it and the scene has lights (docs/methods.md, "Direct light out of the SH").
DirectOptions directOptions(const Scene& scene, const BakeRequest& r, const Pass& pass) {
    DirectOptions d;
    d.maxLights = r.directLights;
    d.shadowEdges = r.shadowEdges;
    d.splitLights = r.splitLights;
    d.seed = r.seed;
    d.threads = r.threads;
    if (!r.direct.empty()) {
        d.mode = parseDirectMode(r.direct);
    } else {
        const bool applies = pass.takesDirectLight() && !r.params.get<bool>("sh-window");
        d.mode = applies && !sceneLights(scene).empty() ? DirectMode::Occlusion : DirectMode::Baked;
    }
    return d;
}

Volume bakeImpl(const Scene& scene, const BakeRequest& given, Interrupter* interrupter, BakeReport& report,
                TileJob* tile) {
    const Pass& pass = checkBakeRequest(given);
    const BakeRequest r = resolveBakeRequest(given);
    if (r.tiles && !tile) throw ValueError("a tile of a bake is written by bakeToFile, not returned by bakeVolume");
    report.pass = &pass;
    report.resolved = r;

    GridPlacement placement;
    placement.spacing = r.spacing.value_or(0.0);
    placement.resolution = (r.spacing || r.resolution || r.nodes) ? r.resolution.value_or(0) : kDefaultResolution;
    if (r.bounds) placement.bounds = toLocalBounds(*r.bounds, scene.origin);
    if (r.nodes) placement.spacing = spacingForNodeBudget(placement.bounds ? *placement.bounds : scene.bounds(), *r.nodes);
    const GridSpec grid = placeUniformGrid(scene.bounds(), placement, pass.bytesPerNode(r));
    report.grid = grid;

    const Tracer tracer(scene);
    const DirectOptions direct = directOptions(scene, r, pass);
    report.direct = planDirectLight(scene, tracer, grid, direct);  // baked: an empty plan

    BakeContext context{scene, tracer, r.transport, r.seed, r.threads, interrupter, {}, r.stage.value_or(-1), nullptr};
    context.transport.skipAtReceiver = report.direct.filter;
    // A staged bake (tiles.h): this pass only, from the merged tiles of the stage before.
    Volume stageInput;
    if (r.stage && *r.stage > 0) {
        stageInput = readProbeStage(r.stageInput, tile ? &tile->stageInput : nullptr, stageInputWindow(r, grid));
        if (metaString(stageInput.meta, "probe_stage_params_hash") != tile->sameBake)
            throw ValueError("'" + r.stageInput + "' is a stage of a bake with another scene or other options than --stage " +
                             std::to_string(*r.stage) + " here");
        context.stageInput = &stageInput;
    }
    const PassParameters& options = r.params;
    report.lastStage = !r.stage || *r.stage == options.get<int>("probe-passes");
    if (tile)
        context.selectTile = [tile, &r](const std::vector<LevelTopology>& levels) -> const NodeMask* {
            tile->mask = tileNodeMask(volumeLevels(levels), *r.tiles, *r.tile);
            return &tile->mask;
        };

    Volume volume = pass.run(context, r, grid, report);
    const bool depthMoments = options.get<bool>("depth-moments");
    if (tile && report.photonSums && depthMoments) {
        // A photon tile holds every node's sums of its batches; depth moments are per node, so
        // it bakes those of its run of nodes only (photonTileDepthNodes, tiles.h).
        tile->mask = photonTileDepthNodes(grid, *r.tiles, *r.tile);
        setTileWindows(volume.levels, &tile->mask);
    }

    const NodeMask* only = tile ? &tile->mask : nullptr;
    if (direct.mode != DirectMode::Baked && report.lastStage)
        bakeLightVisibility(scene, tracer, report.direct, direct, volume, interrupter, only);
    // The levels' refine distance (the passes that place levels declare it; 0 elsewhere).
    const double refineDistance = options.find<double>("refine-distance").value_or(0.0);
    if (refineDistance > 0) bake_detail::PassMetadata(volume.meta).number("refine_distance", refineDistance);
    if (options.get<bool>("sh-window")) applyShWindow(volume);
    if (depthMoments && !volume.hasDepth() && report.lastStage) {  // passes without the gather's hook (bake_depth.h)
        DepthOptions depthOptions;
        depthOptions.raysPerNode = options.find<uint32_t>("depth-rays").value_or(options.get<uint32_t>("rays"));
        depthOptions.seed = r.seed;
        depthOptions.threads = r.threads;
        depthOptions.only = only;
        DepthStats depthStats;
        bakeDepthMoments(tracer, volume, depthOptions, nullptr, &depthStats);
        report.depth = depthStats;
    }
    placeVolumeInWorld(volume, scene.origin);  // baked in the scene's local frame (scene_origin.h)
    bake_detail::PassMetadata(volume.meta).provenance(r.sceneFile.empty() ? std::string("(in memory)") : r.sceneFile,
                                                      skyText(scene, r));
    report.write.halfFloat = r.halfFloat;
    report.write.reproducible = r.reproducible;
    pass.finish(volume, report.write, r);
    return volume;
}
}  // namespace

Volume bakeVolume(const Scene& scene, const BakeRequest& request, Interrupter* interrupter, BakeReport* report) {
    BakeReport local;
    return bakeImpl(scene, request, interrupter, report ? *report : local, nullptr);
}

Volume bakeToFile(const Scene& scene, const BakeRequest& request, const std::string& path, Interrupter* interrupter,
                  BakeReport* reportOut) {
    BakeReport local;
    BakeReport& report = reportOut ? *reportOut : local;
    if (!request.tiles) {
        Volume volume = bakeImpl(scene, request, interrupter, report, nullptr);
        writeVolume(volume, path, report.write);
        return volume;
    }
    checkBakeRequest(request);  // before reading anything
    if (request.tileParameters.empty())
        throw ValueError("a tile needs BakeRequest::tileParameters: the text of the options every tile of the bake shares");
    TileJob tile;
    tile.id.index = *request.tile;
    tile.id.count = *request.tiles;
    // A stage's tiles depend on the stage before's merged file: its content is a parameter.
    const int stage = request.stage.value_or(-1);
    if (stage > 0) tile.stageInput = fileContentHash(request.stageInput);
    const std::string input = stage > 0 ? "stage_input_sha256=" + tile.stageInput.sha256 + "\n" : "";
    tile.id.paramsHash = tileParamsHash(scene.contentHash(), request.tileParameters + input);
    if (stage >= 0) tile.sameBake = sameBakeHash(scene, request);
    TileId onDisk;
    bool done = false;
    std::error_code ec;
    try {  // an unreadable or foreign file there is simply baked over
        done = std::filesystem::exists(path, ec) && readTileId(path, onDisk) && onDisk.index == tile.id.index &&
               onDisk.count == tile.id.count && onDisk.paramsHash == tile.id.paramsHash &&
               fileContentHash(path).uuidFromContent;  // and not damaged since
    } catch (const Error&) {
    }
    if (done) {
        report.skipped = true;
        return {};
    }
    Volume volume = bakeImpl(scene, request, interrupter, report, &tile);
    if (report.photonSums) {  // a photon tile: the whole grid's sums of its batches
        report.photonSums->grid = volume.levels[0].grid;  // placed in the world like the volume
        const VolumeLevel& level = volume.levels[0];
        VolumeLevel tileDepth;  // --depth-moments: those of the tile's run of nodes
        tileDepth.grid = level.grid;
        for (std::size_t n = 0; level.hasDepth() && n < tile.mask[0].size(); ++n) {
            if (!tile.mask[0][n]) continue;
            tileDepth.activeNodes.push_back(n);
            tileDepth.depth.insert(tileDepth.depth.end(), level.nodeDepth(n), level.nodeDepth(n) + depth::kFloatsPerNode);
        }
        writePhotonTile(*report.photonSums, volume.meta, tile.id, path, report.write,
                        report.resolved.params.get<bool>("compact"),
                        level.hasDepth() ? &tileDepth : nullptr);
        report.tileNodes = volume.levels[0].grid.nodeCount();
        return volume;
    }
    // The per-node errors of a uniform grid, for the merge's error summary: those the pass
    // estimated (the point gathers; the other passes leave BakeStats::estimatedError empty).
    TileNodeStats nodeStats;
    if (volume.levels.size() == 1) {
        nodeStats.estimatedError = report.stats.estimatedError;
        nodeStats.firstPassValues = std::move(report.stats.firstPassValues);
        nodeStats.firstPassError = std::move(report.stats.firstPassError);
    }
    if (!report.lastStage) {
        report.write.halfFloat = false;  // the next stage reads the reflected light exactly
        bake_detail::PassMetadata(volume.meta).text("probe_stage_params_hash", tile.sameBake);
    }
    writeTile(volume, tile.mask, tile.id, path, report.write, &nodeStats);
    report.tileNodes = 0;
    for (const auto& l : tile.mask) report.tileNodes += uint64_t(std::count(l.begin(), l.end(), uint8_t(1)));
    return volume;
}

}  // namespace vdblight
