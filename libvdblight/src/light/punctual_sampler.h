// Many-light selection for punctual lights (point and spot): pick ONE light per shading
// point in proportion to an estimate of its contribution there, so that a vertex pays one
// shadow ray and O(log L) work instead of L shadow rays.
//
// A light tree (in the spirit of Conty Estevez & Kulla 2018, without orientation bounds):
// a binary tree over the lights, split at the median of the longest axis, each node holding
// its lights' total power (luminance of the intensity) and bounding sphere. Sampling walks
// from the root; at each node it chooses a child with probability proportional to
//   importance = power / max(d^2, r^2),
// d = distance from the shading point to the child's centre, r = its radius (so a cluster
// around the point is not overweighted), mixed with kUniformMix of the children's light
// counts so every light keeps a non-zero probability. The pmf of the chosen light is the
// product of the choices along its path; the estimator weight/pmf is unbiased.
// Spot cones and occlusion are ignored by the importance (they are evaluated by the caller).
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct Scene;

class PunctualLightSampler {
public:
    static constexpr double kUniformMix = 0.05;

    explicit PunctualLightSampler(const Scene& scene);

    std::size_t lightCount() const { return lightOrder_.size(); }
    /// Chooses a light for a shading point at `x` with u in [0, 1); returns its index
    /// (into scene.pointLights then scene.spotLights) and its probability.
    uint32_t sample(const Vec3f& x, double u, double& pmf) const;
    /// Probability that sample() picks light `l` at `x` (for tests).
    double pmf(const Vec3f& x, uint32_t l) const;

private:
    struct Node {
        Vec3d centre;
        double radius = 0;
        double power = 0;
        uint32_t begin = 0, end = 0;  ///< range in lightOrder_
        int32_t left = -1, right = -1;  ///< children, -1 for a leaf (one light)
    };
    int32_t build(uint32_t begin, uint32_t end, const std::vector<Vec3d>& pos, const std::vector<double>& power);
    /// Probability of choosing the left child of `node` at x.
    double leftProbability(const Node& node, const Vec3d& x) const;

    std::vector<Node> nodes_;
    std::vector<uint32_t> lightOrder_;  ///< light indices, in tree order
    std::vector<uint32_t> slotOf_;      ///< light index -> position in lightOrder_
};

}  // namespace vdblight
