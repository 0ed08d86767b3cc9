// Probe-pass directions guided toward the light a node saw in pass 0 (issue 32, the preview's
// noise through a door). (Internal to the bake module.)
//
// A node in a dark room lit through a door gathers most of its light from the few directions
// that see the door. Uniform directions find them by luck: at the preview's 128 rays that was
// the larger part of the unlit room's noise (docs/time_to_accuracy.md). Pass 0 has already
// traced rays in every direction from the node; its radiance per direction cell is a rough
// map of where the light comes from, and the probe pass draws its directions from it.
//
// The map is a density over the square of uniformSphere (z = 1 - 2u, phi = 2 pi v): that map
// is equal-area, so a density constant on a cell of the square is constant on its patch of the
// sphere. kRows x kCols cells (the first 128 points of a (0,2)-sequence put one sample in each).
// A share of the density stays uniform (a defensive mixture), so no direction's weight exceeds
// 1 / uniformShare and cells that pass 0 saw dark by chance are still sampled: the estimate
// stays unbiased whatever pass 0 saw, only its variance depends on the map. The Sobol' points
// are warped through the density's marginal and conditional inverses, which keeps their
// stratification within the guide's cells.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/parallel_for.h"
#include "layout/grid_neighbours.h"

#include "vdblight/core/math.h"
#include "vdblight/layout/layout.h"

namespace vdblight::bake_detail {

/// Each node's sums and counts (kCells per node of `grid`, node order) replaced by those of
/// the nodes within `radius` steps on every axis (itself included): pass 0's map at one node
/// is one sample per cell, too noisy to guide by; its neighbours see the same openings from
/// nearly the same place. Each node's sums in a fixed order: the same bits for any thread count
/// (`threads` as core::threadCount reads it).
void poolGuideSums(const GridSpec& grid, int radius, int threads, std::vector<float>& sums,
                   std::vector<uint32_t>& counts);

/// The same pooling for the nodes [first, first + count) of `grid` only (a tile's window),
/// reading every node's kCells sums and counts from the pointers sumsOf(node) and
/// countsOf(node) (counts of any arithmetic type, converted to uint32_t):
/// out[(n - first) * kCells + cell], the same additions in the same order as poolGuideSums, so
/// a staged tile's guide equals the single bake's (stage_carry.h).
template <typename SumsOf, typename CountsOf>
void poolGuideWindow(const GridSpec& grid, int radius, std::size_t first, std::size_t count, int threads,
                     SumsOf&& sumsOf, CountsOf&& countsOf, float* outSums, uint32_t* outCounts);

class DirectionGuide {
public:
    static constexpr int kRows = 8;   ///< along u (z)
    static constexpr int kCols = 16;  ///< along v (phi)
    static constexpr int kCells = kRows * kCols;
    /// The probe pass's choices, measured against the accuracy benchmark's ground truth
    /// (docs/time_to_accuracy.md, "Guided probe directions"; two rooms, preview): maps pooled
    /// over 5 x 5 x 5 nodes (radius 1: 7.7 %, 2: 7.4 %, 3: 8.1 %; one node alone: 9.0 %, worse than
    /// uniform's 9.3 % in noise), half of the density uniform (0.3 and 0.5: 7.4 %, 0.2: 7.8 %).
    static constexpr int kPoolRadius = 2;
    static constexpr float kUniformShare = 0.5f;

    /// The cell of a point of the square (u, v in [0, 1)).
    static int cellOf(float u, float v);
    /// The cell of a unit direction (the inverse of uniformSphere, then cellOf).
    static int cellOfDirection(const Vec3f& dir);

    /// A node's density (kCells values, mean 1) from one pass's luminance sums and sample
    /// counts per cell: each cell's mean luminance, normalised to mean 1, mixed with the
    /// uniform density (share `uniformShare` in (0, 1]). A dark node (no light in any cell)
    /// gets the uniform density.
    static void build(const float* luminanceSums, const uint32_t* counts, float uniformShare, float* density);

    /// Samples from `density` (kCells values of build(), read in place: it must outlive this).
    explicit DirectionGuide(const float* density);

    /// Warps a point (u, v) of the square (in place) to the density; returns the density there
    /// (relative to the uniform sphere: the sample's weight is its inverse).
    float warp(float& u, float& v) const;
    /// The density at a direction (relative to the uniform sphere).
    float density(const Vec3f& dir) const { return density_[cellOfDirection(dir)]; }

private:
    const float* density_;
    float rowCdf_[kRows + 1];           ///< cumulative row sums
    float colCdf_[kRows][kCols + 1];    ///< cumulative sums within each row
};

template <typename SumsOf, typename CountsOf>
void poolGuideWindow(const GridSpec& grid, int radius, std::size_t first, std::size_t count, int threads,
                     SumsOf&& sumsOf, CountsOf&& countsOf, float* outSums, uint32_t* outCounts) {
    constexpr int kCells = DirectionGuide::kCells;
    const std::size_t nx = std::size_t(grid.nx), ny = std::size_t(grid.ny);
    // A node's sums are its own: nodes in parallel, each cell's additions in forEachNodeAround's
    // order whatever the threads. A whole neighbour's row at a time, so the cells vectorise
    // (it ran alone between the passes: 8 % of the preview's wall time, issue 32).
    core::parallelFor(count, threads, [&](std::size_t i) {
        const std::size_t n = first + i;
        float* sums = outSums + i * kCells;
        uint32_t* counts = outCounts + i * kCells;
        std::fill(sums, sums + kCells, 0.0f);
        std::fill(counts, counts + kCells, 0u);
        forEachNodeAround(grid, int(n % nx), int(n / nx % ny), int(n / (nx * ny)), std::max(radius, 0),
                          [&](int a, int b, int c, int, int, int) {
                              const std::size_t from = grid.index(a, b, c);
                              const float* fromSums = sumsOf(from);
                              const auto* fromCounts = countsOf(from);
                              for (int cell = 0; cell < kCells; ++cell) {
                                  sums[cell] += fromSums[cell];
                                  counts[cell] += uint32_t(fromCounts[cell]);
                              }
                          });
    });
}

}  // namespace vdblight::bake_detail
