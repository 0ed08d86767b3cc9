// The point-gather pass for Greger bins and higher moments (bake_bins.h).

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "bins_gather.h"
#include "levels_bake.h"
#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "stratified_sphere.h"
#include "vdblight/volume/tiles.h"
#include "bake/bake_bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

LevelLayout uniformLayout(const GridSpec& grid) {
    LevelLayout layout;
    layout.kind = LayoutKind::Uniform;
    layout.refine = 1;
    layout.levels.resize(1);
    layout.levels[0].grid = grid;
    return layout;
}

void gatherBinRadiance(const RadianceEstimator& estimator, const Vec3f& x, int resolution, uint32_t samplesPerBin,
                       uint64_t seed, uint64_t streamIndex, Rgbd* out, RayCount& count) {
    const int R = resolution, bins = 2 * R * R;
    for (int b = 0; b < bins; ++b) out[b] = Rgbd(0, 0, 0);
    Rgbd acc(0, 0, 0);  // the current bin's radiance sum
    bake_detail::sampleStratifiedSphere(
        estimator, x, R, samplesPerBin, seed, streamIndex, count,
        [&](int, const Vec3f&, const Rgb& radiance) { acc += Rgbd(radiance); },
        [&](int b, double scale) {
            out[b] += acc * scale;
            acc = Rgbd(0, 0, 0);
        },
        [&](const Vec3f& direction, const Rgbd& value, double samples) { out[bins::binOf(R, direction)] += value / samples; });
}

Volume bakeBins(const Scene& scene, const Tracer& tracer, const LevelLayout& layout, const BinsBakeOptions& options,
                Interrupter* interrupter, LevelsBakeStats* stats) {
    if (options.basis.isSh2()) throw ValueError("bakeBins needs a bins or moment basis");
    bake_detail::checkLevelsBake(options.samplesPerBin, "samples per bin", options.threads, layout);
    const int R = options.basis.resolution, bins = options.basis.binCount();
    const std::size_t floats = std::size_t(bins) * 3;

    Volume volume = bake_detail::emptyLevelsVolume(layout, bins::basis(options.basis), floats, options.only);
    volume.validate();

    // Transposed (column i contiguous), so that the product below is a sequence of axpys over
    // j, which vectorises without reordering any sum (same bits as the row-by-row dot product).
    const std::vector<float> weights = [&] {
        const std::vector<float> w = bins::quadratureWeights(options.basis);
        std::vector<float> t(w.size());
        for (int j = 0; j < bins; ++j)
            for (int i = 0; i < bins; ++i) t[std::size_t(i) * bins + j] = w[std::size_t(j) * bins + i];
        return t;
    }();
    uint64_t seams = 0;
    const RadianceEstimator estimator(scene, tracer, options.transport);
    const bake_detail::ParallelRun run = bake_detail::forEachLevelNode(
        volume, options.only, options.threads, interrupter, seams, [&](const bake_detail::LevelNode& node, RayCount& count) {
            // Per-thread scratch, reused across nodes (no allocation per node once sized).
            thread_local std::vector<Rgbd> integral;
            thread_local std::vector<float> out;  // colour-major: out[c * bins + j]
            integral.resize(static_cast<std::size_t>(bins));
            out.resize(floats);
            gatherBinRadiance(estimator, node.position(), R, options.samplesPerBin, options.seed, node.stream,
                              integral.data(), count);
            // Quadrature (eq. 4 / 5 with integrated weights): H_j = sum_i W_ji Lbar_i,
            // Lbar_i = I_i / Omega; summed over i in order for every j.
            const double invOmega = 1.0 / bins::binSolidAngle(R);
            std::fill(out.begin(), out.end(), 0.0f);
            float* outR = out.data();
            float* outG = outR + bins;
            float* outB = outG + bins;
            for (int i = 0; i < bins; ++i) {
                const float lr = float(integral[std::size_t(i)].x * invOmega), lg = float(integral[std::size_t(i)].y * invOmega),
                            lb = float(integral[std::size_t(i)].z * invOmega);
                if (lr == 0.0f && lg == 0.0f && lb == 0.0f) continue;  // adds exact zeros
                const float* col = &weights[std::size_t(i) * bins];
                for (int j = 0; j < bins; ++j) {
                    outR[j] += col[j] * lr;
                    outG[j] += col[j] * lg;
                    outB[j] += col[j] * lb;
                }
            }
            float* dst = node.values(floats);
            for (int j = 0; j < bins; ++j) dst[3 * j] = outR[j], dst[3 * j + 1] = outG[j], dst[3 * j + 2] = outB[j];
        });
    bake_detail::finishLevelsBake(volume, layout, seams, run, options.only, stats);

    bake_detail::PassMetadata(volume.meta)
        .common(scene, options.transport, options.seed, layout.totalNodes(), run)
        .method("gather", "point")
        .count("bins_resolution", R)
        .count("bins", bins)
        .count("moment_order", options.basis.order)
        .count("samples_per_bin", options.samplesPerBin)
        .count("rays_per_node", int64_t(uint64_t(bins) * options.samplesPerBin))
        .text("direction_sampling", "scrambled Sobol (0,2) stratified inside each equal-area bin + NEE on emissive "
                                    "triangles; punctual lights exact")
        .text("quadrature", "eq. 5: (n+1)/2 * sum_i Lbar_i * integral over bin i of max(0, w . w_j)^n");
    return volume;
}

}  // namespace vdblight
