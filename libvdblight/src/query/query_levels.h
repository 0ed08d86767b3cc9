// Lookups in multi-level (bilevel / adaptive) SH order-2 volumes (Greger et al. section
// 3.3, n levels): find the level-0 cell of x; while the cell is refined, descend into its
// K^3 children; interpolate trilinearly in the finest cell reached, then convolve with the
// cosine lobe for the normal. Seam nodes (layout/layout.h) make the result continuous.
//
// Depth moments (basis/depth_moments.h) weight the corners only where the cell reached is one of the
// finest level: refinement is complete (every cell with geometry is refined), so a leaf cell
// of a coarser level holds no geometry and every corner sees every point in it; its depth
// moments, measured over a pyramid reaching into the neighbouring cells, could only darken
// corners wrongly. The exported depth textures (export: the finest lattice) agree.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/query/query.h"

namespace vdblight {

/// The fast lookup: level 0 as a dense array, finer levels as "bricks" of (K + 1)^3 nodes
/// (one per refined cell) with a child table per cell, coefficients pre-multiplied by A_l.
class ShLevelsLookup final : public VolumeLookup {
public:
    /// Throws FormatError if a refined cell's child node is missing in a volume that is not
    /// culled (never reads an unbaked node).
    ShLevelsLookup(const Volume& volume, OutsidePolicy outside);
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override;
    Bounds bounds() const override { return grid_.nodeBounds(); }
    /// Located in double (snapped onto nodes within 1e-9 cells) and interpolated in double in
    /// the finest cell that contains x, so a node position returns that node (export).
    void shRadiance(const Vec3d& x, Rgb out[9]) const override;
    /// shRadiance as the sh2 basis's channels (basis/basis.h; export --layout basis).
    void channelValues(const Vec3d& x, float* out) const override;
    /// Level whose cell the lookup at x interpolates in.
    int levelAt(const Vec3f& x) const;
    /// Culled volumes (bake/each_pass.h): true if the cell the lookup at x ends in has a culled
    /// (inactive) corner; such a cell lies inside closed geometry, and irradiance() and
    /// shRadiance() return 0 there instead of reading the missing nodes.
    bool inCulledCell(const Vec3f& x) const override;
    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }

    static bool accepts(const Volume& volume);

private:
    static constexpr int32_t kCulled = -2;  ///< child value of a leaf cell with an inactive corner
    struct Level {
        std::vector<int32_t> child;  ///< per cell (level 0) or per brick cell: brick index in the next level, -1 (leaf) or kCulled
        std::vector<float> nodes;    ///< level 0: dense node-major; finer: per brick (K+1)^3 nodes
        std::vector<float> depth;    ///< the same nodes' depth moments (depth::kFloatsPerNode each); the finest level only, else empty
    };
    template <typename Visit>
    void descend(const Vec3f& x, Visit visit) const;

    GridSpec grid_;  ///< level 0
    OutsidePolicy outside_;
    int K_ = 1;
    Vec3f origin_;
    float invSpacing_ = 1;
    std::vector<Level> levels_;
    bool hasDepth_ = false, depthWeights_ = false;
};

/// The simple lookup ShLevelsLookup is tested against: descends through the volume's own
/// refined-cell lists, finds every node by binary search, interpolates in double and
/// convolves with the generic SH code. Throws FormatError if it would read a node that is
/// not active. `level`, if given, receives the level used.
Rgbd referenceLevelsLookup(const Volume& volume, const Vec3d& x, const Vec3d& n, int* level = nullptr);

}  // namespace vdblight
