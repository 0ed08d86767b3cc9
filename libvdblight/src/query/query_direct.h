// Lookups of volumes baked with `bake --direct occlusion` (direct_light.h): the stored
// (indirect) light plus, for each listed light, its exact unshadowed irradiance for the
// normal times its visibility interpolated between the nodes: trilinearly, or, when the
// volume has depth moments, with the same visibility-aware weights as the SH
// (depth_moments.h), so that a node behind a wall or inside a solid does not darken (or
// light) a point it cannot see; where the volume has shadow edges (shadow_edges.h), with
// their ramp, which keeps hard shadow edges sharp between the nodes.
//
// IrradianceQuery wraps the lookup of such a volume in an OcclusionLookup on its own, so
// `IrradianceQuery::irradiance` is the complete answer for baked and occlusion volumes. For a
// runtime volume it is the indirect light only (the documented answer); its direct light needs
// the scene (`vdblight query --scene`, runtimeDirectIrradiance in scene_lights.h).
#pragma once

#include <memory>
#include <vector>

#include "vdblight/light/direct_light.h"
#include "query/light_visibility.h"
#include "vdblight/query/query.h"

namespace vdblight {

namespace query_detail {
class SharesCell;
class FastExactLights;
}

class OcclusionLookup final : public VolumeLookup, public LightVisibility {
public:
    /// `base` answers for the volume's basis; `volume` supplies the lights and level 0's
    /// visibility channels (it must have them: DirectLightSet::hasVisibility()).
    OcclusionLookup(std::unique_ptr<VolumeLookup> base, const Volume& volume);

    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override;
    Rgb irradianceWorld(const Vec3d& x, const Vec3f& n) const override;
    Bounds bounds() const override { return base_->bounds(); }
    void shRadiance(const Vec3d& x, Rgb out[9]) const override { base_->shRadiance(x, out); }
    void irradianceVectors(const Vec3d& x, float out[54]) const override { base_->irradianceVectors(x, out); }
    void channelValues(const Vec3d& x, float* out) const override { base_->channelValues(x, out); }
    // Both the indirect part and the visibility channels are depth-weighted when the volume
    // has depth moments (depth_moments.h), unless switched off here.
    void setDepthWeights(bool on) override {
        base_->setDepthWeights(on);
        depthWeights_ = on && !depth_.empty();
        updateSharing();
    }
    bool depthWeighted() const override { return base_->depthWeighted(); }
    /// The visibility channels alone back to plain trilinear (for measurements: the SH part
    /// keeps its weights).
    void setVisibilityDepthWeights(bool on) {
        depthWeights_ = on && !depth_.empty();
        updateSharing();
    }
    bool visibilityDepthWeighted() const { return depthWeights_; }
    /// The shadow edges (shadow_edges.h) on or off, where the volume has them (on by default):
    /// off gives the visibility channels' interpolation alone (as before issue 32).
    void setShadowEdges(bool on) { useEdges_ = on && !edges_.empty(); }
    bool shadowEdges() const { return useEdges_; }

    /// Visibility of every listed light at x (between the nodes as above, x clamped to the box;
    /// located in double: what export samples).
    void visibility(const Vec3d& x, float* out) const override;
    /// The direct part alone: sum over lights of exactIrradiance * visibility(x).
    Rgb direct(const Vec3d& x, const Vec3f& n) const;
    /// True if irradiance() blends the visibility with the corners and weights of the base
    /// lookup's own cell (query/shared_cell.h: the default volume's sh:4 lookup offers them)
    /// instead of locating x again in double as visibility() does, and evaluates the polygon
    /// lights' exact irradiance in float (query/fast_exact_lights.h): the cost of one
    /// interpolation less, answers within float rounding of base + direct()'s.
    bool sharesBaseCell() const { return sharing_ != nullptr; }
    /// Off: irradiance() = base + direct() (the visibility located apart, the lights in
    /// double), as before the sharing (for comparisons: vdblight_bench, query_fast_paths_test).
    void setShareBaseCell(bool on) {
        shareWanted_ = on;
        updateSharing();
    }
    const std::vector<DirectLight>& lights() const { return lights_; }

private:
    void updateSharing();
    /// base irradiance + direct light, the visibility blended with the base's cell.
    Rgb irradianceSharingCell(const Vec3f& xf, const Vec3d& x, const Vec3f& n) const;

    std::unique_ptr<VolumeLookup> base_;
    const query_detail::SharesCell* shares_ = nullptr;   ///< base_ if it offers its cell
    const query_detail::SharesCell* sharing_ = nullptr;  ///< shares_ while both weight by depth alike
    std::shared_ptr<const query_detail::FastExactLights> fastLights_;  ///< lights_ for the sharing path
    bool shareWanted_ = true;
    std::vector<DirectLight> lights_;
    GridSpec grid_;
    std::vector<float> visibility_;  ///< node-major, lights_.size() per node
    std::vector<float> edges_;       ///< shadow edges, node-major, kFloatsPerLight per light, or empty
    std::vector<float> depth_;       ///< level 0's depth moments (depth::kFloatsPerNode per node), or empty
    bool depthWeights_ = false;
    bool useEdges_ = false;
};

}  // namespace vdblight
