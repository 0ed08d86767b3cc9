// Filtering across nodes with depth-aware weights (node_filter.h, issue 32).
#include "volume/node_filter.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "core/parallel_for.h"
#include "layout/grid_neighbours.h"

namespace vdblight {

namespace {
/// Binomial weights of offsets -1, 0, +1 along one axis.
constexpr double kTap[3] = {0.25, 0.5, 0.25};
/// Range weights: differences of this many standard errors of the two nodes' difference
/// weigh exp(-1/2).
constexpr double kRangeScale = 1.0;

/// Luminance of a node's first channel (the basis's constant term: the mean radiance).
double meanLuminance(const float* v) { return 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]; }

void filterOnce(const VolumeLevel& level, int channels, const std::vector<float>& in, std::vector<float>& out,
                const std::vector<float>* relativeError, int threads) {
    const GridSpec& g = level.grid;
    const std::size_t floats = std::size_t(channels) * 3;
    const bool depth = level.hasDepth();
    // Each node's output is its own sum over its neighbours' inputs: rows of nodes in parallel,
    // the same bits on any thread count (it ran alone after the probe pass: 1 % of the
    // preview's wall time, issue 32).
    core::parallelFor(std::size_t(g.ny) * std::size_t(g.nz), threads, [&](std::size_t row) {
        const int j = int(row % std::size_t(g.ny)), k = int(row / std::size_t(g.ny));
        std::vector<double> sum(floats);
        for (int i = 0; i < g.nx; ++i) {
            const std::size_t n = g.index(i, j, k);
            std::fill(sum.begin(), sum.end(), 0.0);
            double total = 0;
            forEachNodeAround(g, i, j, k, 1, [&](int a, int b, int c, int di, int dj, int dk) {
                const std::size_t m = g.index(a, b, c);
                double w = kTap[di + 1] * kTap[dj + 1] * kTap[dk + 1];
                if (depth && m != n) {
                    // Each must see the other: the lookup's test in both directions.
                    w *= depth::visibility(level.depth.data() + n * depth::kFloatsPerNode, float(di), float(dj), float(dk));
                    w *= depth::visibility(level.depth.data() + m * depth::kFloatsPerNode, float(-di), float(-dj), float(-dk));
                }
                if (relativeError && m != n) {
                    // A neighbour counts as far as the two nodes' difference is what
                    // their noise explains: a larger difference is light, not noise.
                    const float en = (*relativeError)[n], em = (*relativeError)[m];
                    if (em < 0) return;  // inside a solid (error_summary.h)
                    const double ln = meanLuminance(in.data() + n * floats), lm = meanLuminance(in.data() + m * floats);
                    const double sn = std::max(0.0f, en) * std::fabs(ln), sm = em * std::fabs(lm);
                    const double var = kRangeScale * kRangeScale * (sn * sn + sm * sm), d = ln - lm;
                    w *= var > 0 ? std::exp(-0.5 * d * d / var) : (d == 0 ? 1.0 : 0.0);
                }
                if (w <= 0) return;
                total += w;
                const float* v = in.data() + m * floats;
                for (std::size_t f = 0; f < floats; ++f) sum[f] += w * double(v[f]);
            });
            float* o = out.data() + n * floats;
            for (std::size_t f = 0; f < floats; ++f) o[f] = float(sum[f] / total);  // total >= the centre's 1/8
        }
    });
}
}  // namespace

void filterNodes(Volume& volume, int passes, const std::vector<float>* relativeError, int threads) {
    if (passes < 0) throw ValueError("node filter passes must be at least 0, got " + std::to_string(passes));
    if (passes == 0) return;
    const int channels = volume.basis.channelCount();
    for (VolumeLevel& level : volume.levels) {
        if (relativeError && (volume.levels.size() != 1 || relativeError->size() != level.heldNodes()))
            throw ValueError("the node filter's error estimates do not match the volume");
        if (level.sparse()) throw ValueError("the node filter needs a uniform volume (every node of the grid stored)");
        if (level.windowNodes && level.windowNodes != level.grid.nodeCount())
            throw ValueError("the node filter cannot run on a tile (its kernel crosses tile borders)");
        std::vector<float> out(level.data.size());
        for (int p = 0; p < passes; ++p) {
            filterOnce(level, channels, level.data, out, relativeError, threads);
            level.data.swap(out);
        }
    }
}

}  // namespace vdblight
