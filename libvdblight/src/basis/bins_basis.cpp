// "bins:R" and "moment:n[:R]" (bins.h) as Bases. The bake keeps its own gather for them
// (bake_bins.h: per-bin stratified samples, the same bits as before the interface); this
// class is what the registry, the generic lookup and export know of them, and it bakes
// through the generic gather too (samples binned by direction, then the quadrature).
#include <memory>
#include <mutex>

#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"

namespace vdblight {

namespace {
class BinsBasis final : public Basis {
public:
    BinsBasis(const bins::BasisSpec& spec, bool interpolate) : spec_(spec), interpolate_(interpolate), desc_(bins::basis(spec)) {}
    const BasisDesc& desc() const override { return desc_; }
    std::string describe() const override {
        return spec_.kind == bins::BasisSpec::Kind::Moment ? "moment per equal-area bin, query with --view"
                                                           : "irradiance per equal-area bin";
    }
    std::size_t accumulatorSize() const override { return std::size_t(spec_.binCount()); }
    void accumulate(const Vec3f& w, const Rgbd& radiance, double weight, Rgbd* acc) const override {
        acc[bins::binOf(spec_.resolution, w)] += radiance * weight;  // the integral over the bin
    }
    void finish(const Rgbd* acc, float* values) const override {
        // Quadrature of eq. 4 / 5 (bins.h): H_j = sum_i W_ji I_i / Omega.
        std::call_once(once_, [&] { weights_ = bins::quadratureWeights(spec_); });
        const int n = spec_.binCount();
        const double invOmega = 1.0 / bins::binSolidAngle(spec_.resolution);
        for (int j = 0; j < n; ++j) {
            Rgbd h(0, 0, 0);
            for (int i = 0; i < n; ++i) h += acc[i] * (double(weights_[std::size_t(j) * n + i]) * invOmega);
            for (int c = 0; c < 3; ++c) values[3 * j + c] = float(h[c]);
        }
    }
    bool viewDependent() const override { return spec_.kind == bins::BasisSpec::Kind::Moment; }
    int maxTerms() const override { return 4; }
    int terms(const Vec3f& d, int* channels, float* weights) const override {
        return bins::lookupWeights(spec_.resolution, interpolate_, d, channels, weights);
    }
    std::vector<BasisTexture> textures() const override {
        std::vector<BasisTexture> t = Basis::textures();
        for (std::size_t c = 0; c < t.size(); ++c) {
            const std::string what = "bin " + std::to_string(c) + " (" + t[c].name + ")";
            t[c].components = {{what + " red", what + " green", what + " blue", "unused (0)"}};
        }
        return t;
    }
    std::string formula() const override {
        return "E(d).rgb = texture of the bin of direction d (bins.bin_of_direction; d = the normal n for bins:R, "
               "the view vector mirrored about n for moment:n), or the bilinear blend of the four bins of "
               "bins.blend (what vdblight query does)";
    }

private:
    bins::BasisSpec spec_;
    bool interpolate_;
    BasisDesc desc_;
    mutable std::once_flag once_;
    mutable std::vector<float> weights_;
};

std::unique_ptr<Basis> parseKind(const std::string& text, const char* prefix) {
    if (text.rfind(prefix, 0) != 0) return nullptr;
    return bins::makeBinsBasis(bins::parseBasisSpec(text));
}

std::unique_ptr<Basis> fromDesc(const BasisDesc& desc, bins::BasisSpec::Kind kind) {
    bins::BasisSpec spec;
    if (!bins::specFromVolume(desc, spec) || spec.kind != kind) return nullptr;
    return bins::makeBinsBasis(spec);
}
}  // namespace

std::unique_ptr<Basis> bins::makeBinsBasis(const BasisSpec& spec, bool interpolateBins) {
    return std::make_unique<BinsBasis>(spec, interpolateBins);
}

BasisKind binsBasisKind() {
    return {"bins:N", "Greger: 2 N^2 equal-area bins of irradiance; --rays rounded up to a multiple of the bin count",
            [](const std::string& text) { return parseKind(text, "bins:"); },
            [](const BasisDesc& desc) { return fromDesc(desc, bins::BasisSpec::Kind::Bins); }};
}

BasisKind momentBasisKind() {
    return {"moment:N[:R]", "the N-th moment over 2 R^2 bins, eq. 5, for glossy lookups with query --view; R = 17 by default",
            [](const std::string& text) { return parseKind(text, "moment:"); },
            [](const BasisDesc& desc) { return fromDesc(desc, bins::BasisSpec::Kind::Moment); }};
}

}  // namespace vdblight
