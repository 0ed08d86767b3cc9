// The fast lookup of single-level SH order-2 volumes, which IrradianceQuery picks for them
// (registry.cpp). Internal to the query module (tests and benchmarks that time or compare it
// directly include it as "../libvdblight/src/query/sh_uniform_lookup.h").
#pragma once

#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/query/query.h"

namespace vdblight {

/// The fast lookup for single-level SH order-2 volumes.
class ShUniformLookup final : public VolumeLookup {
public:
    ShUniformLookup(const Volume& volume, OutsidePolicy outside);
    /// The portable build unless setWideVectors(true): vdblight_bench --only query, AVX2 against
    /// the portable build alternately in the same runs (2-core AMD EPYC with AVX-512, shared):
    /// with the 27 coefficients in node records padded to 28 floats (issue 33's sixth session),
    /// with depth weights 0.96x, 0.97x (before, on the 27-float array: 1.04x, 1.08x, 1.02x,
    /// 1.01x, 0.99x, when the AVX2 build ran with depth weights), the plain blend 1.00x, 1.00x.
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override {
        return avx2_ ? irradianceAvx2(x, n) : irradiancePortable(x, n);
    }
    /// On: the AVX2 build where the CPU has it (the same bits; for comparisons).
    void setWideVectors(bool on);
    Bounds bounds() const override { return grid_.nodeBounds(); }
    /// Nine interpolated radiance coefficients at x (RGB each).
    void radianceCoefficients(const Vec3f& x, Rgb out[9]) const;
    void shRadiance(const Vec3d& x, Rgb out[9]) const override;
    /// shRadiance as the sh2 basis's channels (basis.h; export --layout basis).
    void channelValues(const Vec3d& x, float* out) const override;
    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }

    static bool accepts(const Volume& volume);
    /// Floats of a record's coefficient part (27 and the zero), and of a whole record.
    static constexpr int kRecordFloats = 28;
    int recordFloats() const { return stride_; }

private:
    void locate(const Vec3f& x, int& i, int& j, int& k, float& fx, float& fy, float& fz) const;
    /// irradiance, compiled for the portable target and for AVX2 (query/wide_vectors.h: no FMA,
    /// the same operations in the same order, so the same bits), picked at run time.
    Rgb irradianceBody(const Vec3f& x, const Vec3f& n) const;
    Rgb irradiancePortable(const Vec3f& x, const Vec3f& n) const;
    Rgb irradianceAvx2(const Vec3f& x, const Vec3f& n) const;

    GridSpec grid_;
    OutsidePolicy outside_;
    Vec3f origin_;
    float invSpacing_;
    /// One record per node, everything a lookup reads there (issue 33, part 4): the 27
    /// coefficients channel-major [c][rgb] with A_l folded in, a zero (so that the blend runs on
    /// whole 4-lane vectors), then, where the volume has depth moments, the node's prepared
    /// depth values (query_detail::prepareDepth).
    std::vector<float> records_;
    int stride_ = kRecordFloats;
    bool hasDepth_ = false;
    bool depthWeights_ = false;
    bool avx2_ = false;
};

}  // namespace vdblight
