// The fast lookup of single-level SH order-4 volumes (`sh:4`, the default bake's basis), which
// IrradianceQuery picks for them before the generic ChannelLookup (registry.cpp). It gives
// ChannelLookup's answers, every interface method included (same locate, same weights, same
// summation order: the same bits), from a layout made for the irradiance: one record per node
// holding everything a lookup reads there (issue 33, part 4), so that a corner is one stretch
// of memory instead of a piece of each of several arrays:
// - the 18 coefficients that carry irradiance (bands 0, 1, 2 and 4; A_3 = 0), RGB each, in
//   coefficient order (54 floats) and 2 floats of zero padding, so that a lookup blends the
//   eight corners' 56 floats and multiplies them by their terms' weights in whole 4- or 8-lane
//   vectors, then sums each colour's 18 products in term order;
// - where the volume has depth moments, the node's prepared depth values (depth_weights.h:
//   means and squared deviations, the squares made once here instead of at every lookup).
// Band 3 (7 RGB coefficients) sits in its own array, read only by channelValues / shRadiance
// (export), so the irradiance path does not pull it through the cache. Memory: 56 + 21 floats
// per node, 12 more with depth moments. Internal to the query module (tests and benchmarks
// include it as "../libvdblight/src/query/sh4_uniform_lookup.h").
#pragma once

#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"
#include "shared_cell.h"

namespace vdblight {

class ShFourUniformLookup final : public VolumeLookup, public query_detail::SharesCell {
public:
    /// True for an `sh:4` volume (the registered basis's channels) of one dense level.
    static bool accepts(const Volume& volume);
    /// FormatError if the volume is not one that accepts() takes or its arrays do not match its grid.
    ShFourUniformLookup(const Volume& volume, OutsidePolicy outside);
    /// Not copied: the records' first one sits at an offset chosen for this object's storage.
    ShFourUniformLookup(const ShFourUniformLookup&) = delete;
    ShFourUniformLookup& operator=(const ShFourUniformLookup&) = delete;

    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override { return blend(x, n, nullptr); }
    /// irradiance, and the cell it blended (the default volume's visibility reuses it).
    Rgb irradianceSharingCell(const Vec3f& x, const Vec3f& n, query_detail::SharedCell& cell) const override {
        return blend(x, n, &cell);
    }
    /// On: the AVX2 build where the CPU has it (the same bits; the default, it measured
    /// faster: sh4_uniform_lookup.cpp); off: the portable (SSE2) build.
    void setWideVectors(bool on);
    Bounds bounds() const override { return grid_.nodeBounds(); }
    /// The 25 stored RGB coefficients interpolated at x (ChannelLookup::channelValues: located
    /// in double, exact at a node; clamped into the box whatever the outside policy).
    void channelValues(const Vec3d& x, float* out) const override;
    /// The first nine of channelValues (the volume's SH order-2 part).
    void shRadiance(const Vec3d& x, Rgb out[9]) const override;
    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }

    /// Stored coefficients per colour (bands 0..4) and those that carry irradiance (A_l != 0).
    static constexpr int kCoeffs = 25;
    static constexpr int kLitCoeffs = 18;
    static constexpr int kLitFloats = kLitCoeffs * 3;
    static constexpr int kDarkFloats = (kCoeffs - kLitCoeffs) * 3;
    /// Floats of a node record's lit part: kLitFloats and the zero padding.
    static constexpr int kLitStride = kLitFloats + 2;
    /// Floats per node record (kLitStride, plus the prepared depth where the volume has it).
    int recordFloats() const { return stride_; }

private:
    /// The eight corner nodes around the lattice coordinate g (clamped into the node box) and
    /// their weights, trilinear or depth-weighted, as ChannelLookup::locate on a single level;
    /// also as a SharedCell if `cell` is not null.
    template <class T>
    void locate(const T g[3], std::size_t corner[8], float weight[8], query_detail::SharedCell* cell = nullptr) const;
    Rgb blendIrradiance(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const;
    /// blendIrradiance compiled for AVX2 (no FMA, so the same operations in the same order: the
    /// same bits), picked at run time where the CPU has it (query/wide_vectors.h).
    Rgb blendIrradianceAvx2(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const;
    /// The body of both, its blend over the corners in vectors of type V (4 or 8 floats).
    template <class V>
    Rgb blendIrradianceBody(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const;
    Rgb blend(const Vec3f& x, const Vec3f& n, query_detail::SharedCell* cell) const {
        return avx2_ ? blendIrradianceAvx2(x, n, cell) : blendIrradiance(x, n, cell);
    }

    GridSpec grid_;
    OutsidePolicy outside_;
    Vec3f origin_;
    float invSpacing_ = 1;
    float lobe_[kLitCoeffs] = {};  ///< float(A_l) of each lit coefficient, as ShBasis::terms rounds it
    /// Per node stride_ floats: [lit coefficient][colour] as stored (no A_l), 2 zeros, then the
    /// prepared depth (query_detail::prepareDepth) if the volume has depth moments.
    std::vector<float> records_;
    std::size_t recordOffset_ = 0;  ///< floats before the first record, which starts 16-byte aligned
    const float* record(std::size_t node) const { return records_.data() + recordOffset_ + node * std::size_t(stride_); }
    int stride_ = kLitStride;
    std::vector<float> dark_;  ///< per node kDarkFloats: band 3, [coefficient][colour] as stored
    bool hasDepth_ = false;
    bool depthWeights_ = false;
    bool avx2_ = false;
};

}  // namespace vdblight
