// Every basis but sh2 as a Pass, on a uniform grid or on levels: Greger bins and moments
// through their own gather (bake_bins.h, same bits as before the Basis interface), any other
// registered basis (basis.h, e.g. sh:N) through the generic gather (bake_basis.h).
#include "passes.h"

#include <algorithm>

#include "pass_options.h"
#include "bake/bake_basis.h"
#include "bake/bake_bins.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/layout/layout.h"
#include "vdblight/scene/scene.h"

namespace vdblight::bake_detail {

namespace {
class BinsPass : public Pass {
public:
    std::string name() const override { return "bins"; }
    std::string description() const override {
        return "every --basis but sh2: Greger bins / moments (radiance sampled through every bin, one value "
               "per bin direction, bake_bins.h) and any other registered basis (bake_basis.h): sh:N on bilevel / "
               "adaptive layouts (on a uniform grid the point gather stores sh:N)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
    /// The rays per node and the samples per bin as the gather counted them (bins_gather.cpp).
    std::string summaryRays(const BakeSummaryInput& in) const override {
        return metaString(in.volume.meta, "rays_per_node");
    }
    std::string summaryStored(const BakeSummaryInput& in) const override;
};
}  // namespace

std::vector<PassOption> BinsPass::options() const {
    std::vector<PassOption> o = layoutOptions();
    o.push_back(raysOption("rays per node: bins and moments round it up to a multiple of the bin count, other "
                           "bases to 2 R^2 with R = round(sqrt(rays / 2)) (bake_basis.h)"));
    o.push_back(depthMomentsOption());
    o.push_back(depthRaysOption());
    return o;
}

void BinsPass::validate(const BakeRequest& request) const {
    checkLayoutOptions(request);
    Pass::validate(request);
}

std::size_t BinsPass::bytesPerNode(const BakeRequest& r) const {
    // One RGB float per channel (bin), plus OpenVDB's copy while writing.
    return 2 * makeBasis(r.basis)->floatsPerNode() * sizeof(float);
}

std::string BinsPass::untileable(const BakeRequest&) const { return ""; }

Volume BinsPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    const LevelsPlacement placement = levelsPlacement(r);
    const LevelLayout layout = placement.kind == LayoutKind::Uniform
                                   ? uniformLayout(grid)
                                   : placeLevels(grid, c.scene.positions, c.scene.indices, placement, bytesPerNode(r));
    if (!bake_detail::isBinsOrMoment(r.basis)) {  // any other basis of the registry
        const std::unique_ptr<Basis> basis = makeBasis(r.basis);
        BasisBakeOptions bo;
        bo.raysPerNode = *r.rays;
        bo.seed = c.seed;
        bo.threads = c.threads;
        bo.transport = c.transport;
        bo.only = selectTile(c, layout.levels);
        return bakeBasis(c.scene, c.tracer, layout, *basis, bo, c.interrupter, &report.stats);
    }
    const bins::BasisSpec spec = bins::parseBasisSpec(r.basis);
    BinsBakeOptions bo;
    bo.basis = spec;
    bo.samplesPerBin = std::max<uint32_t>(1, uint32_t((uint64_t(*r.rays) + spec.binCount() - 1) / spec.binCount()));
    bo.seed = c.seed;
    bo.threads = c.threads;
    bo.transport = c.transport;
    bo.only = selectTile(c, layout.levels);
    return bakeBins(c.scene, c.tracer, layout, bo, c.interrupter, &report.stats);
}

std::string BinsPass::summaryStored(const BakeSummaryInput& in) const {
    const Volume& volume = in.volume;
    if (!volume.meta.count("samples_per_bin")) return storedBasisSummary(in);  // the generic basis gather
    return "(basis " + volume.basis.kind + ", " + std::to_string(volume.basis.channelCount()) + " Vec3f grids, " +
           metaString(volume.meta, "samples_per_bin") + " samples per bin)";
}

const Pass& binsPass() {
    static const BinsPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
