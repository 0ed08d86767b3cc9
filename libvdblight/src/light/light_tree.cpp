#include "light_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace vdblight {

namespace {
double safeAcos(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }
}  // namespace

LightBounds unionBounds(const LightBounds& a, const LightBounds& b) {
    if (!(a.power > 0) && a.box.empty()) return b;
    if (!(b.power > 0) && b.box.empty()) return a;
    LightBounds u;
    u.box = a.box;
    u.box.extend(b.box.lo);
    u.box.extend(b.box.hi);
    u.power = a.power + b.power;
    u.thetaE = std::max(a.thetaE, b.thetaE);
    u.twoSided = a.twoSided || b.twoSided;
    // Cone union: the smallest cone around both (a inside b, b inside a, or a new axis
    // rotated from a's towards b's).
    const double d = safeAcos(dot(a.axis, b.axis));
    if (std::min(d + b.thetaO, kPi) <= a.thetaO) {
        u.axis = a.axis, u.thetaO = a.thetaO;
    } else if (std::min(d + a.thetaO, kPi) <= b.thetaO) {
        u.axis = b.axis, u.thetaO = b.thetaO;
    } else {
        const double theta = 0.5 * (a.thetaO + d + b.thetaO);
        const Vec3d ortho = b.axis - a.axis * dot(a.axis, b.axis);
        const double len = length(ortho);
        if (theta >= kPi || !(len > 1e-12)) {
            u.axis = a.axis, u.thetaO = kPi;
        } else {
            const double r = theta - a.thetaO;  // rotate a's axis by r towards b's
            u.axis = normalize(a.axis * std::cos(r) + ortho * (std::sin(r) / len));
            u.thetaO = theta;
        }
    }
    return u;
}

double LightTree::importance(const LightBounds& b, const Vec3d& x, const Vec3d* n) {
    return importance(b, Cone::of(b), x, n);
}

LightTree::Cone LightTree::Cone::of(const LightBounds& b) {
    return {std::cos(b.thetaO), std::sin(b.thetaO), std::cos(b.thetaE)};
}

// The angles are handled through their cosines and sines (no inverse trigonometry): for
// clamped differences, cos(max(0, a - b)) = 1 if a < b, else cos a cos b + sin a sin b.
double LightTree::importance(const LightBounds& b, const Cone& cone, const Vec3d& x, const Vec3d* n) {
    if (!(b.power > 0)) return 0;
    const Vec3d d = x - b.box.center();  // from the lights to x
    const double d2 = dot(d, d);
    const Vec3d half = b.box.size() * 0.5;
    const double r2 = dot(half, half);
    const double dist2 = std::max(d2, std::max(r2, 1e-30));
    // Half-angle subtended by the bounding sphere (pi from inside it).
    double cosB = -1, sinB = 0;
    if (d2 > r2) {
        const double sin2 = r2 / d2;
        sinB = std::sqrt(sin2);
        cosB = std::sqrt(1 - sin2);
    }
    const double len = std::sqrt(d2);
    double cosW = len > 0 ? std::clamp(dot(b.axis, d) / len, -1.0, 1.0) : 1.0;
    if (b.twoSided) cosW = std::abs(cosW);
    const double sinW = std::sqrt(std::max(0.0, 1 - cosW * cosW));
    // theta_w - theta_o, clamped at 0
    double cosX = 1, sinX = 0;
    if (cosW < cone.cosO) {
        cosX = cosW * cone.cosO + sinW * cone.sinO;
        sinX = sinW * cone.cosO - cosW * cone.sinO;
    }
    // minus theta_b, clamped at 0
    double cosP = 1;
    if (cosX < cosB) cosP = cosX * cosB + sinX * sinB;
    if (cosP < cone.cosE) return 0;
    double imp = b.power * std::max(0.0, cosP) / dist2;
    if (n && len > 0) {
        const double cosI = std::clamp(-dot(*n, d) / len, -1.0, 1.0);  // n against the direction to the lights
        if (cosI < cosB) {
            const double sinI = std::sqrt(std::max(0.0, 1 - cosI * cosI));
            const double c = cosI * cosB + sinI * sinB;
            if (c <= 0) return 0;
            imp *= c;
        }
    }
    return std::isfinite(imp) ? imp : 0.0;
}

LightTree::LightTree(const std::vector<LightBounds>& lights) {
    if (lights.empty()) return;
    std::vector<Vec3d> centroid(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) centroid[i] = lights[i].box.center();
    order_.resize(lights.size());
    std::iota(order_.begin(), order_.end(), 0u);
    nodes_.reserve(2 * lights.size());
    build(0, uint32_t(lights.size()), lights, centroid);
    slotOf_.resize(lights.size());
    for (uint32_t i = 0; i < order_.size(); ++i) slotOf_[order_[i]] = i;
}

int32_t LightTree::build(uint32_t begin, uint32_t end, const std::vector<LightBounds>& lights,
                         const std::vector<Vec3d>& centroid) {
    const int32_t index = int32_t(nodes_.size());
    nodes_.emplace_back();
    Node node;
    node.begin = begin;
    node.end = end;
    if (end - begin == 1) {
        node.bounds = lights[order_[begin]];
    } else {
        Bounds cb;
        for (uint32_t i = begin; i < end; ++i) cb.extend(centroid[order_[i]]);
        const Vec3d size = cb.size();
        const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
        const uint32_t mid = begin + (end - begin) / 2;
        auto key = [&](uint32_t l) { return centroid[l][axis]; };
        // Ties broken by index: the tree does not depend on the standard library's sort.
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](uint32_t a, uint32_t c) { return key(a) < key(c) || (key(a) == key(c) && a < c); });
        node.left = build(begin, mid, lights, centroid);
        node.right = build(mid, end, lights, centroid);
        node.bounds = unionBounds(nodes_[node.left].bounds, nodes_[node.right].bounds);
    }
    node.cone = Cone::of(node.bounds);
    nodes_[index] = node;
    return index;
}

double LightTree::leftProbability(const Node& node, const Vec3d& x, const Vec3d* n) const {
    const Node& l = nodes_[node.left];
    const Node& r = nodes_[node.right];
    const double il = importance(l.bounds, l.cone, x, n), ir = importance(r.bounds, r.cone, x, n);
    const double byCount = double(l.end - l.begin) / double(node.end - node.begin);
    const double byImportance = il + ir > 0 && std::isfinite(il + ir) ? il / (il + ir) : byCount;
    return (1.0 - kUniformMix) * byImportance + kUniformMix * byCount;
}

uint32_t LightTree::sample(const Vec3d& x, const Vec3d* n, double u, double& pmf) const {
    pmf = 1.0;
    int32_t k = 0;
    while (nodes_[k].left >= 0) {
        const double pl = leftProbability(nodes_[k], x, n);
        if (u < pl) {
            u = u / pl;
            pmf *= pl;
            k = nodes_[k].left;
        } else {
            u = (u - pl) / (1.0 - pl);
            pmf *= 1.0 - pl;
            k = nodes_[k].right;
        }
        u = std::min(std::max(u, 0.0), std::nextafter(1.0, 0.0));
    }
    return order_[nodes_[k].begin];
}

double LightTree::pmf(const Vec3d& x, const Vec3d* n, uint32_t l) const {
    const uint32_t slot = slotOf_[l];
    double p = 1.0;
    int32_t k = 0;
    while (nodes_[k].left >= 0) {
        const double pl = leftProbability(nodes_[k], x, n);
        if (slot < nodes_[nodes_[k].left].end) {
            p *= pl;
            k = nodes_[k].left;
        } else {
            p *= 1.0 - pl;
            k = nodes_[k].right;
        }
    }
    return p;
}

}  // namespace vdblight
