// "sh2": real SH order 2 radiance coefficients (sh.h) as a Basis. The bake keeps its own
// optimised gather for it (bake.h); this class gives the registry, the generic lookup and
// export what the basis is.
#include <memory>

#include "vdblight/basis/basis.h"
#include "basis/sh.h"

namespace vdblight {

namespace {
class Sh2Basis final : public Basis {
public:
    Sh2Basis() : desc_(BasisDesc::sh2()) {}
    const BasisDesc& desc() const override { return desc_; }
    std::string describe() const override { return "radiance SH coefficients"; }
    std::size_t accumulatorSize() const override { return sh::kCoeffs; }
    void accumulate(const Vec3f& w, const Rgbd& radiance, double weight, Rgbd* acc) const override {
        float y[sh::kCoeffs];
        sh::evalUnrolled(w, y);
        for (int j = 0; j < sh::kCoeffs; ++j) acc[j] += radiance * (weight * double(y[j]));
    }
    void finish(const Rgbd* acc, float* values) const override {
        for (int j = 0; j < sh::kCoeffs; ++j)
            for (int c = 0; c < 3; ++c) values[3 * j + c] = float(acc[j][c]);
    }
    int maxTerms() const override { return sh::kCoeffs; }
    int shCoefficients() const override { return sh::kCoeffs; }
    int terms(const Vec3f& d, int* channels, float* weights) const override {
        sh::irradianceWeights(d, weights);
        for (int j = 0; j < sh::kCoeffs; ++j) channels[j] = j;
        return sh::kCoeffs;
    }
    std::string formula() const override {
        return "E = sum_j A_l(j) * L_j * Y_j(n) per colour channel, L_j = texture sh_l<l>m<m>.rgb, Y_j and A_l as in "
               "docs/format.md (SH convention)";
    }

private:
    BasisDesc desc_;
};
}  // namespace

BasisKind sh2BasisKind() {
    return {"sh2", "real SH order 2: 9 radiance coefficients; the default of --quality preview and of every pass but the presets' point gather",
            [](const std::string& text) -> std::unique_ptr<Basis> {
                return text == "sh2" ? std::make_unique<Sh2Basis>() : nullptr;
            },
            [](const BasisDesc& desc) -> std::unique_ptr<Basis> {
                const BasisDesc sh2 = BasisDesc::sh2();
                return desc.kind == sh2.kind && desc.channelNames == sh2.channelNames ? std::make_unique<Sh2Basis>() : nullptr;
            }};
}

}  // namespace vdblight
