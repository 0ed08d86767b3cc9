// The probe pass's values blended with pass 0's by pooled inverse variance (first_pass_blend.h).

#include "volume/first_pass_blend.h"

#include <cmath>

#include "layout/grid_neighbours.h"

namespace vdblight {

namespace {
/// Mean of error^2 over the valid nodes of the 3 x 3 x 3 neighbourhood (infinity: none).
double pooledVariance(const GridSpec& grid, const std::vector<float>& error, int i, int j, int k) {
    return meanSquareAround(grid, error, i, j, k, 1, [](float e) { return e >= 0 && std::isfinite(e); }, INFINITY);
}
}  // namespace

void blendWithFirstPass(const GridSpec& grid, std::size_t floatsPerNode, const std::vector<float>& firstValues,
                        const std::vector<float>& firstError, std::vector<float>& values, std::vector<float>& error) {
    std::vector<float> blended(error);
    for (int k = 0; k < grid.nz; ++k)
        for (int j = 0; j < grid.ny; ++j)
            for (int i = 0; i < grid.nx; ++i) {
                const std::size_t n = grid.index(i, j, k);
                if (!(error[n] >= 0) || !(firstError[n] >= 0)) continue;
                const double v0 = pooledVariance(grid, firstError, i, j, k), v1 = pooledVariance(grid, error, i, j, k);
                if (!std::isfinite(v0) || !std::isfinite(v1) || !(v0 + v1 > 0)) continue;
                const double w = kFirstPassVarianceFactor * v0 / (kFirstPassVarianceFactor * v0 + v1);
                for (std::size_t f = 0; f < floatsPerNode; ++f) {
                    float& x = values[n * floatsPerNode + f];
                    x = float(w * x + (1.0 - w) * firstValues[n * floatsPerNode + f]);
                }
                const double e0 = firstError[n], e1 = error[n];
                blended[n] = float(std::sqrt(w * w * e1 * e1 + (1.0 - w) * (1.0 - w) * e0 * e0));
            }
    error.swap(blended);
}

}  // namespace vdblight
