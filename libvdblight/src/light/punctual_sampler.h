// Many-light selection for punctual lights (point and spot): pick ONE light per shading
// point in proportion to a conservative estimate of its contribution there, so that a
// vertex pays one shadow ray and O(log L) work instead of L shadow rays.
//
// The estimate is precomputed on a coarse grid of cells over the lights and the scene:
// for cell c and light l, importance = luminance(I_l) / max(d^2, h^2), with d the distance
// from the light to the cell's box and h the cell's half diagonal (an upper bound of the
// light's irradiance anywhere in the cell, ignoring occlusion and spot falloff; a spot
// light whose cone misses the cell entirely gets importance 0). The selection pmf mixes
// it with a uniform choice: pmf = (1 - a) imp / sum(imp) + a / L, a = kUniformMix, so every
// light keeps a non-zero probability everywhere and the estimator weight/pmf is unbiased.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/math.h"

namespace vdblight {

struct Scene;

class PunctualLightSampler {
public:
    static constexpr double kUniformMix = 0.1;

    explicit PunctualLightSampler(const Scene& scene);

    std::size_t lightCount() const { return lights_.size(); }
    /// Chooses a light for a shading point at `x` with u in [0, 1); returns its index
    /// (into scene.pointLights then scene.spotLights) and its probability.
    uint32_t sample(const Vec3f& x, double u, double& pmf) const;
    /// Probability that sample() picks light `l` at `x` (for tests).
    double pmf(const Vec3f& x, uint32_t l) const;

private:
    std::size_t cellOf(const Vec3f& x) const;

    struct Light {
        Vec3f position;
        float power;        ///< luminance of the intensity
        int32_t spot = -1;  ///< index into scene.spotLights, -1 for a point light
    };
    std::vector<Light> lights_;
    Vec3d lo_, cellSize_;
    int res_ = 1;
    std::vector<double> cdf_;  ///< per cell, lights_.size() cumulative probabilities (last = 1)
};

}  // namespace vdblight
