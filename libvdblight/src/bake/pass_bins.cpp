// Greger bins and moments as a Pass (bake_bins.h), on a uniform grid or on levels.
#include "passes.h"

#include <algorithm>

#include "pass_options.h"
#include "vdblight/bake_bins.h"
#include "vdblight/bins.h"
#include "vdblight/layout_levels.h"
#include "vdblight/scene.h"

namespace vdblight::bake_detail {

namespace {
class BinsPass : public Pass {
public:
    std::string name() const override { return "bins"; }
    std::string description() const override {
        return "Greger bins / moments: radiance sampled through every bin, one value per bin direction "
               "(bake_bins.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};
}  // namespace

std::vector<PassOption> BinsPass::options() const {
    std::vector<PassOption> o = layoutOptions();
    o.push_back(raysOption("rays per node, rounded up to a multiple of the bin count"));
    o.push_back(depthMomentsOption());
    o.push_back(depthRaysOption());
    return o;
}

void BinsPass::validate(const BakeRequest& request) const {
    checkLayoutOptions(request);
    Pass::validate(request);
}

std::size_t BinsPass::bytesPerNode(const BakeRequest& r) const {
    // One RGB float per bin, plus OpenVDB's copy while writing.
    return 2 * std::size_t(bins::parseBasisSpec(r.basis).binCount()) * 3 * sizeof(float);
}

std::string BinsPass::untileable(const BakeRequest&) const { return ""; }

Volume BinsPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    const bins::BasisSpec spec = bins::parseBasisSpec(r.basis);
    BinsBakeOptions bo;
    bo.basis = spec;
    bo.samplesPerBin = std::max<uint32_t>(1, uint32_t((uint64_t(*r.rays) + spec.binCount() - 1) / spec.binCount()));
    bo.seed = c.seed;
    bo.threads = c.threads;
    bo.transport = c.transport;
    const LevelsPlacement placement = levelsPlacement(r);
    const LevelLayout layout = placement.kind == LayoutKind::Uniform
                                   ? uniformLayout(grid)
                                   : placeLevels(grid, c.scene.positions, c.scene.indices, placement, bytesPerNode(r));
    bo.only = selectTile(c, layout.levels);
    return bakeBins(c.scene, c.tracer, layout, bo, c.interrupter, &report.stats);
}

const Pass& binsPass() {
    static const BinsPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
