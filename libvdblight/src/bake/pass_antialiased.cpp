// The anti-aliased gather as a Pass (bake_antialiased.h), with its memory formula: the
// accumulators of eq. 6 and, for the least-squares fit, its Gram row and CG vectors.
#include "passes.h"

#include "pass_options.h"
#include "bake/bake_antialiased.h"
#include "basis/sh.h"

namespace vdblight::bake_detail {

namespace {
class AntialiasedPass : public Pass {
public:
    std::string name() const override { return "antialiased"; }
    std::string description() const override {
        return "anti-aliased gather (Kontkanen-Laine eq. 6): origins over each cell, domain of interest, validity "
               "(bake_antialiased.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesShWindow() const override { return true; }
    std::string summaryRayNote(const BakeSummaryInput& in) const override {
        return " (sampling antialiased, domain " + metaString(in.volume.meta, "domain") + ")";
    }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};
}  // namespace

std::vector<PassOption> AntialiasedPass::options() const {
    return {raysOption("candidate ray origins (one ray each) per cell"),
            wordOption("domain", "all, or interior = only origins that see no back-face", "interior",
                       {"all", "interior"}, &BakeRequest::domain,
                       "--domain needs --sampling antialiased (point sampling has --invalidate-backface)"),
            wordOption("fit",
                       "projection = eq. 6, or least-squares = fit the node values to the samples over the domain "
                       "(docs/methods.md)",
                       "projection",
                       {"projection", "least-squares"}, &BakeRequest::fit, "--fit needs --sampling antialiased"),
            depthMomentsOption(), depthRaysOption(), shWindowOption()};
}

void AntialiasedPass::validate(const BakeRequest& request) const { Pass::validate(request); }

std::size_t AntialiasedPass::bytesPerNode(const BakeRequest& r) const {
    // Float coefficients plus OpenVDB's copy, and double accumulators per node (coefficients
    // + 2 weights). The least-squares fit adds its 27-entry Gram row, and its solve a prior
    // and six CG vectors of all 27 values per node (node_least_squares.h).
    const std::size_t values = sh::kCoeffs * 3;
    const std::size_t lsq = r.fit == "least-squares" ? values + 7 * values : 0;
    return 2 * values * sizeof(float) + (values + 2 + lsq) * sizeof(double);
}

std::string AntialiasedPass::untileable(const BakeRequest&) const {
    return "--sampling antialiased cannot be tiled (cells share nodes across tile borders, dilation crosses them)";
}

Volume AntialiasedPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    AntialiasedOptions aa;
    aa.raysPerCell = *r.rays;
    aa.seed = c.seed;
    aa.threads = c.threads;
    aa.transport = c.transport;
    aa.domain = r.domain == "all" ? DomainMode::All : DomainMode::Interior;
    aa.fit = r.fit == "least-squares" ? NodeFit::LeastSquares : NodeFit::Projection;
    return bakeShAntialiased(c.scene, c.tracer, grid, aa, c.interrupter, &report.stats);
}

const Pass& antialiasedPass() {
    static const AntialiasedPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
