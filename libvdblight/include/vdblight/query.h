// Run-time lookup of irradiance E(x, n) from a volume (Kontkanen & Laine eq. 3;
// Greger et al. section 3.3): trilinear interpolation of the nodes' radiance
// coefficients, then the cosine-lobe convolution for the normal.
//
// The query copies the volume into its own layout once (coefficients pre-multiplied by
// the convolution constants, node-major, contiguous) so that a lookup touches 8 nodes
// and does no allocation. A query object is immutable and thread-safe.
#pragma once

#include <vector>

#include "vdblight/math.h"
#include "vdblight/volume.h"

namespace vdblight {

/// What a lookup does with a point outside the node box.
enum class OutsidePolicy {
    Clamp,  ///< use the nearest point of the node box (documented default)
    Throw,  ///< throw ValueError naming the point
};

class IrradianceQuery {
public:
    /// Throws FormatError if the volume's basis is not one the query knows.
    explicit IrradianceQuery(const Volume& volume, OutsidePolicy outside = OutsidePolicy::Clamp);

    /// Irradiance (W/m^2, RGB) at x for the unit normal n.
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const;
    /// Nine interpolated radiance coefficients at x (RGB each).
    void radianceCoefficients(const Vec3f& x, Rgb out[9]) const;

    /// True if x lies inside the box spanned by the nodes.
    bool inside(const Vec3f& x) const;
    const GridSpec& grid() const { return grid_; }

private:
    /// Cell origin (i, j, k) and fractions for x, applying the outside policy.
    void locate(const Vec3f& x, int& i, int& j, int& k, float& fx, float& fy, float& fz) const;

    GridSpec grid_;
    OutsidePolicy outside_;
    Vec3f origin_;
    float invSpacing_;
    std::vector<float> coeffs_;  ///< per node 27 floats: channel-major [c][rgb], A_l folded in
};

/// The simple, obviously correct lookup used to test IrradianceQuery: reads the volume's
/// own arrays, interpolates in double and convolves with the generic SH code.
Rgbd referenceLookup(const Volume& volume, const Vec3d& x, const Vec3d& n);

}  // namespace vdblight
