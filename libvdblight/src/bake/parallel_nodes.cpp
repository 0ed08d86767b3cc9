#include "parallel_nodes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "vdblight/bake.h"

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

void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid) {
    BakeStats s;
    s.estimatedError = estimatedError;
    m["error_estimate"] = std::string(
        "relative standard error of each node's mean irradiance over normals (SH DC term), from the per-sample "
        "variance (noise only: not bias, SH truncation or interpolation)");
    m["estimated_error_p50"] = s.errorQuantile(0.5);
    m["estimated_error_p95"] = s.errorQuantile(0.95);
    m["estimated_error_max"] = s.errorQuantile(1.0);
    std::vector<std::size_t> order(estimatedError.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    const std::size_t worst = std::min<std::size_t>(5, order.size());
    // Ties broken by node index: the same text for any thread count.
    std::partial_sort(order.begin(), order.begin() + worst, order.end(), [&](std::size_t a, std::size_t b) {
        return estimatedError[a] != estimatedError[b] ? estimatedError[a] > estimatedError[b] : a < b;
    });
    std::ostringstream text;
    for (std::size_t k = 0; k < worst; ++k) {
        const std::size_t n = order[k];
        const std::size_t i = n % std::size_t(grid.nx), j = (n / std::size_t(grid.nx)) % std::size_t(grid.ny),
                          kk = n / (std::size_t(grid.nx) * std::size_t(grid.ny));
        text << (k ? ";" : "") << i << ',' << j << ',' << kk << ':' << estimatedError[n];
    }
    m["estimated_error_worst_nodes"] = text.str();
}

}  // namespace bake_detail

double BakeStats::errorQuantile(double q) const {
    if (estimatedError.empty()) return 0.0;
    std::vector<float> sorted = estimatedError;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t i = std::min(sorted.size() - 1, std::size_t(std::ceil(q * sorted.size())) - (q > 0 ? 1 : 0));
    return sorted[i];
}
}  // namespace vdblight
