// Photon emission from every light of a Scene, in proportion to power.
//
// Lights and the power Phi (W, RGB) each one sends out:
//  - emissive triangle: Phi = pi L A (twice for two-sided emission); uniform point, cosine
//    direction around the emitting side;
//  - point light: Phi = 4 pi I; uniform direction;
//  - spot light: Phi = integral of I f(w) dw over the outer cone (f the glTF falloff);
//    uniform direction in the outer cone, weighted by f;
//  - directional light: the beam through a disk of radius R perpendicular to its direction,
//    where the sphere (C, R) encloses `cover` (scene and grid): Phi = E pi R^2;
//  - sky: uniform directions, each a beam through such a disk: Phi = pi R^2 * integral of L.
// A light is chosen with probability p_l proportional to the luminance of its power; the
// emitted photon carries (sample weight) / p_l, so that the mean over photons of the
// carried power is the scene's total power (the caller divides by the photon count).
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;

struct Photon {
    Vec3f origin;
    Vec3f direction;  ///< unit, direction of travel
    Rgb power;        ///< W, before division by the photon count
};

class PhotonEmitter {
public:
    /// Throws SceneError if nothing in the scene emits (no emitter, or all black).
    PhotonEmitter(const Scene& scene, const Bounds& cover);

    /// Emits one photon from five numbers in [0, 1): `choose` picks the light, (u1, u2) the
    /// point (on a triangle or beam disk), (u3, u4) the direction; `side` picks the face of a
    /// two-sided emitter.
    Photon emit(float choose, float u1, float u2, float u3, float u4, float side) const;

    /// Sum of the lights' power (W, RGB).
    Rgb totalPower() const { return total_; }
    std::size_t lightCount() const { return lights_.size(); }
    /// Centre and radius of the sphere from which beams (directional, sky) start.
    Vec3f beamCentre() const { return centre_; }
    float beamRadius() const { return radius_; }

private:
    enum class Kind : uint8_t { Triangle, Point, Spot, Directional, Sky };
    struct Light {
        Kind kind;
        uint32_t index;
        Rgb power;
    };
    Photon beam(const Vec3f& dir, float u1, float u2) const;

    const Scene& scene_;
    std::vector<Light> lights_;
    std::vector<float> cdf_;  ///< cumulative probability, last = 1
    Rgb total_{0, 0, 0};
    Vec3f centre_;
    float radius_ = 0;
};

/// Power of a spot light (W, RGB): integral of its intensity times the glTF falloff.
Rgb spotLightPower(float innerConeAngle, float outerConeAngle, const Rgb& intensity);

}  // namespace vdblight
