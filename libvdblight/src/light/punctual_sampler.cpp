#include "punctual_sampler.h"

#include <algorithm>
#include <cmath>

#include "vdblight/scene.h"

namespace vdblight {

namespace {
// Cosine of the angle between the spot axis and the direction from the spot apex to the
// nearest... conservative test: can any point of the sphere (centre, radius) be inside the cone?
bool coneMayReachSphere(const SpotLight& s, const Vec3d& centre, double radius) {
    const Vec3d d = centre - Vec3d(s.position);
    const double dist = length(d);
    if (dist <= radius) return true;
    const double cosAxis = dot(d, Vec3d(s.direction)) / dist;
    const double angle = std::acos(std::clamp(cosAxis, -1.0, 1.0));
    const double spread = std::asin(std::min(1.0, radius / dist));
    return angle - spread <= double(s.outerConeAngle);
}
}  // namespace

PunctualLightSampler::PunctualLightSampler(const Scene& scene) {
    Bounds b = scene.bounds();
    for (const PointLight& l : scene.pointLights) {
        lights_.push_back({l.position, std::max(0.0f, luminance(l.intensity)), -1});
        b.extend(Vec3d(l.position));
    }
    for (std::size_t s = 0; s < scene.spotLights.size(); ++s) {
        lights_.push_back({scene.spotLights[s].position, std::max(0.0f, luminance(scene.spotLights[s].intensity)),
                           int32_t(s)});
        b.extend(Vec3d(scene.spotLights[s].position));
    }
    const std::size_t n = lights_.size();
    if (n == 0) return;
    // A few thousand cells at most: the table is cells x lights doubles.
    res_ = n < 64 ? 2 : (n * 512 * 8 > (std::size_t(64) << 20) ? 4 : 8);
    const Vec3d size = vmax(b.size(), Vec3d(1e-6, 1e-6, 1e-6));
    lo_ = b.lo;
    cellSize_ = size / double(res_);
    const double half = 0.5 * length(cellSize_);
    const std::size_t cells = std::size_t(res_) * res_ * res_;
    cdf_.resize(cells * n);
    std::vector<double> importance(n);
    for (std::size_t c = 0; c < cells; ++c) {
        const int i = int(c % res_), j = int((c / res_) % res_), k = int(c / (std::size_t(res_) * res_));
        const Vec3d clo = lo_ + Vec3d(i * cellSize_.x, j * cellSize_.y, k * cellSize_.z);
        const Vec3d chi = clo + cellSize_;
        const Vec3d centre = (clo + chi) * 0.5;
        double total = 0;
        for (std::size_t l = 0; l < n; ++l) {
            const Vec3d p(lights_[l].position);
            const Vec3d nearest = vmin(vmax(p, clo), chi);
            const Vec3d d = nearest - p;
            double imp = lights_[l].power / std::max(dot(d, d), half * half);
            if (lights_[l].spot >= 0 && !coneMayReachSphere(scene.spotLights[lights_[l].spot], centre, half)) imp = 0;
            importance[l] = imp;
            total += imp;
        }
        const double mix = total > 0 ? kUniformMix : 1.0;
        double running = 0;
        double* cdf = cdf_.data() + c * n;
        for (std::size_t l = 0; l < n; ++l) {
            running += (total > 0 ? (1.0 - mix) * importance[l] / total : 0.0) + mix / double(n);
            cdf[l] = running;
        }
        for (std::size_t l = 0; l < n; ++l) cdf[l] /= running;
        cdf[n - 1] = 1.0;
    }
}

std::size_t PunctualLightSampler::cellOf(const Vec3f& x) const {
    auto axis = [&](float v, double lo, double size) {
        const double t = std::floor((double(v) - lo) / size);
        return std::size_t(std::clamp(t, 0.0, double(res_ - 1)));  // also maps NaN to 0
    };
    return axis(x.x, lo_.x, cellSize_.x) + res_ * (axis(x.y, lo_.y, cellSize_.y) + res_ * axis(x.z, lo_.z, cellSize_.z));
}

uint32_t PunctualLightSampler::sample(const Vec3f& x, double u, double& pmf) const {
    const std::size_t n = lights_.size();
    const double* cdf = cdf_.data() + cellOf(x) * n;
    const std::size_t l = std::min<std::size_t>(std::upper_bound(cdf, cdf + n, u) - cdf, n - 1);
    pmf = cdf[l] - (l > 0 ? cdf[l - 1] : 0.0);
    return uint32_t(l);
}

double PunctualLightSampler::pmf(const Vec3f& x, uint32_t l) const {
    const double* cdf = cdf_.data() + cellOf(x) * lights_.size();
    return cdf[l] - (l > 0 ? cdf[l - 1] : 0.0);
}

}  // namespace vdblight
