// The point gather on bilevel / adaptive levels as a Pass (bake_levels.h), with solid
// culling (solid_cull.h). The layout options (refine, levels, refine distance) are shared
// with the bins pass.
#include "passes.h"

#include <sstream>

#include "pass_options.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "basis/sh.h"
#include "vdblight/scene/scene.h"

namespace vdblight::bake_detail {

namespace {
class LevelsPass : public Pass {
public:
    std::string name() const override { return "levels"; }
    std::string description() const override {
        return "point gather on bilevel / adaptive levels (Greger et al.), seams from the coarser level, optional "
               "solid culling (bake_levels.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesShWindow() const override { return true; }
    std::string summaryLead(const BakeSummaryInput& in) const override;
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};
}  // namespace

std::vector<PassOption> layoutOptions() {
    return {numberOption("refine", "bilevel/adaptive: split refined cells K x K x K", "3", 2, kNoMax, &BakeRequest::refine,
                         "--refine needs --layout bilevel or adaptive"),
            numberOption("levels", "adaptive: number of levels including the first", "3", 1, 16, &BakeRequest::levels,
                         "--levels needs --layout adaptive", "at least 1"),
            numberOption("refine-distance",
                         "bilevel/adaptive: refine every cell within this distance (scene units, max-norm) of a "
                         "triangle, not only cells that contain one (0 = Greger's rule)",
                         "0", 0, kNoMax, &BakeRequest::refineDistance, "--refine-distance needs --layout bilevel or adaptive",
                         "a finite distance >= 0")};
}

void checkLayoutOptions(const BakeRequest& r) {
    if (r.levels && *r.levels > 16)
        throw ValueError("--levels " + std::to_string(*r.levels) +
                         " is absurd (each level multiplies the resolution by --refine); use at most 16");
}

std::vector<PassOption> LevelsPass::options() const {
    std::vector<PassOption> o = layoutOptions();
    o.push_back(raysOption("ray directions per node"));
    o.push_back(flagOption("cull-solids",
                           "bilevel/adaptive with sh2: leave out nodes whose every cell lies inside a closed solid "
                           "(docs/format.md, Levels); queries there return 0",
                           &BakeRequest::cullSolids, "--cull-solids needs --layout bilevel or adaptive and --basis sh2"));
    o.push_back(depthMomentsOption());
    o.push_back(depthRaysOption());
    o.push_back(shWindowOption());
    return o;
}

void LevelsPass::validate(const BakeRequest& request) const {
    checkLayoutOptions(request);
    Pass::validate(request);
}

std::size_t LevelsPass::bytesPerNode(const BakeRequest&) const { return 2 * sh::kCoeffs * 3 * sizeof(float); }

std::string LevelsPass::untileable(const BakeRequest& r) const {
    if (r.shWindow) return "--sh-window cannot be tiled yet (the window would have to follow the seams at merge)";
    return "";
}

Volume LevelsPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    LevelsPlacement placement = levelsPlacement(r);
    placement.keepFinestGeometry = r.cullSolids;
    LevelLayout layout = placeLevels(grid, c.scene.positions, c.scene.indices, placement, bytesPerNode(r));
    if (r.cullSolids) {
        SolidCullStats cull;
        cullSolidNodes(layout, c.tracer, SolidCullOptions(), &cull);
        report.cull = cull;
    }
    GatherOptions options = gatherOptions(c, r);
    options.only = selectTile(c, layout.levels);
    Volume volume = bakeShGatherLevels(c.scene, c.tracer, layout, options, c.interrupter, &report.stats);
    report.layout = LayoutSummary{int(volume.levels.size()), layout.refine, layout.totalNodes(),
                                  layout.denseEquivalentNodes(), layout.culledNodes};
    return volume;
}

/// The nodes culled inside solids and what the levels saved against a dense grid.
std::string LevelsPass::summaryLead(const BakeSummaryInput& in) const {
    const BakeReport& report = in.report;
    const BakeRequest& r = report.resolved;
    std::ostringstream out;
    if (report.cull)
        out << "Solid culling: " << report.cull->nodesCulled << " of " << report.cull->nodesBefore
            << " nodes left out (inside closed solids: " << report.cull->solidRegions << " of " << report.cull->regions
            << " regions of geometry-free cells, " << report.cull->solidCells << " solid cells).\n";
    if (report.layout) {
        const LayoutSummary& l = *report.layout;
        out << "Layout " << r.layout << ": " << l.levels << " levels refined by " << l.refine << ", " << l.nodes
            << " nodes (" << report.stats.seamNodes << " seam nodes set from the coarser level) vs "
            << l.denseEquivalentNodes << " in a dense grid at the finest spacing ("
            << 100.0 * (1.0 - double(l.nodes) / l.denseEquivalentNodes) << " % saved"
            << (r.cullSolids ? ", " + std::to_string(l.culledNodes) + " of them culled inside solids" : "") << ").\n";
    }
    return out.str();
}

const Pass& levelsPass() {
    static const LevelsPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
