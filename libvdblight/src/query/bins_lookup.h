// Lookups in Greger-bin and moment volumes (basis/bins.h; Greger et al. section 3.3): the generic
// ChannelLookup (channel_lookup.h) with the bins basis, which picks the bin of d by inverting
// the equal-area map, or with `interpolateBins` blends the four bins around d
// (bins::lookupWeights).
//
// What comes back is the stored function at d: the irradiance of a surface facing d for
// "bins:R", the n-th moment H^n(d) for "moment:n" (query it with the reflected view vector,
// bins::reflectView).
#pragma once

#include "vdblight/basis/bins.h"
#include "query/channel_lookup.h"

namespace vdblight {

class BinsLookup final : public ChannelLookup {
public:
    /// Default of `interpolateBins` (measured in bench_bins: see docs/methods.md).
    static constexpr bool kInterpolateBinsDefault = bins::kInterpolateBinsDefault;

    /// Throws FormatError if the basis is not bins / moment or a refined cell misses a node.
    BinsLookup(const Volume& volume, OutsidePolicy outside, bool interpolateBins = kInterpolateBinsDefault);
    const bins::BasisSpec& spec() const { return spec_; }
    /// ChannelLookup::irradiance without the virtual call into the basis (the bins are known).
    Rgb irradiance(const Vec3f& x, const Vec3f& d) const override {
        int channels[4];
        float weights[4];
        const int n = bins::lookupWeights(spec_.resolution, interpolate_, d, channels, weights);
        return sumTerms(x, channels, weights, n);
    }

    static bool accepts(const Volume& volume);

private:
    bins::BasisSpec spec_;
    bool interpolate_;
};

/// The simple lookup BinsLookup is tested against: the bin of d by bins::binOf (no blending
/// of bins), descent through the volume's refined-cell lists and nodes by binary search,
/// interpolation in double. Throws FormatError if it would read a node that is not active.
Rgbd referenceBinsLookup(const Volume& volume, const Vec3d& x, const Vec3f& d);

}  // namespace vdblight
