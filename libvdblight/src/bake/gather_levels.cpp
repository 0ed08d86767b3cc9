// The point-gather pass over the levels of a bilevel / adaptive layout.

#include <atomic>
#include <chrono>
#include <utility>
#include <vector>

#include "project_incident.h"
#include "levels_bake.h"
#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
constexpr int kFloats = sh::kCoeffs * 3;

}  // namespace

Volume bakeShGatherLevels(const Scene& scene, const Tracer& tracer, const LevelLayout& layout,
                          const GatherOptions& options, Interrupter* interrupter, LevelsBakeStats* stats) {
    bake_detail::checkLevelsBake(options.raysPerNode, "rays per node", options.threads, layout);

    Volume volume = bake_detail::emptyLevelsVolume(layout, BasisDesc::sh2(), kFloats, options.only);
    if (options.depthMoments)
        for (VolumeLevel& l : volume.levels) l.depth.assign(l.heldNodes() * depth::kFloatsPerNode, 0.0f);
    if (layout.culledNodes > 0) {  // solid_cull.h: inactive nodes inside closed solids
        bake_detail::PassMetadata(volume.meta).text("culling", "solid-regions").count("nodes_culled", int64_t(layout.culledNodes));
    }
    volume.validate();

    uint64_t seams = 0;
    // The nodes it samples (not forEachLevelNode: the seam nodes' depth moments below need the list).
    const std::vector<std::pair<int, std::size_t>> work = bake_detail::nodesToBake(volume, seams, options.only);
    const RadianceEstimator estimator(scene, tracer, options.transport);
    const bake_detail::ParallelRun run =
        bake_detail::forEachItemInParallel(work.size(), options.threads, interrupter, [&](std::size_t w, RayCount& count) {
            const bake_detail::LevelNode node = bake_detail::levelNode(volume, work[w]);
            VolumeLevel& level = node.level;
            Rgbd coeffs[sh::kCoeffs];
            projectIncidentRadiance(estimator, node.position(), options.raysPerNode, options.seed, node.stream, coeffs,
                                    count, nullptr, nullptr,
                                    options.depthMoments ? level.depth.data() + level.held(node.n) * depth::kFloatsPerNode
                                                         : nullptr,
                                    level.grid.spacing);
            float* dst = node.values(kFloats);
            for (int j = 0; j < sh::kCoeffs; ++j) {
                dst[3 * j + 0] = float(coeffs[j].x);
                dst[3 * j + 1] = float(coeffs[j].y);
                dst[3 * j + 2] = float(coeffs[j].z);
            }
        });
    bake_detail::finishLevelsBake(volume, layout, seams, run, options.only, stats);
    RayCount seamDepthRays;
    if (options.depthMoments) {
        // Seam nodes take their radiance from the coarser level, but their depth belongs to
        // their own position: the same rays as if they had been gathered (bake_depth.h).
        // A tile's seam nodes only (the merge copies depth node by node).
        std::vector<std::vector<char>> baked(volume.levels.size());
        for (std::size_t l = 0; l < volume.levels.size(); ++l) baked[l].assign(volume.levels[l].storedNodes(), 0);
        for (const auto& w : work) baked[std::size_t(w.first)][w.second] = 1;
        std::vector<std::pair<int, std::size_t>> seamNodes;
        for (std::size_t l = 0; l < volume.levels.size(); ++l)
            for (std::size_t n = 0; n < baked[l].size(); ++n)
                if (!baked[l][n] && (!options.only || (*options.only)[l][n])) seamNodes.emplace_back(int(l), n);
        seamDepthRays = bake_detail::depthMomentsOfNodes(tracer, volume, seamNodes, options.seed, options.raysPerNode,
                                                         options.threads, nullptr).rays;
    }

    bake_detail::PassMetadata m(volume.meta);
    m.common(scene, options.transport, options.seed, layout.totalNodes(), run)
        .method("gather", "point")
        .count("rays_per_node", options.raysPerNode)
        .text("direction_sampling", "scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact");
    if (options.depthMoments) m.depthMoments(options.raysPerNode);
    m.number("nodes_dense_equivalent", layout.denseEquivalentNodes());
    if (stats) stats->rays += seamDepthRays;
    return volume;
}

}  // namespace vdblight
