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

#include "vdblight/basis.h"
#include "vdblight/errors.h"

namespace vdblight {

namespace {
constexpr int kMaxOrder = 4;
constexpr int kMaxCoeffs = (kMaxOrder + 1) * (kMaxOrder + 1);

double factorial(int n) {
    double f = 1.0;
    for (int i = 2; i <= n; ++i) f *= i;
    return f;
}

/// The cosine-lobe factor A_l (header comment).
double cosineLobe(int l) {
    if (l == 0) return kPi;
    if (l == 1) return 2.0 * kPi / 3.0;
    if (l % 2) return 0.0;
    const double sign = (l / 2 - 1) % 2 ? -1.0 : 1.0;
    const double half = factorial(l / 2);
    return 2.0 * kPi * sign / ((l + 2.0) * (l - 1.0)) * factorial(l) / (std::pow(2.0, l) * half * half);
}

class ShBasis final : public Basis {
public:
    explicit ShBasis(int order) : order_(order), coeffs_((order + 1) * (order + 1)) {
        desc_.kind = "sh:" + std::to_string(order);
        for (int l = 0; l <= order; ++l)
            for (int m = -l; m <= l; ++m) {
                desc_.channelNames.push_back("sh_l" + std::to_string(l) + "m" + (m < 0 ? "_neg" : "") +
                                             std::to_string(std::abs(m)));
                lobe_[l * (l + 1) + m] = cosineLobe(l);
            }
    }
    const BasisDesc& desc() const override { return desc_; }
    std::string describe() const override { return "radiance SH coefficients, bands 0.." + std::to_string(order_); }

    std::size_t accumulatorSize() const override { return std::size_t(coeffs_); }
    void accumulate(const Vec3f& w, const Rgbd& radiance, double weight, Rgbd* acc) const override {
        float y[kMaxCoeffs];
        evalPolynomials(w, y);  // in float, as the SH order-2 gather's sh::evalUnrolled
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
        evalPolynomials(d, y);
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
    /// Y_j(d) for j < (order + 1)^2 as the explicit polynomials of bands 0..4 (docs/engines.md,
    /// "Shaders for sh:N"; the constants are docs/format.md's K_l^|m|, times sqrt(2) for
    /// m != 0, with the polynomial's own factors folded in, to 9 digits), in float: the bake
    /// projects every sample and the lookup weighs every term with them. sh_basis_test checks
    /// them against sh::evalGeneric (the Legendre recurrence in double). Band 3 is evaluated
    /// too (terms() skips it).
    void evalPolynomials(const Vec3f& d, float* y) const {
        const float x = d.x, yy = d.y, z = d.z;
        y[0] = 0.282094792f;
        if (order_ < 1) return;
        y[1] = 0.488602512f * yy, y[2] = 0.488602512f * z, y[3] = 0.488602512f * x;
        if (order_ < 2) return;
        const float x2 = x * x, y2 = yy * yy, z2 = z * z;
        y[4] = 1.092548431f * x * yy, y[5] = 1.092548431f * yy * z, y[6] = 0.315391565f * (3 * z2 - 1);
        y[7] = 1.092548431f * x * z, y[8] = 0.546274215f * (x2 - y2);
        if (order_ < 3) return;
        y[9] = 0.590043590f * yy * (3 * x2 - y2), y[10] = 2.890611443f * x * yy * z;
        y[11] = 0.457045799f * yy * (5 * z2 - 1), y[12] = 0.373176333f * z * (5 * z2 - 3);
        y[13] = 0.457045799f * x * (5 * z2 - 1), y[14] = 1.445305721f * z * (x2 - y2);
        y[15] = 0.590043590f * x * (x2 - 3 * y2);
        if (order_ < 4) return;
        y[16] = 2.503342942f * x * yy * (x2 - y2), y[17] = 1.770130770f * yy * z * (3 * x2 - y2);
        y[18] = 0.946174696f * x * yy * (7 * z2 - 1), y[19] = 0.669046544f * yy * z * (7 * z2 - 3);
        y[20] = 0.105785547f * (35 * z2 * z2 - 30 * z2 + 3), y[21] = 0.669046544f * x * z * (7 * z2 - 3);
        y[22] = 0.473087348f * (x2 - y2) * (7 * z2 - 1), y[23] = 1.770130770f * x * z * (x2 - 3 * y2);
        y[24] = 0.625835735f * (x2 * x2 - 6 * x2 * y2 + y2 * y2);
    }

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
