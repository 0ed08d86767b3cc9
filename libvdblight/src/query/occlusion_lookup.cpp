// OcclusionLookup (query_direct.h): stored light + exact direct light x interpolated visibility.

#include "query/query_direct.h"

#include "depth_weights.h"
#include "basis/shadow_edges.h"
#include "direct_sum.h"
#include "fast_exact_lights.h"
#include "lattice_locate.h"
#include "shared_cell.h"

#include <algorithm>
#include <cmath>

namespace vdblight {

OcclusionLookup::OcclusionLookup(std::unique_ptr<VolumeLookup> base, const Volume& volume)
    : base_(std::move(base)), lights_(volume.direct.lights), grid_(volume.levels.at(0).grid),
      visibility_(volume.levels[0].lightVisibility), edges_(volume.levels[0].lightShadowEdges), depth_(volume.levels[0].depth) {
    if (!volume.direct.hasVisibility() || visibility_.size() != grid_.nodeCount() * lights_.size())
        throw FormatError("occlusion lookup: the volume has no light visibility channels");
    if (!edges_.empty() && edges_.size() != visibility_.size() * shadow_edge::kFloatsPerLight)
        throw FormatError("occlusion lookup: the shadow edges do not match the visibility channels");
    if (!depth_.empty() && depth_.size() != grid_.nodeCount() * depth::kFloatsPerNode)
        throw FormatError("occlusion lookup: the depth moments do not match the grid");
    depthWeights_ = !depth_.empty();
    useEdges_ = !edges_.empty();
    // A lookup anchored far from the origin (shifted_lookup.cpp) offers no cell: it is read as before.
    const auto* shares = dynamic_cast<const query_detail::SharesCell*>(base_.get());
    if (shares && shares->sharesCell()) shares_ = shares;
    if (shares_) fastLights_ = std::make_shared<const query_detail::FastExactLights>(lights_);
    updateSharing();
}

void OcclusionLookup::visibility(const Vec3d& x, float* out) const {
    const std::size_t m = lights_.size();
    int base[3];
    const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    double f[3];
    query_detail::visibilityCell(grid_, x, base, f);
    for (std::size_t i = 0; i < m; ++i) out[i] = 0.0f;
    std::size_t node[8];
    int index[8][3];
    float w[8];
    const float* depth[8];
    for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        w[c] = float((di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]));
        const int i = std::min(base[0] + di, dims[0] - 1), j = std::min(base[1] + dj, dims[1] - 1),
                  k = std::min(base[2] + dk, dims[2] - 1);
        node[c] = grid_.index(i, j, k);
        index[c][0] = i, index[c][1] = j, index[c][2] = k;
        if (depthWeights_) depth[c] = depth_.data() + node[c] * depth::kFloatsPerNode;
    }
    // The SH lookups' weights (depth_weights.h): corners the point cannot see drop out.
    if (depthWeights_) query_detail::weightByDepth(w, depth, float(f[0]), float(f[1]), float(f[2]));
    if (useEdges_) {  // shadow_edges.h: the edges' ramp plus the corners' residuals
        for (std::size_t l = 0; l < m; ++l) {
            float v[8];
            const float* edge[8];
            for (int c = 0; c < 8; ++c) {
                v[c] = visibility_[node[c] * m + l];
                edge[c] = edges_.data() + (node[c] * m + l) * shadow_edge::kFloatsPerLight;
            }
            out[l] = query_detail::edgeVisibility(grid_, x, w, v, edge, index);
        }
        return;
    }
    for (int c = 0; c < 8; ++c) {
        if (w[c] == 0) continue;
        const float* v = visibility_.data() + node[c] * m;
        for (std::size_t l = 0; l < m; ++l) out[l] += w[c] * v[l];
    }
}


Rgb OcclusionLookup::direct(const Vec3d& x, const Vec3f& n) const {
    return query_detail::directLight(
        lights_.size(), x, n, [&](std::size_t i, const Vec3d& at, const Vec3d& nd) { return exactIrradiance(lights_[i], at, nd); },
        [&](float* v) { visibility(x, v); });
}

void OcclusionLookup::updateSharing() {
    sharing_ = shareWanted_ && shares_ && depthWeights_ == base_->depthWeighted() ? shares_ : nullptr;
}

Rgb OcclusionLookup::irradianceSharingCell(const Vec3f& xf, const Vec3d& x, const Vec3f& n) const {
    const std::size_t m = lights_.size();
    // The lights' exact irradiance first, then the blend: their arithmetic reads nothing of the
    // volume, so it runs while the corners' loads of the blend that follows are in flight
    // (the default row's volume of vdblight_bench at its random points, the other order against
    // this one alternately in the same runs: 0.91x, 0.94x). Prefetching the corners' cache lines
    // first measured no faster (the lookup without it: 1.04x, 1.01x) and was left out.
    query_detail::LightScratch scratch(m);
    const query_detail::FastExactLights& exact = *fastLights_;
    const Vec3f nf = query_detail::floatPathNormal(n);  // the shader's normal (fast_exact_lights.h)
    const bool lit = query_detail::exactLights(
        m, x, n, [&](std::size_t i, const Vec3d& at, const Vec3d& nd) { return exact.irradiance(i, at, nd, nf); }, scratch.e);

    query_detail::SharedCell cell;
    const Rgb indirect = sharing_->irradianceSharingCell(xf, n, cell);
    if (!lit) return indirect + Rgb(0, 0, 0);  // + 0, as the sum of no lights (the same bits as before)
    const std::size_t sx = cell.step[0], sy = cell.step[1] * std::size_t(grid_.nx),
                      sz = cell.step[2] * std::size_t(grid_.nx) * grid_.ny;
    const std::size_t node0 = cell.node(grid_, 0);
    const auto node = [&](int c) { return node0 + (c & 1) * sx + ((c >> 1) & 1) * sy + (c >> 2) * sz; };
    const auto values = [&](int c) { return visibility_.data() + node(c) * m; };
    if (useEdges_)  // as visibility(): the edges' ramp plus the corners' residuals
        query_detail::blendCellWithEdges(
            cell, grid_, x, m, values, [&](int c) { return edges_.data() + node(c) * m * shadow_edge::kFloatsPerLight; },
            scratch.v);
    else
        query_detail::blendCell(cell, m, values, scratch.v);
    return indirect + query_detail::visibleSum(m, scratch.e, scratch.v);
}

Rgb OcclusionLookup::irradiance(const Vec3f& x, const Vec3f& n) const {
    if (sharing_) return irradianceSharingCell(x, Vec3d(x), n);
    return base_->irradiance(x, n) + direct(Vec3d(x), n);
}

Rgb OcclusionLookup::irradianceWorld(const Vec3d& x, const Vec3f& n) const {
    // The sharing bases read x as a float (VolumeLookup::irradianceWorld); the exact direct
    // light keeps it in double, as direct() does.
    if (sharing_) return irradianceSharingCell(Vec3f(x), x, n);
    return base_->irradianceWorld(x, n) + direct(x, n);
}

}  // namespace vdblight
