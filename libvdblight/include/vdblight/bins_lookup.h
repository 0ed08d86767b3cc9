// Lookups in Greger-bin and moment volumes (bins.h; Greger et al. section 3.3).
//
// For a point x and a unit direction d: find the cell of x (descending through refined
// cells of a bilevel / adaptive volume exactly as ShLevelsLookup does), find the bin of d by
// inverting the equal-area map (hemisphere by the sign of d.z, then the concentric map back
// to the unit square), and interpolate that bin's values trilinearly over the cell's eight
// nodes. With `interpolateBins`, the four bins whose centres surround d in the square are
// blended bilinearly instead (across the square's border into the other hemisphere, whose
// border bins share the equator), which makes the result continuous in d.
//
// What comes back is the stored function at d: the irradiance of a surface facing d for
// "bins:R", the n-th moment H^n(d) for "moment:n" (query it with the reflected view vector,
// bins::reflectView).
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/bins.h"
#include "vdblight/query.h"

namespace vdblight {

class BinsLookup final : public VolumeLookup {
public:
    /// Default of `interpolateBins` (measured in bench_bins: see docs/methods.md).
    static constexpr bool kInterpolateBinsDefault = true;

    /// Throws FormatError if the basis is not bins / moment or a refined cell misses a node.
    BinsLookup(const Volume& volume, OutsidePolicy outside, bool interpolateBins = kInterpolateBinsDefault);
    Rgb irradiance(const Vec3f& x, const Vec3f& d) const override;
    Bounds bounds() const override { return grid_.nodeBounds(); }
    const bins::BasisSpec& spec() const { return spec_; }
    /// All 2 R^2 bins' RGB values (6 R^2 floats) interpolated in space at x, no direction.
    void binValues(const Vec3d& x, float* out) const override;

    static bool accepts(const Volume& volume);
    /// Depth moments (depth_moments.h), as for the SH lookups: on when the volume has them.
    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }

private:
    struct Level {
        std::vector<int32_t> child;   ///< per cell (level 0) or per brick cell: brick of the next level, -1
        std::vector<uint32_t> nodes;  ///< finer levels: per brick, (K+1)^3 node positions in `data`
        std::vector<float> data;      ///< node-major, channels * 3 floats per node
        std::vector<float> depth;     ///< the same nodes' depth moments, or empty
    };
    /// Up to four (channel, weight) pairs for direction d.
    int binWeights(const Vec3f& d, int channels[4], float weights[4]) const;
    /// The level and eight corner nodes (positions in its data) around the level-0 lattice
    /// coordinate g (clamped into the node box), with their trilinear weights; T = float for
    /// irradiance, double for binValues (exact at the nodes).
    template <class T>
    const Level& locate(const T g[3], std::size_t corner[8], float weight[8]) const;

    bins::BasisSpec spec_;
    bool interpolateBins_;
    GridSpec grid_;
    OutsidePolicy outside_;
    int K_ = 1;
    Vec3f origin_;
    float invSpacing_ = 1;
    std::size_t floatsPerNode_ = 0;
    std::vector<Level> levels_;
    bool hasDepth_ = false, depthWeights_ = false;
};

/// The simple lookup BinsLookup is tested against: the bin of d by bins::binOf (no blending
/// of bins), descent through the volume's refined-cell lists and nodes by binary search,
/// interpolation in double. Throws FormatError if it would read a node that is not active.
Rgbd referenceBinsLookup(const Volume& volume, const Vec3d& x, const Vec3f& d);

}  // namespace vdblight
