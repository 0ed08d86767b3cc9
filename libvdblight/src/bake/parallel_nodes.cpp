#include "parallel_nodes.h"

#include "vdblight/scene.h"

namespace vdblight {
namespace bake_detail {

void addCommonBakeMetadata(Metadata& m, const Scene& scene, const TransportOptions& transport, uint64_t seed,
                           uint64_t nodes, const ParallelRun& run) {
    m["scene_name"] = scene.name;
    m["scene_hash"] = scene.contentHash();
    m["scene_triangles"] = int64_t(scene.triangleCount());
    m["seed"] = int64_t(seed);
    m["bounces"] = int64_t(transport.maxBounces);
    m["roulette_start"] = int64_t(transport.rouletteStart);
    m["nodes"] = int64_t(nodes);
    m["rays_intersect"] = int64_t(run.rays.intersect);
    m["rays_occluded"] = int64_t(run.rays.occluded);
    m["bake_seconds"] = run.seconds;
    m["threads"] = int64_t(run.threads);
}

}  // namespace bake_detail
}  // namespace vdblight
