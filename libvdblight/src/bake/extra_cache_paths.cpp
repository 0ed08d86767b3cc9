// More paths for the surface probe cache where pass 0 is noisiest (extra_cache_paths.h).

#include "bake/extra_cache_paths.h"

#include <algorithm>
#include <cmath>

#include "layout/grid_neighbours.h"
#include "node_sampler.h"

namespace vdblight::bake_detail {

namespace {
bool usable(float e) { return e >= 0 && std::isfinite(e); }
}  // namespace

std::vector<uint32_t> extraCachePaths(const GridSpec& grid, const std::vector<float>& firstError,
                                      const std::vector<uint8_t>& insideSolid, uint32_t perNode) {
    const std::size_t nodes = grid.nodeCount();
    std::vector<double> pooled(nodes, -1.0), sorted;
    for (int k = 0; k < grid.nz; ++k)
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                const std::size_t n = grid.index(i, j, k);
                if ((!insideSolid.empty() && insideSolid[n]) || !usable(firstError[n])) continue;
                pooled[n] = std::sqrt(meanSquareAround(grid, firstError, i, j, k, 1, usable, 0.0));
                sorted.push_back(pooled[n]);
            }
    std::vector<uint32_t> paths(nodes, 0);
    if (sorted.empty()) return paths;
    const auto middle = sorted.begin() + std::ptrdiff_t(sorted.size() / 2);
    std::nth_element(sorted.begin(), middle, sorted.end());
    const double threshold = kNoisyFactor * *middle;
    for (std::size_t n = 0; n < nodes; ++n)
        if (pooled[n] > threshold) paths[n] = perNode;
    return paths;
}

ParallelRun traceExtraCachePaths(const RadianceEstimator& estimator, const GridSpec& grid, uint64_t seed,
                                 const std::vector<uint32_t>& paths, SurfaceBins& bins, int threads,
                                 Interrupter* interrupter) {
    const uint64_t stream = hashCombine(seed, kExtraCachePathsStream);
    return forEachItemInParallel(grid.nodeCount(), threads, interrupter, [&](std::size_t n, RayCount& count) {
        if (paths[n] == 0) return;
        detail::NodeSampler sampler(estimator, Vec3f(grid.node(n)), stream, n, paths[n]);
        sampler.recordSurfaceOnly(&bins);  // the node's values are pass 0's: its own light samples are not traced
        sampler.addSamples(0, paths[n], count);
    });
}

}  // namespace vdblight::bake_detail
