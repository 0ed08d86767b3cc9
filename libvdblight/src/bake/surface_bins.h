// A cache of the irradiance of reflected light and sky at the surfaces themselves, built from
// pass 0's own paths (DeferredPaths::firstVertexIrradiance): `bake --probe-cache surface`,
// issue 15. The node cache (surface_cache.h) lets the nodes around a surface point stand for
// it, which biases the probe pass high where nearby geometry closes the point's hemisphere
// (docs/measurements/default_bake.md, "The probe pass's bias, isolated", point 4); these bins hold samples taken
// at the surfaces. (Internal to the bake module.)
//
// Bins: the cells of the node grid, six per cell, one per signed axis of the surface normal
// (its largest component). A read at p with normal n blends the bins of n's axis in the row of
// cells along n that holds p, bilinearly over the two other axes (cell centres), each bin
// weighted by its sample count too, so that a bin few paths reached counts little; a read
// where no path came returns false (the path then goes on: unbiased).
//
// Deterministic for any thread count and order: the sums are integers (fixed point: irradiance
// in units of radianceScale x 2^-30, each sample clamped to 2^10 radianceScale; positions in
// 2^-20 of a cell), which add exactly.
//
// Sparse: a cell's bins are allocated when its first sample comes. The samples lie on surfaces,
// so a bake fills a thin shell of its cells, and a stage-0 tile only the cells its own nodes'
// paths reach: 8 B per cell of the grid plus kBytesPerCell per cell that holds samples.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/volume.h"

namespace vdblight::bake_detail {

/// std::llround(x) for 0 <= x < 2^53, inline (llround is a library call, and SurfaceBins::add
/// made six per sample): x minus its integer part is exact, so the half is decided exactly.
inline uint64_t roundNonNegative(double x) {
    const uint64_t whole = uint64_t(x);
    return whole + (x - double(whole) >= 0.5 ? 1 : 0);
}

class SurfaceBins final : public SurfaceSampleSink, public SurfaceIrradianceCache {
public:
    /// Bins over the cells of `grid`; `tracer`: the scene's, for the reads' visibility tests;
    /// `radianceScale` (> 0): the scene's brightest radiance (radianceScale(), below), which
    /// sets the fixed point's unit.
    SurfaceBins(const Tracer& tracer, const GridSpec& grid, double radianceScale);
    /// Bins holding `sums` (a stage input's: every tile's stage-0 samples, merged); ValueError
    /// if they do not fit the grid.
    SurfaceBins(const Tracer& tracer, const GridSpec& grid, const SurfaceBinSums& sums);
    ~SurfaceBins() override;
    SurfaceBins(const SurfaceBins&) = delete;
    SurfaceBins& operator=(const SurfaceBins&) = delete;
    /// The bins' integer sums, the cells that hold samples (a stage-0 tile's, for the merge).
    SurfaceBinSums sums() const;
    void add(const Vec3f& p, const Vec3f& n, const Rgb& irradiance) override;
    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override;
    /// Samples in all bins, and their mean (tests).
    uint64_t samples() const;
    Rgb meanIrradiance() const;
    /// Bytes held per cell that holds samples, and per cell of the grid.
    static constexpr std::size_t kBytesPerCell = SurfaceBinSums::kValuesPerCell * sizeof(uint64_t);
    static constexpr std::size_t kBytesPerGridCell = sizeof(void*);
    /// Cells that hold samples.
    std::size_t cellsHeld() const;

private:
    struct Bin {
        std::atomic<uint64_t> sum[3]{};
        std::atomic<uint64_t> count{};
        std::atomic<uint64_t> pos[3]{};  ///< sample positions, fixed point in the grid's cells
    };
    using Cell = std::array<Bin, SurfaceBinSums::kBinsPerCell>;
    std::size_t cellIndex(int i, int j, int k) const;  ///< cell coordinates clamped
    Cell& cellForAdd(std::size_t index);               ///< allocated on first use

    GridSpec grid_;
    const Tracer& tracer_;
    std::array<int, 3> cells_;
    double unit_;  ///< irradiance per integer step
    std::size_t cellCount_ = 0;
    /// One pointer per cell, null until a sample comes (owned: freed by the destructor).
    std::unique_ptr<std::atomic<Cell*>[]> cellPtrs_;
};

/// The brightest radiance a scene's lights give, as the unit of SurfaceBins: emissive
/// materials, the sky, punctual intensities at `spacing`, directional irradiance / pi; 1 for
/// a scene without light.
double radianceScale(const Scene& scene, double spacing);

}  // namespace vdblight::bake_detail
