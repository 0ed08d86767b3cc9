// "sh:N": real spherical harmonics of order N = 1..4 (bands l = 0..N, (N + 1)^2 radiance
// coefficients per colour), through the Basis interface alone (basis.h).
//
// Convention as sh.h's order 2 (docs/format.md "SH convention"): real, orthonormal, no
// Condon-Shortley phase, index j = l (l + 1) + m, channel j named sh_l<l>m<m> ("m_neg" for
// m < 0; sh:2's nine names are sh2's). Irradiance for a unit normal n (Ramamoorthi & Hanrahan):
//   E(n) = sum_j A_l(j) L_j Y_j(n),  A_0 = pi, A_1 = 2 pi / 3, A_l = 0 for odd l > 1 and for
//   even l: A_l = 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2)
//   (A_2 = pi / 4, A_3 = 0, A_4 = -pi / 24).
// Band 3 is stored (it is part of the radiance) but adds nothing to irradiance.
#include <cmath>
#include <memory>
#include <string>

#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"
#include "sh_polynomials.h"

namespace vdblight {

namespace {
constexpr int kMaxOrder = 4;
constexpr int kMaxCoeffs = (kMaxOrder + 1) * (kMaxOrder + 1);

class ShBasis final : public Basis {
public:
    explicit ShBasis(int order) : order_(order), coeffs_((order + 1) * (order + 1)) {
        desc_.kind = "sh:" + std::to_string(order);
        for (int l = 0; l <= order; ++l)
            for (int m = -l; m <= l; ++m) {
                desc_.channelNames.push_back("sh_l" + std::to_string(l) + "m" + (m < 0 ? "_neg" : "") +
                                             std::to_string(std::abs(m)));
                lobe_[l * (l + 1) + m] = sh::cosineLobe(l);
            }
    }
    const BasisDesc& desc() const override { return desc_; }
    std::string describe() const override { return "radiance SH coefficients, bands 0.." + std::to_string(order_); }

    std::size_t accumulatorSize() const override { return std::size_t(coeffs_); }
    void accumulate(const Vec3f& w, const Rgbd& radiance, double weight, Rgbd* acc) const override {
        float y[kMaxCoeffs];
        sh::evalPolynomials(order_, w, y);  // in float, as the SH order-2 gather's sh::evalUnrolled
        for (int j = 0; j < coeffs_; ++j) acc[j] += radiance * (weight * double(y[j]));
    }
    void finish(const Rgbd* acc, float* values) const override {
        for (int j = 0; j < coeffs_; ++j)
            for (int c = 0; c < 3; ++c) values[3 * j + c] = float(acc[j][c]);
    }

    int maxTerms() const override { return coeffs_; }
    int shCoefficients() const override { return coeffs_; }
    int terms(const Vec3f& d, int* channels, float* weights) const override {
        // The lookup's hot path (ChannelLookup, every query of the default's sh:4 volumes).
        float y[kMaxCoeffs];
        sh::evalPolynomials(order_, d, y);  // band 3 too (skipped below)
        int n = 0;
        for (int j = 0; j < coeffs_; ++j) {
            if (lobe_[j] == 0.0) continue;  // odd bands above 1: no irradiance
            channels[n] = j;
            weights[n++] = float(lobe_[j]) * y[j];
        }
        return n;
    }
    std::string formula() const override {
        return "E = sum_j A_l(j) * L_j * Y_j(n) per colour channel over j = l (l + 1) + m, l = 0.." + std::to_string(order_) +
               ", L_j = texture sh_l<l>m<m>.rgb (m_neg<|m|> for m < 0), Y_j real orthonormal SH without the "
               "Condon-Shortley phase (docs/format.md), A_0..A_4 = pi, 2 pi / 3, pi / 4, 0, -pi / 24";
    }

private:
    int order_;
    int coeffs_;
    BasisDesc desc_;
    double lobe_[kMaxCoeffs] = {};
};

std::unique_ptr<Basis> parse(const std::string& text) {
    if (text.rfind("sh:", 0) != 0) return nullptr;
    const std::string n = text.substr(3);
    if (n.size() != 1 || n[0] < '1' || n[0] > '0' + kMaxOrder)
        throw ValueError("--basis '" + text + "': the SH order must be 1, 2, 3 or 4 (bands 0..N, (N+1)^2 coefficients)");
    return std::make_unique<ShBasis>(n[0] - '0');
}
}  // namespace

BasisKind shBasisKind() {
    return {"sh:N", "real SH of order N = 1..4: (N+1)^2 radiance coefficients, bands 0..N; sh:2 is sh2's basis",
            &parse, [](const BasisDesc& desc) -> std::unique_ptr<Basis> {
                std::unique_ptr<Basis> b;
                try {
                    b = parse(desc.kind);
                } catch (const ValueError&) {
                    return nullptr;
                }
                return b && b->desc().channelNames == desc.channelNames ? std::move(b) : nullptr;
            }};
}

}  // namespace vdblight
