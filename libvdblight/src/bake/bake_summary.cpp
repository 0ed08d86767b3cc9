// The summary `vdblight bake` prints (bakeSummary, bake_volume.h), written by the pass that
// baked (Pass::summary): the base here is the node gathers' summary, whose parts a pass
// overrides (summaryLead, summaryRays, summaryRayNote, summaryStored) in its own file; the
// photon pass writes its own (pass_photons.cpp).
#include <cmath>
#include <sstream>

#include "passes.h"
#include "vdblight/bake/bake.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/volume/volume.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

namespace {
/// The bake's own noise estimate, honestly labelled: per node the relative standard error of
/// its mean irradiance from the sample variance, over the nodes that lookups in free space read
/// (error_summary.h); what it does not measure is said, and the nodes left out are counted.
void writeNoiseSummary(std::ostream& out, const BakeStats& stats, const Volume& volume, const GridSpec& grid) {
    auto percent = [](double e) { return std::to_string(int(std::lround(e * 1000.0)) / 10) + "." +
                                         std::to_string(int(std::lround(e * 1000.0)) % 10) + " %"; };
    const std::vector<float>& err = stats.estimatedError;
    std::size_t worst = err.size();  // the largest error a free-space lookup reads
    for (std::size_t n = 0; n < err.size(); ++n)
        if (err[n] >= 0.0f && (worst == err.size() || err[n] > err[worst])) worst = n;
    const std::size_t inside = nodesInsideSolids(err);
    if (worst == err.size()) {
        out << "Noise per node: every one of the " << inside << " nodes lies inside solids.\n";
        return;
    }
    out << "Noise per node (relative standard error of its irradiance, from the sample variance"
        << (inside ? ", over the nodes that lookups in free space read" : "") << "): p50 "
        << percent(stats.errorQuantile(0.5)) << ", p95 " << percent(stats.errorQuantile(0.95)) << ", max "
        << percent(err[worst]) << " at node " << worst % grid.nx << "," << (worst / grid.nx) % grid.ny << ","
        << worst / (std::size_t(grid.nx) * grid.ny);
    if (volume.meta.count("nodes_at_max_rays"))
        out << "; " << metaString(volume.meta, "nodes_at_max_rays") << " nodes stopped at the ray cap above the target";
    out << ". Not included: SH truncation, interpolation between nodes.\n";
    if (inside)
        out << inside << " nodes inside solids (most of their rays hit back faces), not read by free-space "
                         "lookups (the depth weights keep them out).\n";
}

/// The lights kept out of the basis (bake_direct.h), once the last stage is baked.
void writeDirectLight(std::ostream& out, const BakeReport& report) {
    const DirectPlan& plan = report.direct;
    if (plan.mode == DirectMode::Baked || !report.lastStage) return;
    out << "Direct light (" << directModeName(plan.mode) << "): " << plan.lights.size() << " of "
        << plan.sceneLightCount << " lights kept out of the SH";
    if (plan.mode == DirectMode::Occlusion) {
        out << ", with visibility channels; measured share of the direct light:";
        for (double share : plan.contribution) out << ' ' << int(100.0 * share + 0.5) << " %";
    }
    out << ".\n";
}

/// One tile (or one stage of a tile) of a node gather, and what to do with it next.
void writeTile(std::ostream& out, const BakeSummaryInput& in) {
    const BakeRequest& r = in.report.resolved;
    const int stage = r.stage.value_or(-1);
    out << "Baked tile " << *in.request.tile << " of " << *in.request.tiles
        << (stage >= 0 ? " (stage " + std::to_string(stage) + " of 0.." + std::to_string(*r.probePasses) + ")" : "")
        << ": " << in.report.tileNodes << " of " << in.report.stats.nodes << " nodes, "
        << formatCount(double(in.report.stats.rays.total())) << " rays in " << formatSeconds(in.report.stats.seconds)
        << ". Wrote " << in.output
        << (in.report.lastStage ? " (merge the tiles with 'vdblight merge')"
                                : " (merge this stage's tiles with 'vdblight merge', then bake stage " +
                                      std::to_string(stage + 1) + " with --stage-input MERGED.vdb)")
        << ".\n";
}
}  // namespace

std::string Pass::summaryRays(const BakeSummaryInput& in) const { return std::to_string(*in.report.resolved.rays); }

namespace bake_detail {
std::string storedBasisSummary(const BakeSummaryInput& in) {
    return "(basis " + in.volume.basis.kind + ": " + makeBasis(in.report.resolved.basis)->describe() + ", " +
           std::to_string(in.volume.basis.channelCount()) + " Vec3f grids)";
}
}  // namespace bake_detail

std::string Pass::summaryStored(const BakeSummaryInput& in) const {
    const Volume& volume = in.volume;
    // A registry basis (basis.h) of the generic or the point gather.
    if (!volume.basis.isSh2()) return bake_detail::storedBasisSummary(in);
    return std::string("(SH order 2 radiance, 9 Vec3f grids") + (volume.levels[0].validity.empty() ? "" : " + validity") +
           ")";
}

std::string Pass::summary(const BakeSummaryInput& in) const {
    const BakeReport& report = in.report;
    const BakeRequest& r = report.resolved;
    const GridSpec& grid = report.grid;
    const LevelsBakeStats& stats = report.stats;
    const Volume& volume = in.volume;
    const Scene& scene = in.scene;
    std::ostringstream out;
    out << summaryLead(in);
    writeDirectLight(out, report);
    if (r.tiles) {
        writeTile(out, in);
        return out.str();
    }
    if (*r.depthMoments)
        out << "Depth moments: " << (report.depth && report.depth->rays
                                         ? formatCount(double(report.depth->rays)) + " first-hit rays in " +
                                               formatSeconds(report.depth->seconds)
                                         : std::string("from the gather's own first hits"))
            << " (" << depth::kBytesPerNode << " B per node at 8 bits).\n";
    out << "Baked " << stats.nodes << " nodes (" << (volume.levels.size() > 1 ? "level 0: " : "") << grid.nx << " x "
        << grid.ny << " x " << grid.nz << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' ("
        << scene.triangleCount() << " triangles";
    out << "; " << in.sceneSource;
    if (scene.stats.degenerateTrianglesSkipped)
        out << ", " << scene.stats.degenerateTrianglesSkipped << " degenerate skipped";
    const int bounces = r.transport.maxBounces;
    out << ") with " << summaryRays(in) << " rays per node"
        << (*r.probePasses > 0 ? " (+ " + std::to_string(*r.probePasses) + " probe-to-probe pass" +
                                     (*r.probePasses > 1 ? "es" : "") + ")"
                               : std::string())
        << " and "
        << (bounces >= kSafetyBounces ? std::string("all bounces (Russian roulette)")
                                      : "up to " + std::to_string(bounces) + " bounces")
        << ": " << formatCount(double(stats.rays.total())) << " rays (" << formatCount(double(stats.rays.intersect))
        << " closest-hit, " << formatCount(double(stats.rays.occluded)) << " shadow) in "
        << formatSeconds(stats.seconds) << ", " << formatCount(stats.raysPerSecond()) << " rays/s on "
        << std::get<int64_t>(volume.meta.at("threads")) << " threads";
    out << summaryRayNote(in);
    if (volume.meta.count("nodes_dilated"))
        out << "; " << metaString(volume.meta, "nodes_dilated") << " nodes filled by dilation";
    out << ". Wrote " << in.output << " " << summaryStored(in) << ".\n";
    if (!stats.estimatedError.empty()) writeNoiseSummary(out, stats, volume, grid);
    return out.str();
}

std::string bakeSummary(const BakeSummaryInput& in) {
    if (in.report.skipped)
        return "Tile " + std::to_string(*in.request.tile) + " of " + std::to_string(*in.request.tiles) +
               " is already baked with the same scene and parameters (" + in.output + "): skipped.\n";
    return in.report.pass->summary(in);
}

}  // namespace vdblight
