// The photon pass as a Pass (photons.h), with its memory formula and the compact form.
#include "passes.h"

#include <sstream>

#include "pass_options.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/scene/scene.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/bake/each_pass.h"
#include "volume/volume_compact.h"

namespace vdblight::bake_detail {

namespace {
class PhotonsPass : public Pass {
public:
    std::string name() const override { return "photons"; }
    std::string description() const override {
        return "photon pass (Pacanowski et al.): irradiance vectors from photons crossing the node lattice "
               "(photons.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
    void finish(Volume& volume, WriteOptions& write, const BakeRequest& request) const override;
    std::string summary(const BakeSummaryInput& in) const override;
};
}  // namespace

std::vector<PassOption> PhotonsPass::options() const {
    PassOption photons = describeOption(
        "photons", "photons emitted in total",
        presetValues([](const BakeRequest& r) { return std::to_string(*r.photons); }, "photons"), 1, double(kMaxPhotons));
    photons.number = [](const BakeRequest& r) -> std::optional<double> {
        return r.photons ? std::optional<double>(double(*r.photons)) : std::nullopt;
    };
    photons.setNumber = [](BakeRequest& r, double v) { r.photons = uint64_t(v); };
    photons.setText = [](BakeRequest& r, const std::string& text) {
        r.photons = parseOptionValue<uint64_t>("photons", text);
    };
    return {photons, flagOption("compact",
                                "write the compact colour + direction form (Pacanowski et al. 4.2; 12 half-float "
                                "grids) instead of the 18 full grids",
                                &BakeRequest::compact, "--compact applies to --method photons only"),
            depthMomentsOption(), depthRaysOption()};
}

void PhotonsPass::validate(const BakeRequest& request) const {
    try {
        if (request.photons) checkPhotonCount(*request.photons);  // its message says how long too many would take
    } catch (const ValueError& e) {
        throw ValueError(std::string("--photons: ") + e.what());
    }
    Pass::validate(request);
}

std::size_t PhotonsPass::bytesPerNode(const BakeRequest& r) const {
    // 54 values per node: 128-bit fixed-point totals (photon_sums.h), a float buffer per
    // thread, the volume and OpenVDB's copy; a tile writes its totals as 128-bit integer
    // grids instead of the volume.
    return 54 * (16 + 4 * 4) + (r.tiles ? 54 * 16 : 0);
}

std::string PhotonsPass::untileable(const BakeRequest&) const {
    // A tile traces a run of the photon batches (photon_sums.h, tiles.h) over every node, and
    // bakes the depth moments of a run of the nodes (photonTileDepthNodes): always tileable.
    return "";
}

Volume PhotonsPass::run(const BakeContext& c, const BakeRequest& r, const GridSpec& grid, BakeReport& report) const {
    PhotonOptions options;
    options.photons = *r.photons;  // resolveBakeRequest sets the default
    options.seed = c.seed;
    options.threads = c.threads;
    options.transport = c.transport;
    PhotonStats stats;
    Volume volume;
    if (r.tiles) {  // the sums of the tile's batches, for bakeToFile's writePhotonTile
        options.tiles = *r.tiles;
        options.tile = *r.tile;
        report.photonSums = std::make_shared<PhotonSums>(
            tracePhotons(c.scene, c.tracer, grid, options, c.interrupter, &stats, &volume.meta));
        volume.basis = iv::basis();
        volume.levels.resize(1);
        volume.levels[0].grid = grid;
    } else {
        volume = bakePhotons(c.scene, c.tracer, grid, options, c.interrupter, &stats);
    }
    report.stats.nodes = grid.nodeCount();
    report.stats.rays = stats.rays;
    report.stats.seconds = stats.seconds;
    report.photons = stats;
    return volume;
}

void PhotonsPass::finish(Volume& volume, WriteOptions& write, const BakeRequest& r) const {
    if (!r.compact || r.tiles) return;  // a tile holds sums: the merge makes the compact form
    volume = iv::compact(volume);
    write.halfFloat = true;
}

/// The photons traced and the file written; a tile: its batches, summed over the whole grid.
std::string PhotonsPass::summary(const BakeSummaryInput& in) const {
    const BakeReport& report = in.report;
    const PhotonStats& stats = *report.photons;
    std::ostringstream out;
    if (report.photonSums) {
        const PhotonSums& sums = *report.photonSums;
        out << "Baked tile " << *in.request.tile << " of " << *in.request.tiles << ": photon batches " << sums.firstBatch
            << ".." << sums.endBatch - 1 << " of " << sums.batches << " (" << formatCount(double(stats.photons)) << " of "
            << formatCount(double(report.resolved.photons.value_or(0))) << " photons), "
            << formatCount(double(stats.rays.total())) << " rays in " << formatSeconds(stats.seconds)
            << (report.depth ? "; depth moments of its share of the nodes, " + formatCount(double(report.depth->rays)) +
                                   " first-hit rays in " + formatSeconds(report.depth->seconds)
                             : std::string())
            << ". Wrote " << in.output
            << " (the whole grid's sums of these batches; merge the tiles with 'vdblight merge').\n";
        return out.str();
    }
    const GridSpec& grid = report.grid;
    const Scene& scene = in.scene;
    out << "Baked " << grid.nodeCount() << " nodes (" << grid.nx << " x " << grid.ny << " x " << grid.nz
        << ", spacing " << grid.spacing << ") of scene '" << scene.name << "' (" << scene.triangleCount()
        << " triangles; " << in.sceneSource << ") with " << formatCount(double(stats.photons)) << " photons: "
        << formatCount(double(stats.segments)) << " segments, " << formatCount(double(stats.crossings))
        << " face crossings, " << formatCount(double(stats.rays.total())) << " rays in " << formatSeconds(stats.seconds)
        << " (" << formatCount(stats.seconds > 0 ? double(stats.photons) / stats.seconds : 0.0)
        << " photons/s). Wrote " << in.output
        << (report.resolved.compact ? " (compact irradiance vectors: colour + direction, 12 half-float Vec3 grids).\n"
                                    : " (irradiance vectors, 18 Vec3f grids).\n");
    if (report.depth)  // the default's (--no-depth-moments: none)
        out << "Depth moments: " << formatCount(double(report.depth->rays)) << " first-hit rays in "
            << formatSeconds(report.depth->seconds) << " (" << depth::kBytesPerNode << " B per node at 8 bits).\n";
    return out.str();
}

const Pass& photonsPass() {
    static const PhotonsPass pass;
    return pass;
}

}  // namespace vdblight::bake_detail
