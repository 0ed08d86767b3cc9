// Filling nodes that got no valid samples from their neighbours (documented in
// bake_antialiased.h and docs/methods.md).
#include <vector>

#include "bake/bake_antialiased.h"
#include "vdblight/core/errors.h"
#include "layout/grid_neighbours.h"

namespace vdblight {

int dilateUnfilledNodes(VolumeLevel& level, int channels, std::vector<uint8_t>& filled, std::vector<double>& weight) {
    const GridSpec& g = level.grid;
    const std::size_t nodes = g.nodeCount();
    if (filled.size() != nodes || weight.size() != nodes || level.data.size() != nodes * std::size_t(channels) * 3)
        throw ValueError("dilateUnfilledNodes: arrays do not match the grid");
    std::size_t missing = 0;
    for (uint8_t f : filled) missing += f ? 0 : 1;
    if (missing == nodes) throw SceneError("no node has a valid sample to dilate from");

    const std::size_t values = std::size_t(channels) * 3;
    std::vector<double> sum(values);
    int passes = 0;
    while (missing > 0) {
        ++passes;
        // Jacobi pass: read only nodes filled before this pass, write the newly filled ones after it.
        std::vector<std::size_t> newNodes;
        std::vector<float> newData;
        std::vector<double> newWeight;
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) {
                    const std::size_t n = g.index(i, j, k);
                    if (filled[n]) continue;
                    std::fill(sum.begin(), sum.end(), 0.0);
                    double total = 0, donorWeight = 0;
                    int donors = 0;
                    forEachNodeAround(g, i, j, k, 1, [&](int a, int b, int c, int di, int dj, int dk) {
                        const std::size_t m = g.index(a, b, c);
                        if (!filled[m]) return;
                        const double w = weight[m] / double(di * di + dj * dj + dk * dk);
                        const float* src = level.data.data() + m * values;
                        for (std::size_t v = 0; v < values; ++v) sum[v] += w * src[v];
                        total += w;
                        donorWeight += weight[m];
                        ++donors;
                    });
                    if (donors == 0 || !(total > 0)) continue;
                    newNodes.push_back(n);
                    for (std::size_t v = 0; v < values; ++v) newData.push_back(float(sum[v] / total));
                    newWeight.push_back(donorWeight / donors);
                }
        if (newNodes.empty()) throw SceneError("dilation cannot reach every node");  // unreachable for a grid
        for (std::size_t e = 0; e < newNodes.size(); ++e) {
            const std::size_t n = newNodes[e];
            std::copy(newData.begin() + std::ptrdiff_t(e * values), newData.begin() + std::ptrdiff_t((e + 1) * values),
                      level.data.begin() + std::ptrdiff_t(n * values));
            filled[n] = 1;
            weight[n] = newWeight[e];
        }
        missing -= newNodes.size();
    }
    return passes;
}

}  // namespace vdblight
