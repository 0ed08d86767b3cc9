// OcclusionLookup (occlusion_lookup.cpp) on a streamed volume: the stored light plus, for each
// listed light, its exact direct light times its visibility interpolated from level 0's nodes,
// with OcclusionLookup's locate, weights and sums, the nodes' visibility and depth read through
// StreamedVolume, so that the answers are the same bits as the in-memory query's.
#include <algorithm>
#include <vector>

#include "depth_weights.h"
#include "direct_sum.h"
#include "fast_exact_lights.h"
#include "lattice_locate.h"
#include "shared_cell.h"
#include "stream_lookups.h"
#include "query/light_visibility.h"
#include "basis/shadow_edges.h"

namespace vdblight::query_detail {

namespace {

class StreamingOcclusionLookup final : public VolumeLookup, public LightVisibility {
public:
    StreamingOcclusionLookup(std::unique_ptr<VolumeLookup> base, std::shared_ptr<const StreamedVolume> volume)
        : base_(std::move(base)), volume_(std::move(volume)), lights_(volume_->header().direct.lights),
          grid_(volume_->header().levels.at(0).grid) {
        if (!volume_->hasVisibility()) throw FormatError("occlusion lookup: the volume has no light visibility channels");
        hasDepth_ = depthWeights_ = volume_->hasDepth();
        edges_ = volume_->hasShadowEdges();
        const auto* shares = dynamic_cast<const SharesCell*>(base_.get());
        if (shares && shares->sharesCell()) shares_ = shares;
        if (shares_) fastLights_ = std::make_unique<FastExactLights>(lights_);
        updateSharing();
    }

    // As OcclusionLookup::irradiance and irradianceWorld: with the base's cell where it offers it.
    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override {
        if (sharing_) return irradianceSharingCell(x, Vec3d(x), n);
        return base_->irradiance(x, n) + direct(Vec3d(x), n);
    }
    Rgb irradianceWorld(const Vec3d& x, const Vec3f& n) const override {
        if (sharing_) return irradianceSharingCell(Vec3f(x), x, n);
        return base_->irradianceWorld(x, n) + direct(x, n);
    }
    Bounds bounds() const override { return base_->bounds(); }
    void shRadiance(const Vec3d& x, Rgb out[9]) const override { base_->shRadiance(x, out); }
    void channelValues(const Vec3d& x, float* out) const override { base_->channelValues(x, out); }
    void setDepthWeights(bool on) override {
        base_->setDepthWeights(on);
        depthWeights_ = on && hasDepth_;
        updateSharing();
    }
    bool depthWeighted() const override { return base_->depthWeighted(); }

    // As OcclusionLookup::visibility, operation for operation.
    void visibility(const Vec3d& x, float* out) const override {
        const std::size_t m = lights_.size();
        int base[3];
        const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
        double f[3];
        visibilityCell(grid_, x, base, f);
        for (std::size_t i = 0; i < m; ++i) out[i] = 0.0f;
        std::vector<float> v(8 * m);
        float w[8];
        float d[8][depth::kFloatsPerNode];
        const float* depth[8];
        for (int c = 0; c < 8; ++c) {
            const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
            w[c] = float((di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]));
            const int i = std::min(base[0] + di, dims[0] - 1), j = std::min(base[1] + dj, dims[1] - 1),
                      k = std::min(base[2] + dk, dims[2] - 1);
            volume_->readVisibility(i, j, k, v.data() + c * m);
            if (depthWeights_) volume_->readDepth(0, i, j, k, d[c]);
            depth[c] = d[c];
        }
        if (depthWeights_) weightByDepth(w, depth, float(f[0]), float(f[1]), float(f[2]));
        if (edges_) {  // as OcclusionLookup: the edges' ramp plus the corners' residuals
            std::vector<float> e(8 * m * shadow_edge::kFloatsPerLight);
            int index[8][3];
            for (int c = 0; c < 8; ++c) {
                const int i = std::min(base[0] + (c & 1), dims[0] - 1), j = std::min(base[1] + ((c >> 1) & 1), dims[1] - 1),
                          k = std::min(base[2] + ((c >> 2) & 1), dims[2] - 1);
                index[c][0] = i, index[c][1] = j, index[c][2] = k;
                volume_->readShadowEdges(i, j, k, e.data() + c * m * shadow_edge::kFloatsPerLight);
            }
            for (std::size_t l = 0; l < m; ++l) {
                float vis[8];
                const float* edge[8];
                for (int c = 0; c < 8; ++c) {
                    vis[c] = v[c * m + l];
                    edge[c] = e.data() + (c * m + l) * shadow_edge::kFloatsPerLight;
                }
                out[l] = edgeVisibility(grid_, x, w, vis, edge, index);
            }
            return;
        }
        for (int c = 0; c < 8; ++c) {
            if (w[c] == 0) continue;
            for (std::size_t l = 0; l < m; ++l) out[l] += w[c] * v[c * m + l];
        }
    }

private:
    void updateSharing() { sharing_ = shares_ && depthWeights_ == base_->depthWeighted() ? shares_ : nullptr; }

    // As OcclusionLookup::irradianceSharingCell.
    Rgb irradianceSharingCell(const Vec3f& xf, const Vec3d& x, const Vec3f& n) const {
        SharedCell cell;
        const Rgb indirect = sharing_->irradianceSharingCell(xf, n, cell);
        const std::size_t m = lights_.size();
        const Vec3f nf = floatPathNormal(n);
        return indirect + directLight(
                              m, x, n, [&](std::size_t i, const Vec3d& at, const Vec3d& nd) { return fastLights_->irradiance(i, at, nd, nf); },
                              [&](float* v) {
                                  std::vector<float> node(8 * m);
                                  const auto values = [&](int c) {
                                      volume_->readVisibility(cell.i(c), cell.j(c), cell.k(c), node.data() + c * m);
                                      return node.data() + c * m;
                                  };
                                  if (!edges_) return blendCell(cell, m, values, v);
                                  // As visibility(): the edges' ramp plus the corners' residuals.
                                  std::vector<float> edge(8 * m * shadow_edge::kFloatsPerLight);
                                  blendCellWithEdges(cell, grid_, x, m, values, [&](int c) {
                                      float* e = edge.data() + c * m * shadow_edge::kFloatsPerLight;
                                      volume_->readShadowEdges(cell.i(c), cell.j(c), cell.k(c), e);
                                      return e;
                                  }, v);
                              });
    }

    // As OcclusionLookup::direct.
    Rgb direct(const Vec3d& x, const Vec3f& n) const {
        std::vector<float> v(lights_.size());
        visibility(x, v.data());
        Rgb sum(0, 0, 0);
        const Vec3d nd = normalize(Vec3d(n));
        for (std::size_t i = 0; i < lights_.size(); ++i)
            if (v[i] > 0) sum += exactIrradiance(lights_[i], x, nd) * v[i];
        return sum;
    }

    std::unique_ptr<VolumeLookup> base_;
    std::shared_ptr<const StreamedVolume> volume_;
    std::vector<DirectLight> lights_;
    GridSpec grid_;  ///< level 0's, in world coordinates
    bool hasDepth_ = false, depthWeights_ = false, edges_ = false;
    const SharesCell* shares_ = nullptr;   ///< base_ if it offers its cell
    const SharesCell* sharing_ = nullptr;  ///< shares_ while both weight by depth alike
    std::unique_ptr<FastExactLights> fastLights_;  ///< lights_ for the sharing path
};

}  // namespace

std::unique_ptr<VolumeLookup> streamingOcclusionLookup(std::unique_ptr<VolumeLookup> base,
                                                       std::shared_ptr<const StreamedVolume> volume) {
    return std::make_unique<StreamingOcclusionLookup>(std::move(base), std::move(volume));
}

}  // namespace vdblight::query_detail
