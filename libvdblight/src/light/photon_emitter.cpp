// Photon emission (see photon_emitter.h for the lights and their power).
#include "light/photon_emitter.h"

#include <algorithm>

#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// The glTF KHR_lights_punctual falloff, as in light/radiance_estimator.cpp.
float spotFalloff(const SpotLight& s, float cosAngle) {
    const float cosOuter = std::cos(s.outerConeAngle), cosInner = std::cos(s.innerConeAngle);
    if (cosAngle <= cosOuter) return 0.0f;
    if (cosInner - cosOuter <= 1e-6f) return 1.0f;
    const float t = std::min(1.0f, (cosAngle - cosOuter) / (cosInner - cosOuter));
    return t * t;
}

/// Integral of an equirectangular map's (nearest-texel) radiance over the sphere.
Rgb skyIntegral(const Sky& sky) {
    if (!sky.map) return sky.constant * float(4.0 * kPi);
    const SkyMap& m = *sky.map;
    Rgbd sum{0, 0, 0};
    for (int r = 0; r < m.height; ++r) {
        // Row r covers polar angles [r, r + 1] * pi / height; each texel 2 pi / width of azimuth.
        const double solidAngle = (std::cos(r * kPi / m.height) - std::cos((r + 1) * kPi / m.height)) * 2.0 * kPi / m.width;
        for (int c = 0; c < m.width; ++c) sum += Rgbd(m.texels[std::size_t(r) * m.width + c]) * solidAngle;
    }
    return Rgb(sum);
}

/// Unit direction within `cosOuter` of `axis`, uniform in solid angle.
Vec3f uniformCone(const Vec3f& axis, float cosOuter, float u, float v) {
    const float c = 1.0f - u * (1.0f - cosOuter);
    const float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
    const float phi = float(2.0 * kPi) * v;
    Vec3f t, b;
    orthonormalBasis(axis, t, b);
    return t * (s * std::cos(phi)) + b * (s * std::sin(phi)) + axis * c;
}
}  // namespace

Rgb spotLightPower(float innerConeAngle, float outerConeAngle, const Rgb& intensity) {
    // In cos(angle) = c, f = ((c - cosOuter) / (cosInner - cosOuter))^2 on the ramp and 1 inside.
    const double co = std::cos(double(outerConeAngle)), ci = std::cos(double(innerConeAngle));
    const double ramp = std::max(ci - co, 0.0);
    const double solid = ramp <= 1e-6 ? 2.0 * kPi * (1.0 - co) : 2.0 * kPi * (ramp / 3.0 + (1.0 - ci));
    return intensity * float(solid);
}

PhotonEmitter::PhotonEmitter(const Scene& scene, const Bounds& cover) : scene_(scene) {
    if (cover.empty()) throw ValueError("photon emission needs a non-empty box to cover");
    centre_ = Vec3f(cover.center());
    radius_ = float(0.5 * length(cover.size())) * 1.001f + 1e-6f;
    const float beamArea = float(kPi) * radius_ * radius_;

    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const Material& m = scene.material(t);
        if (!m.isEmissive()) continue;
        const Vec3f a = scene.vertex(t, 0), b = scene.vertex(t, 1), c = scene.vertex(t, 2);
        const float area = 0.5f * length(cross(b - a, c - a));
        const float sides = m.twoSidedEmission ? 2.0f : 1.0f;
        lights_.push_back({Kind::Triangle, uint32_t(t), m.emission * (float(kPi) * area * sides)});
    }
    for (std::size_t i = 0; i < scene.pointLights.size(); ++i)
        lights_.push_back({Kind::Point, uint32_t(i), scene.pointLights[i].intensity * float(4.0 * kPi)});
    for (std::size_t i = 0; i < scene.spotLights.size(); ++i) {
        const SpotLight& s = scene.spotLights[i];
        lights_.push_back({Kind::Spot, uint32_t(i), spotLightPower(s.innerConeAngle, s.outerConeAngle, s.intensity)});
    }
    for (std::size_t i = 0; i < scene.directionalLights.size(); ++i)
        lights_.push_back({Kind::Directional, uint32_t(i), scene.directionalLights[i].irradiance * beamArea});
    if (!scene.sky.isBlack()) lights_.push_back({Kind::Sky, 0, skyIntegral(scene.sky) * beamArea});

    // Drop black lights; choose the others in proportion to luminous power.
    lights_.erase(std::remove_if(lights_.begin(), lights_.end(),
                                 [](const Light& l) { return !(luminance(l.power) > 0.0f) || !isFinite(l.power); }),
                  lights_.end());
    if (lights_.empty()) throw SceneError("the scene has no light to emit photons from (no emissive triangle, punctual light or sky)");
    double sum = 0;
    for (const Light& l : lights_) sum += luminance(l.power);
    double acc = 0;
    for (const Light& l : lights_) {
        acc += luminance(l.power);
        cdf_.push_back(float(acc / sum));
        total_ += l.power;
    }
    cdf_.back() = 1.0f;
}

Photon PhotonEmitter::beam(const Vec3f& dir, float u1, float u2) const {
    // A disk of radius R perpendicular to dir, one radius behind the centre: every line
    // along dir that meets the covered sphere passes through it.
    float dx, dy;
    concentricSquareToDisk(u1, u2, dx, dy);
    Vec3f t, b;
    orthonormalBasis(dir, t, b);
    Photon p;
    p.origin = centre_ - dir * radius_ + (t * dx + b * dy) * radius_;
    p.direction = dir;
    return p;
}

Photon PhotonEmitter::emit(float choose, float u1, float u2, float u3, float u4, float side) const {
    const std::size_t n = std::min(std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), choose) - cdf_.begin()),
                                   lights_.size() - 1);
    const Light& light = lights_[n];
    const float pmf = cdf_[n] - (n > 0 ? cdf_[n - 1] : 0.0f);
    Photon p;
    switch (light.kind) {
        case Kind::Triangle: {
            const Vec3f a = scene_.vertex(light.index, 0), b = scene_.vertex(light.index, 1),
                        c = scene_.vertex(light.index, 2);
            float b1, b2;
            uniformTriangle(u1, u2, b1, b2);
            const Vec3f pos = a * (1.0f - b1 - b2) + b * b1 + c * b2;
            Vec3f normal = normalize(cross(b - a, c - a));
            if (scene_.material(light.index).twoSidedEmission && side < 0.5f) normal = -normal;
            Vec3f t, bt;
            orthonormalBasis(normal, t, bt);
            const Vec3f local = cosineHemisphere(u3, u4);
            p.direction = normalize(t * local.x + bt * local.y + normal * local.z);
            p.origin = offsetRayOrigin(pos, normal, p.direction);
            p.power = light.power;
            break;
        }
        case Kind::Point:
            p.origin = scene_.pointLights[light.index].position;
            p.direction = uniformSphere(u3, u4);
            p.power = light.power;
            break;
        case Kind::Spot: {
            const SpotLight& s = scene_.spotLights[light.index];
            const Vec3f axis = normalize(s.direction);
            const float cosOuter = std::cos(s.outerConeAngle);
            p.origin = s.position;
            p.direction = uniformCone(axis, cosOuter, u3, u4);
            const float solid = float(2.0 * kPi) * (1.0f - cosOuter);
            p.power = s.intensity * (spotFalloff(s, dot(axis, p.direction)) * solid);
            break;
        }
        case Kind::Directional:
            p = beam(normalize(scene_.directionalLights[light.index].direction), u1, u2);
            p.power = light.power;
            break;
        case Kind::Sky: {
            const Vec3f toSky = uniformSphere(u3, u4);
            p = beam(-toSky, u1, u2);
            p.power = scene_.sky.radiance(toSky) * (float(4.0 * kPi) * float(kPi) * radius_ * radius_);
            break;
        }
    }
    p.power = p.power / pmf;
    return p;
}

}  // namespace vdblight
