#include "parallel_nodes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "vdblight/bake.h"
#include "vdblight/error_summary.h"

#include "vdblight/layout_levels.h"
#include "vdblight/scene.h"

namespace vdblight {
namespace bake_detail {

std::vector<std::pair<int, std::size_t>> nodesToBake(const Volume& volume, uint64_t& seams, const NodeMask* only) {
    if (only && only->size() != volume.levels.size()) throw ValueError("the node mask does not match the levels");
    std::vector<std::pair<int, std::size_t>> work;
    const int K = volume.refineFactor();
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const std::size_t stored = volume.levels[l].storedNodes();
        std::vector<char> skip(stored, 0);
        if (l > 0)
            for (std::size_t n : seamNodes(volume.levels, int(l), K)) skip[n] = 1, ++seams;
        for (std::size_t n = 0; n < stored; ++n)
            if (!skip[n] && (!only || (*only)[l].at(n))) work.emplace_back(int(l), n);
    }
    return work;
}

void addCommonBakeMetadata(Metadata& m, const Scene& scene, const TransportOptions& transport, uint64_t seed,
                           uint64_t nodes, const ParallelRun& run) {
    m["scene_name"] = scene.name;
    m["scene_hash"] = scene.contentHash();
    m["scene_triangles"] = int64_t(scene.triangleCount());
    m["seed"] = int64_t(seed);
    m["bounces"] = int64_t(transport.maxBounces);
    m["roulette_start"] = int64_t(transport.rouletteStart);
    m["roulette_max_survival"] = double(kRouletteMaxSurvival);
    m["nodes"] = int64_t(nodes);
    m["rays_intersect"] = int64_t(run.rays.intersect);
    m["rays_occluded"] = int64_t(run.rays.occluded);
    m["bake_seconds"] = run.seconds;
    m["threads"] = int64_t(run.threads);
}

}  // namespace bake_detail

double BakeStats::errorQuantile(double q) const { return vdblight::errorQuantile(estimatedError, q); }
}  // namespace vdblight
