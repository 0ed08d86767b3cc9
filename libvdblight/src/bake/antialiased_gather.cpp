// The anti-aliased gather pass (Kontkanen & Laine eq. 6, optionally restricted to the
// domain of interest): each cell's rays are weighted by the trilinear basis functions of
// its eight nodes; cells are processed in parallel, a chunk of z-slabs at a time, and reduced into
// the nodes in cell order.
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "domain_classification.h"
#include "core/grid_index.h"
#include "parallel_nodes.h"
#include "pass_metadata.h"
#include "bake/bake_antialiased.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "node_least_squares.h"
#include "sampling/radical_inverse_fast.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
enum Dimension : uint64_t { kLightPoint = 21, kLightChoice = 22, kPath = 23, kPunctualChoice = 24 };
constexpr int kValues = sh::kCoeffs * 3;

/// One cell's contribution to its eight corner nodes (corner bit 0 = +x, 1 = +y, 2 = +z).
struct CellPartial {
    double coeff[8][kValues];
    double norm[8];       ///< sum of b_i over accepted origins (eq. 6 denominator)
    double candidate[8];  ///< sum of b_i over all candidate origins (validity denominator)
    double gram[8][8];    ///< sum of b_i b_k over accepted origins (NodeFit::LeastSquares)
    uint32_t accepted;
};

void bakeCell(const Scene& scene, const RadianceEstimator& estimator, const Tracer& tracer, const GridSpec& grid, std::size_t cell,
              const AntialiasedOptions& o, CellPartial& out, RayCount& count, std::vector<LightSample>& punctual) {
    std::vector<Hit> hits;
    const std::vector<CellSample> samples = classifyCell(scene, tracer, grid, cell, o.raysPerCell, o.seed, o.domain, count, &hits, o.fallback);
    int cx, cy, cz;
    cellDims(grid, cx, cy, cz);
    const core::Index3 ijk = core::unflatten(cell, uint64_t(cx), uint64_t(cy));
    const Vec3d lo = grid.node(ijk.i, ijk.j, ijk.k);
    const bool flat[3] = {grid.nx == 1, grid.ny == 1, grid.nz == 1};

    const uint64_t stream = hashCombine(o.seed, cell);
    Rng rng(stream, kPath);
    const bool nee = estimator.hasEmissiveTriangles();
    constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
    out = CellPartial{};
    float y[sh::kCoeffs];
    // Per-sample products are summed in float, 4 lanes at a time, over blocks of kBlock
    // accepted samples, and each block's sums are added to the cell's double sums: a third of
    // the instructions of summing every product in double (docs/methods.md), with the float
    // rounding bounded by a block's length (kBlock ulps at most) instead of the cell's.
    constexpr int kBlock = 64, kPadded = 28;  // 27 values padded to whole SSE vectors
    alignas(16) float blockCoeff[8][kPadded] = {};
    alignas(16) float blockGram[8][8] = {};
    int inBlock = 0;
    const bool lsq = o.fit == NodeFit::LeastSquares;
    const auto flush = [&] {
        for (int c = 0; c < 8; ++c)
            for (int v = 0; v < kValues; ++v) out.coeff[c][v] += double(blockCoeff[c][v]);
        if (lsq)
            for (int a = 0; a < 8; ++a)
                for (int b = 0; b < 8; ++b) out.gram[a][b] += double(blockGram[a][b]);
        std::fill(&blockCoeff[0][0], &blockCoeff[0][0] + 8 * kPadded, 0.0f);
        std::fill(&blockGram[0][0], &blockGram[0][0] + 64, 0.0f);
        inBlock = 0;
    };
    for (uint32_t i = 0; i < uint32_t(samples.size()); ++i) {
        const CellSample& s = samples[i];
        double w[8];
        double t[3];
        for (int a = 0; a < 3; ++a) t[a] = flat[a] ? 0.0 : std::clamp((double(s.origin[a]) - lo[a]) / grid.spacing, 0.0, 1.0);
        for (int c = 0; c < 8; ++c) {
            w[c] = 1.0;
            for (int a = 0; a < 3; ++a) w[c] *= (c >> a & 1) ? t[a] : 1.0 - t[a];
            out.candidate[c] += w[c];
        }
        if (!s.accepted) continue;
        ++out.accepted;
        // Incident radiance along this ray (first hit reused from the classification) ...
        alignas(16) float term[kPadded] = {};
        const Rgb l = estimator.gatherRadiance(s.origin, s.direction, kSpherePdf, rng, count, &hits[i]);
        sh::evalUnrolled(s.direction, y);
        const float lp[3] = {l[0] / kSpherePdf, l[1] / kSpherePdf, l[2] / kSpherePdf};
        for (int j = 0; j < sh::kCoeffs; ++j)
            for (int ch = 0; ch < 3; ++ch) term[3 * j + ch] += lp[ch] * y[j];
        // ... one NEE sample of the emissive triangles ...
        if (nee) {
            // The point on the light: Halton bases 13, 17 (independent of the cell's bases 2..11).
            const double shift = toUnitDouble(hashCombine(stream, kLightPoint));
            double u = radicalInverseFast<13>(i) + shift, v = radicalInverseFast<17>(i) + shift * 0.618034;
            u -= std::floor(u);
            v -= std::floor(v);
            LightSample ls;
            if (estimator.sampleEmissiveTriangles(s.origin, float(u), float(v), toUnitFloat(hashCombine(stream ^ kLightChoice, i)), ls,
                                                  count)) {
                sh::evalUnrolled(ls.direction, y);
                const Rgb weight = ls.weight * misWeight(ls.pdf, kSpherePdf);
                for (int j = 0; j < sh::kCoeffs; ++j)
                    for (int ch = 0; ch < 3; ++ch) term[3 * j + ch] += weight[ch] * y[j];
            }
        }
        // ... and the punctual lights at this origin: exactly, or with many point/spot lights
        // one of them chosen by the light tree (light.h; Halton base 19, shifted per cell).
        punctual.clear();
        estimator.punctualLights(s.origin, punctual, count, true);
        if (estimator.samplesPunctualLights()) {
            double u = radicalInverseFast<19>(i) + toUnitDouble(hashCombine(stream, kPunctualChoice));
            u -= std::floor(u);
            LightSample ls;
            if (estimator.samplePunctualLight(s.origin, u, ls, count)) punctual.push_back(ls);
        }
        for (const LightSample& p : punctual) {
            sh::evalUnrolled(p.direction, y);
            for (int j = 0; j < sh::kCoeffs; ++j)
                for (int ch = 0; ch < 3; ++ch) term[3 * j + ch] += p.weight[ch] * y[j];
        }
        alignas(16) float used[8];  // the basis weights this origin contributes with
        for (int c = 0; c < 8; ++c) {
            used[c] = 0.0f;
            if (w[c] == 0.0) continue;
            if (o.visibleSupport) {
                const Vec3d node(lo.x + (c & 1) * grid.spacing, lo.y + (c >> 1 & 1) * grid.spacing,
                                 lo.z + (c >> 2 & 1) * grid.spacing);
                Ray ray;
                ray.origin = s.origin;
                ray.direction = Vec3f(node) - s.origin;
                ray.tfar = 1.0f;
                ++count.occluded;
                if (tracer.occluded(ray)) continue;
            }
            used[c] = float(w[c]);
            out.norm[c] += w[c];
            for (int v = 0; v < kPadded; ++v) blockCoeff[c][v] += used[c] * term[v];
        }
        if (lsq)
            for (int a = 0; a < 8; ++a)
                for (int b = 0; b < 8; ++b) blockGram[a][b] += used[a] * used[b];
        if (++inBlock == kBlock) flush();
    }
    if (inBlock > 0) flush();
}
}  // namespace

Volume bakeShAntialiased(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const AntialiasedOptions& o,
                         Interrupter* interrupter, BakeStats* stats) {
    if (o.raysPerCell == 0) throw ValueError("rays per cell must be at least 1");
    const std::size_t nodes = bake_detail::checkThreadsAndGrid(o.threads, grid);
    int cx, cy, cz;
    cellDims(grid, cx, cy, cz);
    const std::size_t cells = cellCount(grid), slabCells = std::size_t(cx) * std::size_t(cy);

    if (o.fit == NodeFit::LeastSquares && !(o.tikhonov >= 0 && std::isfinite(o.tikhonov)))
        throw ValueError("the Tikhonov weight must be finite and >= 0, got " + std::to_string(o.tikhonov));
    if (o.fit == NodeFit::LeastSquares && !(o.fitTolerance > 0 && std::isfinite(o.fitTolerance)))
        throw ValueError("the least-squares tolerance must be finite and > 0, got " + std::to_string(o.fitTolerance));
    std::vector<double> acc(nodes * kValues, 0.0), norm(nodes, 0.0), candidate(nodes, 0.0);
    std::optional<NodeGram> gram;
    if (o.fit == NodeFit::LeastSquares) gram.emplace(grid);
    const RadianceEstimator estimator(scene, tracer, o.transport);
    tbb::enumerable_thread_specific<std::vector<LightSample>> punctualScratch;
    uint64_t accepted = 0;
    bake_detail::ParallelRun run;
    const auto start = std::chrono::steady_clock::now();
    const int threads = core::threadCount(o.threads);
    {
        core::TaskProgress progress(interrupter, "baking (anti-aliased)", cells, "bake cancelled");
        // Cells are baked in chunks of whole z-slabs (at most ~kChunkCells cells, at least one
        // slab) so that the parallel loop balances over many cells between reductions.
        constexpr std::size_t kChunkCells = 8192;
        const int slabsPerChunk = int(std::clamp<std::size_t>(kChunkCells / slabCells, 1, std::size_t(cz)));
        std::vector<CellPartial> chunk(std::size_t(slabsPerChunk) * slabCells);
        for (int ck0 = 0; ck0 < cz; ck0 += slabsPerChunk) {
            const std::size_t first = std::size_t(ck0) * slabCells;
            const std::size_t count = std::size_t(std::min(cz - ck0, slabsPerChunk)) * slabCells;
            run.rays += bake_detail::forEachItemInParallel(count, o.threads, progress, [&](std::size_t c, RayCount& rays) {
                bakeCell(scene, estimator, tracer, grid, first + c, o, chunk[c], rays, punctualScratch.local());
            }).rays;
            // Fixed-order reduction: cells in index order, corners in bit order.
            for (std::size_t c = 0; c < count; ++c) {
                const CellPartial& part = chunk[c];
                const core::Index3 cell = core::unflatten(first + c, uint64_t(cx), uint64_t(cy));
                accepted += part.accepted;
                if (gram) gram->addCell(cell.i, cell.j, cell.k, part.gram);
                for (int corner = 0; corner < 8; ++corner) {
                    const int i = cell.i + (corner & 1), j = cell.j + (corner >> 1 & 1), k = cell.k + (corner >> 2 & 1);
                    if (i >= grid.nx || j >= grid.ny || k >= grid.nz) continue;  // flat axis
                    const std::size_t n = grid.index(i, j, k);
                    norm[n] += part.norm[corner];
                    candidate[n] += part.candidate[corner];
                    for (int v = 0; v < kValues; ++v) acc[n * kValues + v] += part.coeff[corner][v];
                }
            }
        }
    }
    if (accepted == 0) {
        throw SceneError("no ray origin in any cell lies in the domain of interest: every surface is seen from its "
                         "back side (do the normals look reversed? check the faces' winding)");
    }

    Volume volume = bake_detail::emptyShVolume(grid);
    VolumeLevel& level = volume.levels[0];
    level.validity.assign(nodes, 0.0f);
    std::vector<uint8_t> filled(nodes, 0);
    std::size_t unfilled = 0;
    for (std::size_t n = 0; n < nodes; ++n) {
        level.validity[n] = candidate[n] > 0 ? float(std::min(1.0, norm[n] / candidate[n])) : 0.0f;
        if (!(norm[n] > 0)) {
            ++unfilled;
            continue;
        }
        filled[n] = 1;
        for (int v = 0; v < kValues; ++v) level.data[n * kValues + v] = float(acc[n * kValues + v] / norm[n]);
    }
    const int passes = unfilled ? dilateUnfilledNodes(level, sh::kCoeffs, filled, norm) : 0;
    LeastSquaresStats fitStats;
    if (gram) {
        // The least-squares fit, pulled towards the eq.-6 values (dilated where unsupported).
        const std::vector<double> prior(level.data.begin(), level.data.end());
        const std::vector<double> fitted = solveNodeLeastSquares(*gram, acc, prior, kValues, o.tikhonov, &fitStats, o.fitTolerance);
        for (std::size_t q = 0; q < fitted.size(); ++q) level.data[q] = float(fitted[q]);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const RayCount total = run.rays;
    // As the other passes' keys (PassMetadata), except roulette_max_survival, which this pass
    // has never written (its files stay the same bits).
    bake_detail::PassMetadata m(volume.meta);
    m.scene(scene).method("gather", "antialiased").transport(o.transport, o.seed, false).run(nodes, total, seconds, threads);
    m.text("domain", o.domain == DomainMode::Interior ? "interior" : "all");
    if (o.visibleSupport) m.text("support", "visible (origin-to-node occlusion test)");
    if (gram) {
        m.text("fit", "least-squares (Tikhonov towards eq. 6)")
            .number("fit_tikhonov", o.tikhonov)
            .count("fit_cg_iterations", fitStats.maxIterations)
            .number("fit_tolerance", o.fitTolerance);
    } else {
        m.text("fit", "projection (eq. 6)");
    }
    m.count("rays_per_cell", o.raysPerCell)
        .text("origin_sampling", "shifted Halton (bases 5, 7, 11) per cell, trilinear weights, eq. 6")
        .text("direction_sampling", "shifted Halton (bases 2, 3) uniform sphere + NEE on emissive triangles; punctual "
                                    "lights exact per origin (one sampled per origin above the exact-light limit)")
        .count("cells", int64_t(cells))
        .count("origins_accepted", int64_t(accepted))
        .count("origins_rejected", int64_t(cells * o.raysPerCell - accepted))
        .count("nodes_dilated", int64_t(unfilled))
        .count("dilation_passes", passes);
    if (stats) {
        stats->nodes = nodes;
        stats->rays = total;
        stats->seconds = seconds;
    }
    return volume;
}

}  // namespace vdblight
