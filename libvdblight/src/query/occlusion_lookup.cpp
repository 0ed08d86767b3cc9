// OcclusionLookup (query_direct.h): stored light + exact direct light x interpolated visibility.

#include "query/query_direct.h"

#include "depth_weights.h"
#include "basis/shadow_edges.h"

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
}

void OcclusionLookup::visibility(const Vec3d& x, float* out) const {
    const std::size_t m = lights_.size();
    int base[3], dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    double f[3];
    for (int a = 0; a < 3; ++a) {
        double u = (x[a] - grid_.origin[a]) / grid_.spacing;
        if (!(u > 0)) u = 0;  // NaN and below: the first node
        u = std::min(u, double(dims[a] - 1));
        base[a] = std::min(int(u), std::max(0, dims[a] - 2));
        f[a] = dims[a] > 1 ? u - base[a] : 0.0;
    }
    for (std::size_t i = 0; i < m; ++i) out[i] = 0.0f;
    std::size_t node[8];
    float w[8];
    const float* depth[8];
    for (int c = 0; c < 8; ++c) {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        w[c] = float((di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]));
        const int i = std::min(base[0] + di, dims[0] - 1), j = std::min(base[1] + dj, dims[1] - 1),
                  k = std::min(base[2] + dk, dims[2] - 1);
        node[c] = grid_.index(i, j, k);
        if (depthWeights_) depth[c] = depth_.data() + node[c] * depth::kFloatsPerNode;
    }
    // The SH lookups' weights (depth_weights.h): corners the point cannot see drop out.
    if (depthWeights_) query_detail::weightByDepth(w, depth, float(f[0]), float(f[1]), float(f[2]));
    if (useEdges_) {  // shadow_edges.h: the edges' ramp plus the corners' residuals
        for (std::size_t l = 0; l < m; ++l) {
            float v[8], d[8], width[8];
            for (int c = 0; c < 8; ++c) {
                v[c] = visibility_[node[c] * m + l];
                d[c] = edges_[(node[c] * m + l) * shadow_edge::kFloatsPerLight];
                width[c] = edges_[(node[c] * m + l) * shadow_edge::kFloatsPerLight + 1];
            }
            out[l] = shadow_edge::visibility(w, v, d, width);
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
    // Each light's exact irradiance first: where the normal faces away from every light (half
    // of all normals, for a light on the ceiling) the visibility is not needed at all. Adding a
    // light's zero would not change the sum's bits, so skipping it gives the same answer.
    float vis[16];
    Rgb exact[16];
    std::vector<float> manyVis;
    std::vector<Rgb> manyExact;
    float* v = vis;
    Rgb* e = exact;
    if (lights_.size() > 16) {
        manyVis.resize(lights_.size());
        manyExact.resize(lights_.size());
        v = manyVis.data();
        e = manyExact.data();
    }
    const Vec3d nd = normalize(Vec3d(n));
    bool any = false;
    for (std::size_t i = 0; i < lights_.size(); ++i) {
        e[i] = exactIrradiance(lights_[i], x, nd);
        any = any || e[i] != Rgb(0, 0, 0);
    }
    Rgb sum(0, 0, 0);
    if (!any) return sum;
    visibility(x, v);
    for (std::size_t i = 0; i < lights_.size(); ++i)
        if (v[i] > 0) sum += e[i] * v[i];
    return sum;
}

Rgb OcclusionLookup::irradiance(const Vec3f& x, const Vec3f& n) const {
    return base_->irradiance(x, n) + direct(Vec3d(x), n);
}

Rgb OcclusionLookup::irradianceWorld(const Vec3d& x, const Vec3f& n) const {
    return base_->irradianceWorld(x, n) + direct(x, n);
}

}  // namespace vdblight
