// DeferredPaths (light.h): a batch of paths whose NEE shadow rays are traced together, then
// read back in gatherRadiance's order and arithmetic (the same bits as one ray at a time).

#include <algorithm>

#include "vdblight/light/light.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

void DeferredPaths::clear() {
    terms_.clear();
    first_.clear();
    pathEnd_.clear();
    firstEmission_.clear();
    rays_.clear();
}

uint32_t DeferredPaths::addShadowRay(const Ray& ray) {
    rays_.push_back(ray);
    return uint32_t(rays_.size() - 1);
}

void DeferredPaths::trace(const Tracer& tracer) {
    if (blockedCapacity_ < rays_.size()) {
        blockedCapacity_ = std::max(rays_.size(), 2 * blockedCapacity_);
        blocked_.reset(new bool[blockedCapacity_]);
    }
    tracer.occluded(rays_.data(), rays_.size(), blocked_.get());
}

Rgb DeferredPaths::termValue(const Term& t) const {
    // gatherRadiance's arithmetic: a direct term is throughput * directAtSurface(...) / pi
    // with directAtSurface = 0 + (weight if unblocked).
    if (!t.direct) return t.value;
    Rgb e{0, 0, 0};
    const bool lit = t.shadow != kNoShadowRay && !blocked_[t.shadow];
    e += lit ? t.value : Rgb(0, 0, 0);  // 0 + 0 = 0: the bits of not adding; no branch
    return t.throughput * e * float(kInvPi);
}

Rgb DeferredPaths::radiance(std::size_t i) const {
    // The terms in gatherRadiance's order and arithmetic.
    Rgb radiance{0, 0, 0};
    for (uint32_t k = i == 0 ? 0 : pathEnd_[i - 1]; k < pathEnd_[i]; ++k) radiance += termValue(terms_[k]);
    return radiance;
}

bool DeferredPaths::firstVertexIrradiance(std::size_t i, Vec3f& p, Vec3f& n, Rgb& irradiance) const {
    if (i >= first_.size() || first_[i].from == kNoShadowRay) return false;
    const FirstVertex& v = first_[i];
    Rgb sum{0, 0, 0};
    for (uint32_t k = v.from; k < pathEnd_[i]; ++k)
        if (k != v.skip) sum += termValue(terms_[k]);
    // The continuation's terms carry the first vertex's albedo (and roulette's 1/q, which
    // stays: a path roulette ends adds 0, so the mean is right).
    for (int c = 0; c < 3; ++c) irradiance[c] = v.albedo[c] > 0 ? float(kPi) * sum[c] / v.albedo[c] : 0.0f;
    p = v.p;
    n = v.n;
    return true;
}

}  // namespace vdblight
