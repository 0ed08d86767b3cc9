// A light tree with orientation bounds, for choosing ONE light among many at a shading point
// in proportion to an estimate of its contribution there (the importance of pbrt-v4's
// BVHLightSampler / Conty Estevez & Kulla 2018, written from their description).
//
// Every light is described by LightBounds: a box, its power, and a cone of emission
// directions (axis w, spread theta_o of the emitters' axes around w, and theta_e beyond
// which nothing is emitted): a point light emits everywhere (theta_o = pi), a spot light
// inside its outer cone (theta_o = outer angle, theta_e = 0), an emissive triangle around its
// normal (theta_o = 0, theta_e = pi/2; two-sided ones on both sides). A binary tree over the
// lights (median split of the longest axis of the centroids) stores the union of its lights'
// bounds per node. The importance of a node at a point p (and, at a surface, its normal n) is
//   power * cos(theta') / max(d^2, r^2)  [* cos(max(0, theta_i - theta_b)) with a normal]
// with d the distance from p to the node's centre, r its bounding radius, theta_b the
// half-angle the bounding sphere subtends at p, theta' = max(0, theta_w - theta_o - theta_b)
// the smallest angle between the emission cone and the direction to p (0 if theta' > theta_e).
// Sampling walks from the root choosing a child by importance, mixed with kUniformMix of the
// children's light counts so that every light keeps a non-zero probability; the pmf of the
// chosen light is the product of the choices, and weight / pmf is unbiased.
#pragma once

#include <cstdint>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct LightBounds {
    Bounds box;
    double power = 0;
    Vec3d axis{0, 0, 1};    ///< unit
    double thetaO = kPi;    ///< spread of the emitters' axes around `axis`
    double thetaE = 0.5 * kPi;  ///< emission beyond thetaO
    bool twoSided = false;  ///< also emits around -axis
};

class LightTree {
public:
    static constexpr double kUniformMix = 0.01;

    LightTree() = default;
    explicit LightTree(const std::vector<LightBounds>& lights);

    std::size_t size() const { return order_.size(); }
    /// Chooses a light for point x (normal n, or nullptr in free space) with u in [0, 1):
    /// returns its index in the constructor's list and its probability.
    uint32_t sample(const Vec3d& x, const Vec3d* n, double u, double& pmf) const;
    /// Probability that sample() picks light `l` at x (with the same normal).
    double pmf(const Vec3d& x, const Vec3d* n, uint32_t l) const;
    /// The importance of `b` at x (exposed for tests).
    static double importance(const LightBounds& b, const Vec3d& x, const Vec3d* n);

private:
    struct Cone {
        double cosO, sinO, cosE;
        static Cone of(const LightBounds& b);
    };
    static double importance(const LightBounds& b, const Cone& cone, const Vec3d& x, const Vec3d* n);
    struct Node {
        LightBounds bounds;
        Cone cone{};
        uint32_t begin = 0, end = 0;    ///< range in order_
        int32_t left = -1, right = -1;  ///< children, -1 for a leaf (one light)
    };
    int32_t build(uint32_t begin, uint32_t end, const std::vector<LightBounds>& lights,
                  const std::vector<Vec3d>& centroid);
    double leftProbability(const Node& node, const Vec3d& x, const Vec3d* n) const;

    std::vector<Node> nodes_;
    std::vector<uint32_t> order_;  ///< light indices in tree order
    std::vector<uint32_t> slotOf_; ///< light index -> position in order_
};

/// The union of two emission cones (smallest cone containing both), and of two bounds.
LightBounds unionBounds(const LightBounds& a, const LightBounds& b);

}  // namespace vdblight
