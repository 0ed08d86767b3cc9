// The error-targeted point gather as a Pass (bake_adaptive.h).
#include "passes.h"

#include <sstream>

#include "pass_options.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "basis/sh.h"

namespace vdblight::bake_detail {

namespace {
class AdaptivePass : public Pass {
public:
    std::string name() const override { return "adaptive"; }
    std::string description() const override {
        return "error-targeted point gather: each node sampled until its irradiance reaches a relative standard "
               "error (bake_adaptive.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesDirectLight() const override { return true; }
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
    std::string summaryLead(const BakeSummaryInput& in) const override;
    std::string summaryRays(const BakeSummaryInput&) const override { return "error-targeted"; }
};
}  // namespace

namespace {
const char* const kNeedsTarget =
    "--max-rays and --min-rays need an error-targeted bake (--target-error)";
}

std::vector<PassOption> AdaptivePass::options() const {
    PassOption target = numberOption("target-error",
                                     "sample each node in doubling rounds until the relative standard error of its "
                                     "mean irradiance is below this (e.g. 0.02), up to --max-rays",
                                     "none: every preset has a fixed --rays budget", 0, 1, &BakeRequest::targetError,
                                     "--target-error works with --method gather, --sampling point, --layout uniform "
                                     "and --basis sh2 only");
    target.minExclusive = true;
    return {target,
            numberOption("min-rays", "error-targeted bakes: rays of the first round", std::to_string(kTargetMinRays), 2, double(1u << 30), &BakeRequest::minRays,
                         kNeedsTarget),
            numberOption("max-rays", "error-targeted bakes: most rays a node may take", std::to_string(kTargetMaxRays), 2, double(1u << 30), &BakeRequest::maxRays,
                         kNeedsTarget),
            probePassesOption(), depthMomentsOption(), depthRaysOption(), shWindowOption()};
}

void AdaptivePass::validate(const BakeRequest& request) const {
    const BakeRequest r = resolveBakeRequest(request);
    if (r.method != "gather" || r.sampling != "point" || r.invalidateBackface ||
        parseLayoutKind(r.layout) != LayoutKind::Uniform || !isSh2(r.basis))
        throw ValueError("--target-error works with --method gather, --sampling point, --layout uniform and --basis "
                         "sh2 only");
    if (!(*r.targetError > 0 && *r.targetError <= 1))
        throw ValueError("--target-error must be in (0, 1], got " + std::to_string(*r.targetError));
    if (*r.minRays < 2 || *r.maxRays < *r.minRays)
        throw ValueError("--min-rays must be at least 2 and --max-rays at least --min-rays, got " +
                         std::to_string(*r.minRays) + " and " + std::to_string(*r.maxRays));
    Pass::validate(request);
}

std::size_t AdaptivePass::bytesPerNode(const BakeRequest&) const { return 2 * sh::kCoeffs * 3 * sizeof(float); }

std::string AdaptivePass::untileable(const BakeRequest& r) const { return pointGatherUntileable(r); }

Volume AdaptivePass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    AdaptiveOptions a;
    a.targetError = *r.targetError;
    a.minRays = *r.minRays;
    a.maxRays = *r.maxRays;
    a.seed = c.seed;
    a.threads = c.threads;
    a.transport = c.transport;
    a.probePasses = *r.probePasses;
    LevelTopology shape;
    shape.grid = grid;
    a.only = selectTile(c, {shape});
    a.stage = c.stage;
    a.stageInput = c.stageInput;
    AdaptiveStats stats;
    Volume v = bakeShGatherAdaptive(c.scene, c.tracer, grid, a, c.interrupter, &stats);
    static_cast<BakeStats&>(report.stats) = stats;
    report.adaptive = std::move(stats);
    return v;
}

/// The error reached against the target, and the rays that saved (a tile's errors are the
/// merge's to summarise).
std::string AdaptivePass::summaryLead(const BakeSummaryInput& in) const {
    const BakeReport& report = in.report;
    const BakeRequest& r = report.resolved;
    if (!report.adaptive || report.adaptive->estimatedError.empty() || r.tiles) return {};
    const AdaptiveStats& as = *report.adaptive;
    const uint32_t maxRays = *r.maxRays;
    std::ostringstream out;
    out << "Error-targeted: relative standard error of mean irradiance p50 " << as.errorQuantile(0.5) << ", p95 "
        << as.errorQuantile(0.95) << ", max " << as.errorQuantile(1.0) << " (target " << *r.targetError << ", "
        << as.nodesAtMax << " nodes stopped at --max-rays " << maxRays << "); " << formatCount(double(as.samples))
        << " gathered rays, " << formatCount(double(as.samples) / double(as.nodes)) << " per node, "
        << formatCount(double(uint64_t(maxRays) * as.nodes - as.samples)) << " ("
        << int(100.0 * (1.0 - double(as.samples) / (double(maxRays) * as.nodes))) << " %) saved against " << maxRays
        << " rays on every node.\n";
    return out.str();
}

const Pass& adaptivePass() {
    static const AdaptivePass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
