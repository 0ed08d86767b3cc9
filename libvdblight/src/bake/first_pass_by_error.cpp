// Pass 0's rays per node from its own error estimate (first_pass_by_error.h).

#include "bake/first_pass_by_error.h"

#include <algorithm>
#include <cmath>

#include "layout/grid_neighbours.h"

namespace vdblight::bake_detail {

namespace {
/// A relative error the split can use: NodeSampler gives 1e30 where the node saw no light.
bool usable(float e) { return e >= 0 && e < 1e29f; }
}  // namespace

uint32_t pilotRays(uint32_t raysPerNode) { return std::max<uint32_t>(2, raysPerNode / kPilotShare); }

std::vector<uint32_t> raysPerNodeByError(const GridSpec& grid, const std::vector<float>& pilotError,
                                         const std::vector<uint8_t>& insideSolid, uint32_t pilotRays,
                                         uint32_t raysPerNode) {
    const std::size_t nodes = grid.nodeCount();
    std::vector<uint32_t> rays(nodes, pilotRays);
    if (pilotRays >= raysPerNode) return rays;
    std::vector<double> weight(nodes, 0.0);
    double total = 0;
    for (int k = 0; k < grid.nz; ++k)
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                const std::size_t n = grid.index(i, j, k);
                if ((!insideSolid.empty() && insideSolid[n]) || !usable(pilotError[n])) continue;
                weight[n] = std::pow(std::sqrt(meanSquareAround(grid, pilotError, i, j, k, 1, usable, 0.0)), kErrorPower);
                total += weight[n];
            }
    if (!(total > 0)) return rays;
    const double budget = double(raysPerNode - pilotRays) * double(nodes);
    const double most = double(kMostRaysFactor) * raysPerNode - pilotRays;
    for (std::size_t n = 0; n < nodes; ++n)
        rays[n] += uint32_t(std::lround(std::min(most, budget * weight[n] / total)));
    return rays;
}

}  // namespace vdblight::bake_detail
