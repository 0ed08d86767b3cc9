// Probe-pass directions guided by pass 0's radiance per direction cell (direction_guide.h).

#include "bake/direction_guide.h"

#include <algorithm>
#include <cmath>

#include "layout/grid_neighbours.h"

namespace vdblight::bake_detail {

namespace {
/// The index of the interval of `cdf` (n + 1 increasing values from 0) holding x, and x's
/// fraction within it, both clamped so that a rounding at the ends stays inside.
int invert(const float* cdf, int n, float x, float& fraction) {
    int i = int(std::upper_bound(cdf + 1, cdf + n, x) - (cdf + 1));
    i = std::clamp(i, 0, n - 1);
    const float width = cdf[i + 1] - cdf[i];
    fraction = width > 0 ? std::clamp((x - cdf[i]) / width, 0.0f, 1.0f) : 0.5f;
    return i;
}
/// (i + fraction) / n, kept below 1 (uniformSphere's square is [0, 1)).
float cellPoint(int i, float fraction, int n) {
    return std::min((float(i) + fraction) / float(n), 0x1.fffffep-1f);
}
}  // namespace

void poolGuideSums(const GridSpec& grid, int radius, int threads, std::vector<float>& sums,
                   std::vector<uint32_t>& counts) {
    constexpr std::size_t kCells = DirectionGuide::kCells;
    if (radius <= 0) return;
    // In place, one z-slab of nodes at a time (the map is 1 KB per node: a pooled copy of it
    // would double the bake's peak). Slab k reads the original slabs k - radius .. k + radius:
    // those above k are still in the arrays, slab k and those below it were copied to a ring of
    // radius + 1 slabs before being overwritten.
    const std::size_t slabNodes = std::size_t(grid.nx) * std::size_t(grid.ny), slab = slabNodes * kCells;
    const std::size_t ring = std::size_t(radius) + 1;
    std::vector<float> oldSums(ring * slab), outSums(slab);
    std::vector<uint32_t> oldCounts(ring * slab), outCounts(slab);
    for (int k = 0; k < grid.nz; ++k) {
        const std::size_t at = std::size_t(k) * slab, ringAt = std::size_t(k) % ring * slab;
        std::copy_n(sums.begin() + std::ptrdiff_t(at), slab, oldSums.begin() + std::ptrdiff_t(ringAt));
        std::copy_n(counts.begin() + std::ptrdiff_t(at), slab, oldCounts.begin() + std::ptrdiff_t(ringAt));
        const auto rowOf = [&](std::size_t n, const auto& old, const auto& now) {
            const std::size_t z = n / slabNodes;
            return z <= std::size_t(k) ? old.data() + z % ring * slab + (n - z * slabNodes) * kCells
                                       : now.data() + n * kCells;
        };
        poolGuideWindow(
            grid, radius, std::size_t(k) * slabNodes, slabNodes, threads,
            [&](std::size_t n) { return rowOf(n, oldSums, sums); },
            [&](std::size_t n) { return rowOf(n, oldCounts, counts); }, outSums.data(), outCounts.data());
        std::copy(outSums.begin(), outSums.end(), sums.begin() + std::ptrdiff_t(at));
        std::copy(outCounts.begin(), outCounts.end(), counts.begin() + std::ptrdiff_t(at));
    }
}

int DirectionGuide::cellOf(float u, float v) {
    const int r = std::clamp(int(u * float(kRows)), 0, kRows - 1);
    const int c = std::clamp(int(v * float(kCols)), 0, kCols - 1);
    return r * kCols + c;
}

int DirectionGuide::cellOfDirection(const Vec3f& dir) {
    const float u = 0.5f * (1.0f - std::clamp(dir.z, -1.0f, 1.0f));
    float v = float(std::atan2(double(dir.y), double(dir.x)) / (2.0 * kPi));
    if (v < 0) v += 1.0f;
    return cellOf(u, v);
}

void DirectionGuide::build(const float* luminanceSums, const uint32_t* counts, float uniformShare, float* density) {
    double total = 0;
    float mean[kCells];
    for (int c = 0; c < kCells; ++c) {
        mean[c] = counts[c] ? std::max(0.0f, luminanceSums[c]) / float(counts[c]) : 0.0f;
        total += mean[c];
    }
    // Cells pass 0 did not sample get the node's mean (neutral), so they are not left dark.
    int sampled = 0;
    for (int c = 0; c < kCells; ++c) sampled += counts[c] ? 1 : 0;
    const double fill = sampled ? total / sampled : 0.0;
    if (sampled < kCells) {
        for (int c = 0; c < kCells; ++c)
            if (!counts[c]) mean[c] = float(fill);
        total = fill * kCells;
    }
    const bool dark = !(total > 0) || !std::isfinite(total);
    for (int c = 0; c < kCells; ++c)
        density[c] = dark ? 1.0f : uniformShare + (1.0f - uniformShare) * float(mean[c] * kCells / total);
}

DirectionGuide::DirectionGuide(const float* density) : density_(density) {
    rowCdf_[0] = 0;
    for (int r = 0; r < kRows; ++r) {
        colCdf_[r][0] = 0;
        for (int c = 0; c < kCols; ++c) colCdf_[r][c + 1] = colCdf_[r][c] + density[r * kCols + c];
        rowCdf_[r + 1] = rowCdf_[r] + colCdf_[r][kCols];
    }
}

float DirectionGuide::warp(float& u, float& v) const {
    float fu, fv;
    const int r = invert(rowCdf_, kRows, u * rowCdf_[kRows], fu);
    const int c = invert(colCdf_[r], kCols, v * colCdf_[r][kCols], fv);
    u = cellPoint(r, fu, kRows);
    v = cellPoint(c, fv, kCols);
    // The density of the warped point: the cell's value over the mean of all cells (1 for
    // build's densities, up to rounding: normalised here so the weights stay exact).
    return density_[r * kCols + c] * float(kCells) / rowCdf_[kRows];
}

}  // namespace vdblight::bake_detail
