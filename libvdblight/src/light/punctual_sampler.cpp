#include "punctual_sampler.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "vdblight/scene/scene.h"

namespace vdblight {

PunctualLightSampler::PunctualLightSampler(const Scene& scene) {
    std::vector<Vec3d> pos;
    std::vector<double> power;
    for (const PointLight& l : scene.pointLights) {
        pos.emplace_back(l.position);
        power.push_back(std::max(0.0f, luminance(l.intensity)));
    }
    for (const SpotLight& s : scene.spotLights) {
        pos.emplace_back(s.position);
        power.push_back(std::max(0.0f, luminance(s.intensity)));
    }
    if (pos.empty()) return;
    lightOrder_.resize(pos.size());
    std::iota(lightOrder_.begin(), lightOrder_.end(), 0u);
    nodes_.reserve(2 * pos.size());
    build(0, uint32_t(pos.size()), pos, power);
    slotOf_.resize(pos.size());
    for (uint32_t i = 0; i < lightOrder_.size(); ++i) slotOf_[lightOrder_[i]] = i;
}

int32_t PunctualLightSampler::build(uint32_t begin, uint32_t end, const std::vector<Vec3d>& pos,
                                    const std::vector<double>& power) {
    const int32_t index = int32_t(nodes_.size());
    nodes_.emplace_back();
    Bounds b;
    double total = 0;
    for (uint32_t i = begin; i < end; ++i) {
        b.extend(pos[lightOrder_[i]]);
        total += power[lightOrder_[i]];
    }
    Node node;
    node.centre = (b.lo + b.hi) * 0.5;
    node.radius = 0.5 * length(b.size());
    node.power = total;
    node.begin = begin;
    node.end = end;
    if (end - begin > 1) {
        const Vec3d size = b.size();
        const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
        const uint32_t mid = begin + (end - begin) / 2;
        auto key = [&](uint32_t l) { return axis == 0 ? pos[l].x : (axis == 1 ? pos[l].y : pos[l].z); };
        // Ties broken by index: the tree does not depend on the standard library's sort.
        std::nth_element(lightOrder_.begin() + begin, lightOrder_.begin() + mid, lightOrder_.begin() + end,
                         [&](uint32_t a, uint32_t c) { return key(a) < key(c) || (key(a) == key(c) && a < c); });
        node.left = build(begin, mid, pos, power);
        node.right = build(mid, end, pos, power);
    }
    nodes_[index] = node;
    return index;
}

double PunctualLightSampler::leftProbability(const Node& node, const Vec3d& x) const {
    auto importance = [&](const Node& c) {
        const Vec3d d = c.centre - x;
        return c.power / std::max(dot(d, d), std::max(c.radius * c.radius, 1e-30));
    };
    const Node& l = nodes_[node.left];
    const Node& r = nodes_[node.right];
    const double il = importance(l), ir = importance(r);
    const double byCount = double(l.end - l.begin) / double(node.end - node.begin);
    const double byImportance = il + ir > 0 && std::isfinite(il + ir) ? il / (il + ir) : byCount;
    return (1.0 - kUniformMix) * byImportance + kUniformMix * byCount;
}

uint32_t PunctualLightSampler::sample(const Vec3f& x, double u, double& pmf) const {
    const Vec3d p(x);
    pmf = 1.0;
    int32_t n = 0;
    while (nodes_[n].left >= 0) {
        const double pl = leftProbability(nodes_[n], p);
        if (u < pl) {
            u = u / pl;
            pmf *= pl;
            n = nodes_[n].left;
        } else {
            u = (u - pl) / (1.0 - pl);
            pmf *= 1.0 - pl;
            n = nodes_[n].right;
        }
        u = std::min(std::max(u, 0.0), std::nextafter(1.0, 0.0));
    }
    return lightOrder_[nodes_[n].begin];
}

double PunctualLightSampler::pmf(const Vec3f& x, uint32_t l) const {
    const Vec3d p(x);
    const uint32_t slot = slotOf_[l];
    double pmf = 1.0;
    int32_t n = 0;
    while (nodes_[n].left >= 0) {
        const double pl = leftProbability(nodes_[n], p);
        if (slot < nodes_[nodes_[n].left].end) {
            pmf *= pl;
            n = nodes_[n].left;
        } else {
            pmf *= 1.0 - pl;
            n = nodes_[n].right;
        }
    }
    return pmf;
}

}  // namespace vdblight
