// Point sampling with the engines' leak heuristic: nodes whose rays see too many back-faces
// are invalid and get their valid neighbours' values by dilation.

#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "project_incident.h"
#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "bake/bake_antialiased.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

Volume bakeShGatherInvalidated(const Scene& scene, const Tracer& tracer, const GridSpec& grid,
                               const GatherOptions& options, double maxBackfaceFraction, Interrupter* interrupter,
                               BakeStats* stats) {
    if (!(maxBackfaceFraction >= 0.0 && maxBackfaceFraction <= 1.0))
        throw ValueError("the back-face fraction must be in [0, 1], got " + std::to_string(maxBackfaceFraction));
    if (options.raysPerNode == 0) throw ValueError("rays per node must be at least 1");
    const std::size_t nodes = bake_detail::checkThreadsAndGrid(options.threads, grid);
    constexpr int kValues = sh::kCoeffs * 3;

    Volume volume = bake_detail::emptyShVolume(grid);
    VolumeLevel& level = volume.levels[0];
    std::vector<uint32_t> backFaces(nodes, 0);

    const RadianceEstimator estimator(scene, tracer, options.transport);
    const bake_detail::ParallelRun run =
        bake_detail::forEachItemInParallel(nodes, options.threads, interrupter, [&](std::size_t n, RayCount& count) {
            Rgbd coeffs[sh::kCoeffs];
            projectIncidentRadiance(estimator, Vec3f(grid.node(n)), options.raysPerNode, options.seed, n, coeffs, count,
                                    &tracer, &backFaces[n]);
            float* dst = level.data.data() + n * kValues;
            for (int j = 0; j < sh::kCoeffs; ++j)
                for (int c = 0; c < 3; ++c) dst[3 * j + c] = float(coeffs[j][c]);
        });

    level.validity.assign(nodes, 0.0f);
    std::vector<uint8_t> valid(nodes, 0);
    std::vector<double> weight(nodes, 0.0);
    std::size_t invalid = 0;
    for (std::size_t n = 0; n < nodes; ++n) {
        const double fraction = double(backFaces[n]) / options.raysPerNode;
        valid[n] = fraction <= maxBackfaceFraction;
        weight[n] = valid[n] ? 1.0 : 0.0;
        level.validity[n] = valid[n] ? 1.0f : 0.0f;
        invalid += valid[n] ? 0 : 1;
    }
    if (invalid == nodes) {
        throw SceneError("every node sees back-faces in more than " + std::to_string(maxBackfaceFraction) +
                         " of its rays (do the normals look reversed? check the faces' winding)");
    }
    const int passes = invalid ? dilateUnfilledNodes(level, sh::kCoeffs, valid, weight) : 0;

    bake_detail::PassMetadata(volume.meta)
        .common(scene, options.transport, options.seed, nodes, run)
        .method("gather", "point")
        .number("invalidate_backface", maxBackfaceFraction)
        .count("rays_per_node", options.raysPerNode)
        .text("direction_sampling", "scrambled Sobol (0,2) uniform sphere + NEE on emissive triangles; punctual lights exact")
        .count("nodes_dilated", int64_t(invalid))
        .count("dilation_passes", passes);
    if (stats) {
        stats->nodes = nodes;
        stats->rays = run.rays;
        stats->seconds = run.seconds;
    }
    return volume;
}

}  // namespace vdblight
