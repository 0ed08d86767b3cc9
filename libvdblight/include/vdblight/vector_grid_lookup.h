// Lookup of irradiance-vector volumes (basis "irradiance_vectors", one level): spatial
// interpolation of the six vectors, then E(n) by the blend (irradiance_vectors.h): Bounded by
// default (the quadratic blend, exact for SH bands 0-2 and uniform light, clamped to the
// bounds the vectors prove), Quadratic, or Paper (Pacanowski et al. section 4.1: the three
// vectors of n's signs blended by n^2, a lower bound of E; only those three are interpolated).
//
// Spatial interpolation is trilinear, or tricubic: per axis the Catmull-Rom cubic through
// four nodes (one-sided at the box's faces by linear extrapolation of the end nodes), which
// reproduces linear fields exactly and is C1 across cells.
//
// Depth moments (depth_moments.h, `bake --method photons --depth-moments`): where the volume
// has them, the trilinear weights are multiplied by each corner's visibility from the point,
// as in the SH lookups (query/depth_weights.h), so that a point behind a thin wall does not
// read the nodes on the other side. Tricubic interpolation ignores them (its sixty-four taps
// have no visibility test): depthWeighted() says which applies.
//
// It also reads the compact colour + direction form (basis "irradiance_vectors_compact",
// irradiance_vectors_compact.h): colour and direction are interpolated the same way, then
// decoded by iv::compactIrradiance.
#pragma once

#include <vector>

#include "vdblight/irradiance_vectors.h"
#include "vdblight/query.h"

namespace vdblight {

enum class Interpolation { Trilinear, Tricubic };

class VectorGridLookup final : public VolumeLookup {
public:
    VectorGridLookup(const Volume& volume, OutsidePolicy outside, Interpolation interp = Interpolation::Trilinear,
                     iv::Blend blend = iv::kDefaultBlend);
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override;
    Bounds bounds() const override { return grid_.nodeBounds(); }
    void setDepthWeights(bool on) override { depthWeights_ = on && !depth_.empty() && interp_ == Interpolation::Trilinear; }
    bool depthWeighted() const override { return depthWeights_; }
    /// Trilinear in double (whatever the Interpolation), snapped onto nodes within 1e-9 cells,
    /// depth-weighted as irradiance() is.
    void irradianceVectors(const Vec3d& x, float out[54]) const override;

    static bool accepts(const Volume& volume);

private:
    void locate(const Vec3f& x, int idx[3], float frac[3]) const;
    int weightsAndNodes(int axis, int i, float f, int nodes[4], float w[4]) const;

    GridSpec grid_;
    OutsidePolicy outside_;
    Interpolation interp_;
    iv::Blend blend_;
    Vec3f origin_;
    float invSpacing_;
    bool compact_ = false;
    int stride_ = 0;           ///< floats per node
    int perDirection_ = 0;     ///< floats per direction delta (9 full, 6 compact)
    std::vector<float> data_;  ///< the volume's level 0, stride_ floats per node
    std::vector<float> depth_;  ///< depth::kFloatsPerNode per node, or empty
    bool depthWeights_ = false;
};

/// The simple lookup used to test VectorGridLookup: trilinear in double over the volume's
/// own arrays (full form), then iv::referenceIrradiance. With depthWeights and a volume with
/// depth moments, the corners are weighted by referenceNodeVisibility (query.h).
Rgbd referenceVectorLookup(const Volume& volume, const Vec3d& x, const Vec3d& n, iv::Blend blend = iv::kDefaultBlend,
                           bool depthWeights = true);

}  // namespace vdblight
