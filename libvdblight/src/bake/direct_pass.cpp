// `bake --direct runtime | occlusion` (bake_direct.h): light selection and visibility channels.

#include "vdblight/bake/each_pass.h"

#include <algorithm>
#include <numeric>

#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "shadow_edge_lattice.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "basis/shadow_edges.h"
#include "bake/light_reach.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// Sample streams of the ranking and visibility rays (independent of the gather's).
constexpr uint64_t kRankStream = 0xd1ec7a11ull, kVisibilityStream = 0x7151b1eull;
constexpr int kMaxLights = 16;
constexpr int kMaxSplit = 4;

/// The chosen lights with each quad as its pieces (DirectOptions::splitLights), each piece's
/// contribution an equal share of its light's (the ranking's figure, reported, not re-measured);
/// ValueError if they are more than kMaxLights.
void splitChosenLights(DirectPlan& plan, int pieces) {
    std::vector<SceneLight> lights;
    std::vector<double> contribution;
    for (std::size_t i = 0; i < plan.lights.size(); ++i) {
        const std::vector<DirectLight> split = splitQuadLight(plan.lights[i].light, pieces);
        if (split.size() == 1) {
            lights.push_back(plan.lights[i]);
            contribution.push_back(plan.contribution[i]);
            continue;
        }
        for (const DirectLight& piece : split) {
            lights.push_back(freeLight(piece));  // its visibility samples the piece only
            contribution.push_back(plan.contribution[i] / double(split.size()));
        }
    }
    if (lights.size() > std::size_t(kMaxLights))
        throw ValueError("--split-lights " + std::to_string(pieces) + ": the " + std::to_string(plan.lights.size()) +
                         " chosen lights make " + std::to_string(lights.size()) + " listed lights, more than " +
                         std::to_string(kMaxLights) + " (lower --split-lights or --direct-lights)");
    plan.lights = std::move(lights);
    plan.contribution = std::move(contribution);
}

}  // namespace

void checkDirectLightCounts(int maxLights, int splitLights) {
    if (maxLights < 1 || maxLights > kMaxLights)
        throw ValueError("--direct-lights must be between 1 and " + std::to_string(kMaxLights) + ", got " +
                         std::to_string(maxLights));
    if (splitLights < 1 || splitLights > kMaxSplit)
        throw ValueError("--split-lights must be between 1 and " + std::to_string(kMaxSplit) + ", got " +
                         std::to_string(splitLights));
}

DirectPlan planDirectLight(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const DirectOptions& o) {
    DirectPlan plan;
    plan.mode = o.mode;
    if (o.mode == DirectMode::Baked) return plan;
    checkDirectLightCounts(o.maxLights, o.splitLights);
    std::vector<SceneLight> all = sceneLights(scene);
    plan.sceneLightCount = all.size();
    if (all.empty() && o.mode == DirectMode::Occlusion)
        throw ValueError("--direct occlusion: the scene has no lights (emissive triangles, point, spot or directional "
                         "lights); the sky stays in the volume");
    // Measured contribution: at evenly strided nodes, mean irradiance x visibility, per light.
    const std::size_t nodes = grid.nodeCount();
    const std::size_t stride = std::max<std::size_t>(1, nodes / std::max<uint32_t>(1, o.rankingNodes));
    const std::size_t ranked = (nodes + stride - 1) / stride;
    std::vector<double> perNode(ranked * all.size(), 0.0);
    bake_detail::forEachItemInParallel(ranked, o.threads, nullptr, [&](std::size_t r, RayCount& rays) {
        const std::size_t n = r * stride;
        const Vec3f x(grid.node(n));
        for (std::size_t i = 0; i < all.size(); ++i) {
            const double mean = luminance(meanIrradiance(all[i].light, Vec3d(x)));
            if (!(mean > 0)) continue;
            const uint64_t stream = hashCombine(hashCombine(o.seed ^ kRankStream, n), i);
            perNode[r * all.size() + i] = mean * lightVisibility(scene, tracer, all[i], x, o.rankingSamples, stream, rays);
        }
    });
    std::vector<double> total(all.size(), 0.0);
    for (std::size_t r = 0; r < ranked; ++r)  // fixed order: deterministic
        for (std::size_t i = 0; i < all.size(); ++i) total[i] += perNode[r * all.size() + i];
    const double sum = std::accumulate(total.begin(), total.end(), 0.0);
    std::vector<std::size_t> order(all.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return total[a] > total[b]; });
    const std::size_t keep = o.mode == DirectMode::Runtime ? all.size() : std::min<std::size_t>(all.size(), std::size_t(o.maxLights));
    for (std::size_t k = 0; k < keep; ++k) {
        const std::size_t i = o.mode == DirectMode::Runtime ? k : order[k];  // runtime: scene order
        plan.lights.push_back(all[i]);
        plan.contribution.push_back(sum > 0 ? total[i] / sum : 0.0);
    }
    // The receivers leave the chosen lights out whole: the filter knows their scene triangles,
    // which their pieces (free lights) do not carry.
    plan.filter = receiverFilter(scene, plan.lights);
    if (o.mode == DirectMode::Occlusion && o.splitLights > 1) splitChosenLights(plan, o.splitLights);
    return plan;
}

void bakeLightVisibility(const Scene& scene, const Tracer& tracer, const DirectPlan& plan, const DirectOptions& o,
                         Volume& volume, Interrupter* interrupter, const NodeMask* only) {
    volume.direct.mode = plan.mode;
    volume.direct.lights.clear();
    for (const SceneLight& l : plan.lights) volume.direct.lights.push_back(l.light);
    if (!volume.direct.hasVisibility()) return;
    if (volume.levels.size() != 1 || volume.levels[0].sparse())
        throw ValueError("--direct occlusion needs a single-level (uniform) volume");
    VolumeLevel& level = volume.levels[0];
    const GridSpec& grid = level.grid;
    const std::size_t lights = plan.lights.size();
    level.lightVisibility.assign(level.heldNodes() * lights, 1.0f);  // a tile: its window (tiles.h)
    level.lightShadowEdges.clear();
    if (o.shadowEdges) level.lightShadowEdges.assign(level.heldNodes() * lights * shadow_edge::kFloatsPerLight, 0.0f);
    std::vector<std::size_t> selected;  // a tile's nodes (tiles.h)
    if (only) {
        if (only->size() != 1 || (*only)[0].size() != grid.nodeCount()) throw ValueError("the node mask does not match the grid");
        for (std::size_t n = 0; n < grid.nodeCount(); ++n)
            if ((*only)[0][n]) selected.push_back(n);
    }
    // The visibility channels first: the edges' search reads them (shadow_edge_lattice.h).
    std::vector<bake_detail::LightReach> reach;  // where a light can add nothing (behind a one-sided polygon, outside a spot's cone)
    reach.reserve(plan.lights.size());
    for (const SceneLight& l : plan.lights) reach.emplace_back(l.light);
    const auto visibilityOf = [&](std::size_t n, std::size_t i, RayCount& rays) {
        const Vec3f x(grid.node(n));
        if (!reach[i].reaches(Vec3d(x))) return 1.0f;  // see bake_direct.h
        const uint64_t stream = hashCombine(hashCombine(o.seed ^ kVisibilityStream, n), i);
        return float(lightVisibility(scene, tracer, plan.lights[i], x, o.visibilitySamples, stream, rays));
    };
    bake_detail::ParallelRun run = bake_detail::forEachItemInParallel(
        only ? selected.size() : grid.nodeCount(), o.threads, interrupter, [&](std::size_t item, RayCount& rays) {
            const std::size_t n = only ? selected[item] : item;
            for (std::size_t i = 0; i < lights; ++i) level.lightVisibility[level.held(n) * lights + i] = visibilityOf(n, i, rays);
        });
    // A tile without nodes has no edges to bake (bakeShadowEdgesOnLattice reads an empty node
    // list as every node, which would write past the tile's empty window).
    if (o.shadowEdges && !(only && selected.empty())) {
        // A neighbour outside a tile is computed again, with its own stream: the same value.
        const auto storedOrComputed = [&](std::size_t n, std::size_t i, RayCount& rays) {
            const bool stored = only ? bool((*only)[0][n]) : true;
            return stored ? level.lightVisibility[level.held(n) * lights + i] : visibilityOf(n, i, rays);
        };
        const bake_detail::EdgeLatticeRun edges = bake_detail::bakeShadowEdgesOnLattice(
            scene, tracer, plan.lights, level, selected, storedOrComputed, o.threads, interrupter);
        run.rays += edges.rays;
        run.seconds += edges.seconds;
    }
    bake_detail::PassMetadata metadata(volume.meta);
    metadata.count("direct_visibility_samples", int64_t(o.visibilitySamples))
        .count("direct_visibility_rays", int64_t(run.rays.total()));
    // Only where it changed the list: a whole-light bake's file stays as before.
    if (o.splitLights > 1) metadata.count("direct_split_lights", int64_t(o.splitLights));
    // The wall time goes into the bake's own (the one metadata entry that may differ between
    // runs with the same seed, besides the thread count).
    if (auto it = volume.meta.find("bake_seconds"); it != volume.meta.end() && std::holds_alternative<double>(it->second))
        it->second = std::get<double>(it->second) + run.seconds;
}

}  // namespace vdblight
