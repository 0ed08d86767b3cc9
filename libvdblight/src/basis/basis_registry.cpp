// The registry of bases (basis.h) and the parts of the interface every basis shares.
// A new basis adds its BasisKind's declaration and one entry to the list below.
#include <cmath>

#include "vdblight/basis/basis.h"
#include "vdblight/core/errors.h"

namespace vdblight {

// Each kind lives in its own file (src/basis/<name>_basis.cpp).
BasisKind sh2BasisKind();
BasisKind shBasisKind();
BasisKind binsBasisKind();
BasisKind momentBasisKind();

const std::vector<BasisKind>& basisKinds() {
    static const std::vector<BasisKind> kinds = {
        sh2BasisKind(),
        shBasisKind(),
        binsBasisKind(),
        momentBasisKind(),
    };
    return kinds;
}

std::unique_ptr<Basis> makeBasis(const std::string& text) {
    for (const BasisKind& kind : basisKinds())
        if (std::unique_ptr<Basis> b = kind.parse(text)) return b;
    std::string syntaxes;
    const std::vector<BasisKind>& kinds = basisKinds();
    for (std::size_t k = 0; k < kinds.size(); ++k)
        syntaxes += std::string(k == 0 ? "" : (k + 1 == kinds.size() ? " or " : ", ")) + kinds[k].syntax;
    throw ValueError("--basis must be " + syntaxes + ", got '" + text + "'");
}

std::unique_ptr<Basis> basisOf(const BasisDesc& desc) {
    for (const BasisKind& kind : basisKinds())
        if (std::unique_ptr<Basis> b = kind.fromDesc(desc)) return b;
    return nullptr;
}

std::string basisChoices() {
    std::string s;
    for (const BasisKind& kind : basisKinds()) s += std::string(s.empty() ? "" : "; ") + kind.syntax + " (" + kind.help + ")";
    return s;
}

Vec3f Basis::lookupDirection(const Vec3f& n, const Vec3f& v) const {
    if (!viewDependent()) return n;
    return normalize(n * (2.0f * dot(n, v)) - v);  // the view mirrored about the normal
}

Rgb Basis::evaluate(const float* values, const Vec3f& d) const {
    std::vector<int> channels(static_cast<std::size_t>(maxTerms()));
    std::vector<float> weights(static_cast<std::size_t>(maxTerms()));
    const int n = terms(d, channels.data(), weights.data());
    Rgb e{0, 0, 0};
    for (int t = 0; t < n; ++t) {
        const float* q = values + 3 * channels[std::size_t(t)];
        e += Rgb(q[0], q[1], q[2]) * weights[std::size_t(t)];
    }
    return e;
}

std::vector<BasisTexture> Basis::textures() const {
    std::vector<BasisTexture> out;
    const BasisDesc& d = desc();
    for (int c = 0; c < d.channelCount(); ++c) {
        const std::string& name = d.channelNames[std::size_t(c)];
        BasisTexture t;
        t.name = name;
        t.components = {{name + " red", name + " green", name + " blue", "unused (0)"}};
        t.source = {{3 * c, 3 * c + 1, 3 * c + 2, -1}};
        out.push_back(std::move(t));
    }
    return out;
}

}  // namespace vdblight
