// The generic lookup of every basis in the registry (basis/basis.h): for a point x and a direction
// d, find the cell of x (descending through refined cells of a bilevel / adaptive volume as
// ShLevelsLookup does), interpolate trilinearly over its eight nodes (weighted by depth
// moments when the volume has them) and evaluate the basis's linear functional for d
// (Basis::terms) on the interpolated channels. d is the normal, or for a view-dependent
// basis the view mirrored about it (Basis::lookupDirection; IrradianceQuery::viewDependent).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vdblight/basis/basis.h"
#include "vdblight/query/query.h"

namespace vdblight {

class ChannelLookup : public VolumeLookup {
public:
    /// True if the volume's basis is a registered one (basisOf) with a dense level 0.
    static bool accepts(const Volume& volume);
    /// The registered basis of the volume (FormatError if none).
    ChannelLookup(const Volume& volume, OutsidePolicy outside);
    /// With a given basis (its channel count must match the volume's). Throws FormatError if
    /// level 0 has culled (inactive) nodes or a refined cell misses a node.
    ChannelLookup(const Volume& volume, OutsidePolicy outside, std::unique_ptr<Basis> basis);

    Rgb irradiance(const Vec3f& x, const Vec3f& d) const override;
    Bounds bounds() const override { return grid_.nodeBounds(); }
    /// All channels' RGB values (3 per channel) interpolated in space at x, no direction.
    void channelValues(const Vec3d& x, float* out) const override;
    /// For real SH of order >= 2 (Basis::shCoefficients() >= 9): its first nine channels,
    /// interpolated as channelValues (the SH order-2 part of the stored expansion).
    /// Otherwise FormatError, as the base class.
    void shRadiance(const Vec3d& x, Rgb out[9]) const override;
    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }
    const Basis& basis() const { return *basis_; }

    /// Most terms a basis may return to this lookup.
    static constexpr int kMaxTerms = 64;

protected:
    /// sum over corners c and terms t of w_c * weights_t * channel_t of corner c at x (the
    /// basis's terms already chosen: a subclass that knows its basis calls this directly).
    Rgb sumTerms(const Vec3f& x, const int* channels, const float* weights, int terms) const;

private:
    struct Level {
        std::vector<int32_t> child;   ///< per cell (level 0) or per brick cell: brick of the next level, -1
        std::vector<uint32_t> nodes;  ///< finer levels: per brick, (K+1)^3 node positions in `data`
        std::vector<float> data;      ///< node-major, channels * 3 floats per node
        std::vector<float> depth;     ///< the same nodes' depth moments; the finest level only, else empty
    };
    /// The level and eight corner nodes (positions in its data) around the level-0 lattice
    /// coordinate g (clamped into the node box), with their trilinear weights; T = float for
    /// irradiance, double for channelValues (exact at the nodes).
    template <class T>
    const Level& locate(const T g[3], std::size_t corner[8], float weight[8]) const;

    std::unique_ptr<Basis> basis_;
    GridSpec grid_;
    OutsidePolicy outside_;
    int K_ = 1;
    Vec3f origin_;
    float invSpacing_ = 1;
    std::size_t floatsPerNode_ = 0;
    std::vector<Level> levels_;
    bool hasDepth_ = false, depthWeights_ = false;
};

}  // namespace vdblight
