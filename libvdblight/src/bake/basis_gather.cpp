// The generic point-gather pass (bake_basis.h): the bins gather's sampling, any basis's
// accumulation.
#include <algorithm>
#include <cmath>
#include <vector>

#include "levels_bake.h"
#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "stratified_sphere.h"
#include "bake/bake_basis.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

int basisGatherResolution(uint32_t raysPerNode) {
    return std::max(1, int(std::lround(std::sqrt(double(raysPerNode) / 2.0))));
}

Volume bakeBasis(const Scene& scene, const Tracer& tracer, const LevelLayout& layout, const Basis& basis,
                 const BasisBakeOptions& options, Interrupter* interrupter, LevelsBakeStats* stats) {
    bake_detail::checkLevelsBake(options.raysPerNode, "rays per node", options.threads, layout);
    const int R = basisGatherResolution(options.raysPerNode);
    const std::size_t floats = basis.floatsPerNode(), accumulators = basis.accumulatorSize();
    const double scale = 4.0 * kPi / (2.0 * R * R);  // 1 / (pdf * samples), one sample per cell

    Volume volume = bake_detail::emptyLevelsVolume(layout, basis.desc(), floats, options.only);
    volume.validate();

    uint64_t seams = 0;
    const RadianceEstimator estimator(scene, tracer, options.transport);
    const bake_detail::ParallelRun run = bake_detail::forEachLevelNode(
        volume, options.only, options.threads, interrupter, seams, [&](const bake_detail::LevelNode& node, RayCount& count) {
            thread_local std::vector<Rgbd> acc;  // per-thread scratch, reused across nodes
            acc.assign(accumulators, Rgbd(0, 0, 0));
            bake_detail::sampleStratifiedSphere(
                estimator, node.position(), R, 1, options.seed, node.stream, count,
                [&](int, const Vec3f& d, const Rgb& l) { basis.accumulate(d, Rgbd(l), scale, acc.data()); },
                [](int, double) {},
                [&](const Vec3f& d, const Rgbd& value, double samples) { basis.accumulate(d, value, 1.0 / samples, acc.data()); });
            basis.finish(acc.data(), node.values(floats));
        });
    bake_detail::finishLevelsBake(volume, layout, seams, run, options.only, stats);

    const uint32_t rays = uint32_t(2 * R * R);
    bake_detail::PassMetadata(volume.meta)
        .common(scene, options.transport, options.seed, layout.totalNodes(), run)
        .method("gather", "point")
        .count("rays_per_node", rays)
        .count("strata_resolution", R)
        .text("direction_sampling", "scrambled Sobol (0,2) point in each of 2 R^2 equal-area cells (bins.h) + NEE on "
                                    "emissive triangles; punctual lights exact")
        .text("projection", "generic gather: Basis::accumulate per sample, Basis::finish per node (bake_basis.h)");
    return volume;
}

}  // namespace vdblight
