// The photon pass: photons from the lights, traced with Embree, walked through the node
// lattice into irradiance vectors (photons.h).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <atomic>
#include <chrono>
#include <cstring>
#include <sstream>
#include <vector>

#include "core/parallel_for.h"
#include "face_crossing.h"
#include "pass_metadata.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "light/photon_emitter.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/bake/each_pass.h"
#include "sampling/radical_inverse_fast.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// Independent Cranley-Patterson shifts of the emission dimensions.
enum Dimension : uint64_t { kChoose = 1, kPos1, kPos2, kDir1, kDir2, kPath };

// The per-batch sums are in PhotonSumLayout order (photon_sums.h): direction-major, the
// crossed axis fastest.
using SumLayout = PhotonSumLayout;

/// dst[0..8] += src[0..8] (src 16-byte aligned): the walk's innermost operation.
inline void addNine(float* dst, const float* src) {
#if defined(__SSE2__)
    _mm_storeu_ps(dst, _mm_add_ps(_mm_loadu_ps(dst), _mm_load_ps(src)));
    _mm_storeu_ps(dst + 4, _mm_add_ps(_mm_loadu_ps(dst + 4), _mm_load_ps(src + 4)));
    dst[8] += src[8];
#else
    for (int f = 0; f < 9; ++f) dst[f] += src[f];
#endif
}

struct Counters {
    uint64_t segments = 0, crossings = 0;
    RayCount rays;
};

/// Everything a worker needs to trace photons; read-only, shared by all threads.
class PhotonWalker {
public:
    PhotonWalker(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options)
        : scene_(scene), tracer_(tracer), grid_(grid), layout_(grid), options_(options),
          emitter_(scene, cover(scene, grid)) {
        dims_[0] = grid.nx, dims_[1] = grid.ny, dims_[2] = grid.nz;
        invSpacing_ = 1.0 / grid.spacing;
        for (int k = 0; k < 6; ++k) shift_[k] = toUnitDouble(hashCombine(options.seed, uint64_t(k + 1)));
        // Rays that escape end beyond the far side of the beam sphere.
        const Bounds b = cover(scene, grid);
        farDistance_ = float(4.0 * length(b.size()) + 4.0 * length(b.center()) + 1.0);
    }

    /// Traces photon `index` and adds its crossings to `sums` (kFloatsPerNode per node, in
    /// SumLayout order).
    void trace(uint64_t index, float* sums, Counters& count) const {
        const double invN = 1.0 / double(options_.photons);
        auto wrap = [&](double v, int dim) {
            v += shift_[dim];
            return float(v - std::floor(v));
        };
        Rng rng(hashCombine(options_.seed, index), kPath);
        Photon p = emitter_.emit(wrap(radicalInverseFast<2>(index), 0), wrap(radicalInverseFast<3>(index), 1),
                                 wrap(radicalInverseFast<5>(index), 2), wrap(radicalInverseFast<7>(index), 3),
                                 wrap(radicalInverseFast<11>(index), 4), rng.uniform());
        Rgb power = p.power * float(invN);
        Vec3f origin = p.origin, dir = p.direction;
        for (int bounce = 0;; ++bounce) {
            ++count.rays.intersect;
            const Hit hit = tracer_.intersect(Ray{origin, dir, 0.0f, std::numeric_limits<float>::infinity()});
            const float t = hit.hit() ? hit.t : farDistance_;
            const Vec3f end = origin + dir * t;
            walk(origin, end, dir, power, sums, count);
            if (!hit.hit() || bounce >= options_.transport.maxBounces) return;
            // Diffuse reflection by albedo, Russian roulette on the largest component, capped
            // like the gather's (light.h) so that white walls do not keep photons forever.
            const Rgb albedo = scene_.material(hit.triangle).albedo;
            const float survive = std::min(kRouletteMaxSurvival, maxComponent(albedo));
            if (!(rng.uniform() < survive)) return;
            power = power * albedo / survive;
            Vec3f n = normalize(hit.geometricNormal);
            if (dot(n, dir) > 0) n = -n;
            Vec3f tx, ty;
            orthonormalBasis(n, tx, ty);
            const Vec3f local = cosineHemisphere(rng.uniform(), rng.uniform());
            const Vec3f next = normalize(tx * local.x + ty * local.y + n * local.z);
            origin = offsetRayOrigin(end, n, next);
            dir = next;
        }
    }

    const PhotonEmitter& emitter() const { return emitter_; }

private:
    static Bounds cover(const Scene& scene, const GridSpec& grid) {
        Bounds b = grid.nodeBounds();
        const Bounds s = scene.bounds();
        if (!s.empty()) {
            b.extend(s.lo);
            b.extend(s.hi);
        }
        return b;
    }

    void walk(const Vec3f& from, const Vec3f& to, const Vec3f& dir, const Rgb& power, float* sums,
              Counters& count) const {
        ++count.segments;
        // The vector each crossing of a plane normal to axis a adds, per colour: w = -dir
        // (towards the light), scaled by 1 / |dir_a| for the flux estimator.
        alignas(16) float add[3][12];
        float* target[3];
        const float w[3] = {-dir.x, -dir.y, -dir.z};
        const float rgb[3] = {power.x, power.y, power.z};
        for (int a = 0; a < 3; ++a) {
            const float scale = options_.estimator == PhotonEstimator::Flux && w[a] != 0.0f ? 1.0f / std::abs(w[a]) : 1.0f;
            for (int c = 0; c < 3; ++c) {
                const float pc = rgb[c] * scale;
                for (int k = 0; k < 3; ++k) add[a][3 * c + k] = pc * w[k];
            }
            target[a] = sums + layout_.offset(iv::direction(a, w[a] < 0.0f), 0, 0, 0);
        }
        const Vec3d g0 = (Vec3d(from) - grid_.origin) * invSpacing_;
        const Vec3d g1 = (Vec3d(to) - grid_.origin) * invSpacing_;
        uint64_t crossings = 0;
        forEachFaceCrossing(g0, g1, dims_, [&](int a, int i, int j, int k) {
            const std::size_t* st = layout_.stride[a];
            addNine(target[a] + (i * st[0] + j * st[1] + k * st[2]) * 9, add[a]);
            ++crossings;
        });
        count.crossings += crossings;
    }

    const Scene& scene_;
    const Tracer& tracer_;
    GridSpec grid_;
    SumLayout layout_;
    PhotonOptions options_;
    PhotonEmitter emitter_;
    int dims_[3];
    double invSpacing_;
    double shift_[6];
    float farDistance_;
};

void checkOptions(const GridSpec& grid, const PhotonOptions& options) {
    checkPhotonCount(options.photons);
    if (options.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    if (grid.nx < 2 || grid.ny < 2 || grid.nz < 2)
        throw ValueError("the photon pass needs at least 2 nodes along every axis, got " + std::to_string(grid.nx) +
                         " x " + std::to_string(grid.ny) + " x " + std::to_string(grid.nz));
    if (!(grid.spacing > 0) || !std::isfinite(grid.spacing)) throw ValueError("grid spacing must be positive");
}

}  // namespace

void checkPhotonCount(uint64_t photons) {
    if (photons == 0) throw ValueError("the photon count must be at least 1");
    if (photons > kMaxPhotons) {
        // A rough rate (about a million photons per second per thread) to say how absurd.
        const double hours = double(photons) / 1e6 / 2.0 / 3600.0;
        std::ostringstream s;
        s << photons << " photons would take about " << std::llround(hours)
          << " hours on 2 threads (at ~1 M photons/s per thread); at most " << kMaxPhotons << " are accepted";
        throw ValueError(s.str());
    }
}

uint64_t photonBatchSize(uint64_t photons, std::size_t nodes) {
    const uint64_t byCount = (photons + 255) / 256;
    const uint64_t byGrid = uint64_t(nodes) * iv::kFloatsPerNode / 16;
    return std::max<uint64_t>({byCount, byGrid, 4096});
}

PhotonSums tracePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                        Interrupter* interrupter, PhotonStats* stats, Metadata* meta) {
    checkOptions(grid, options);
    const PhotonWalker walker(scene, tracer, grid, options);
    const std::size_t nodes = grid.nodeCount();
    const std::size_t floats = nodes * iv::kFloatsPerNode;
    const uint64_t batchSize = photonBatchSize(options.photons, nodes);
    const uint64_t batches = (options.photons + batchSize - 1) / batchSize;
    // A tile traces its run of batches (photon_sums.h); the batches do not depend on it.
    uint64_t firstBatch = 0, endBatch = batches;
    if (options.tiles > 0) photonTileBatches(batches, options.tiles, options.tile, firstBatch, endBatch);
    const uint64_t traced = std::min(options.photons, endBatch * batchSize) - firstBatch * batchSize;
    const Rgb power = walker.emitter().totalPower();
    PhotonSums out;
    out.grid = grid;
    out.exponent = photonSumExponent(double(maxComponent(power)));
    out.firstBatch = firstBatch, out.endBatch = endBatch, out.batches = batches;
    const double scale = std::ldexp(1.0, -out.exponent);

    const int threads = core::threadCount(options.threads);
    // Several batches per thread and round (memory permitting), so that a thread held up
    // by the machine's load does not leave the others waiting at every round's reduction.
    const uint64_t runBatches = endBatch - firstBatch;
    const uint64_t bufferBytes = uint64_t(floats) * sizeof(float);
    const uint64_t affordable = std::max<uint64_t>(1, (uint64_t(256) << 20) / bufferBytes);
    const uint64_t slots =
        std::min<uint64_t>(runBatches, std::max<uint64_t>(threads, std::min<uint64_t>(4 * threads, affordable)));
    std::vector<std::vector<float>> buffers(slots, std::vector<float>(floats));
    std::vector<PhotonFixed>& total = out.values;
    total.assign(floats, 0);
    std::vector<Counters> batchCounts(runBatches);

    const auto start = std::chrono::steady_clock::now();
    {
        core::TaskProgress progress(interrupter, "tracing photons", traced, "bake cancelled");
        for (uint64_t first = 0; first < runBatches; first += slots) {
            const uint64_t round = std::min(slots, runBatches - first);
            core::parallelFor(round, threads, [&](std::size_t s) {
                const uint64_t b = firstBatch + first + s;
                float* sums = buffers[s].data();
                std::memset(sums, 0, floats * sizeof(float));
                const uint64_t end = std::min(options.photons, (b + 1) * batchSize);
                for (uint64_t i = b * batchSize; i < end; ++i) walker.trace(i, sums, batchCounts[b - firstBatch]);
            });
            // Each batch's float sums as fixed-point integers (photon_sums.h): exact in any
            // order, so a merge of tiles gives the same totals.
            constexpr std::size_t kBlock = 4096;
            std::atomic<bool> outOfRange{false};
            core::parallelFor((floats + kBlock - 1) / kBlock, threads, [&](std::size_t block) {
                const std::size_t begin = block * kBlock, end = std::min(floats, begin + kBlock);
                for (uint64_t s = 0; s < round; ++s) {
                    const float* src = buffers[s].data();
                    for (std::size_t e = begin; e != end; ++e) {
                        if (src[e] == 0.0f) continue;
                        PhotonFixed v;
                        if (toPhotonFixed(src[e], scale, v)) total[e] += v;
                        else outOfRange = true;
                    }
                }
            });
            if (outOfRange)
                throw ValueError("a photon batch's sum through one face is not finite or exceeds 2^37 times the scene's "
                                 "emitted power (the fixed-point range of photon_sums.h)");
            progress.reportDone(std::min(options.photons, (firstBatch + first + round) * batchSize) - firstBatch * batchSize);
            progress.throwIfCancelled();
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    Counters sum;
    for (const Counters& c : batchCounts) {
        sum.segments += c.segments;
        sum.crossings += c.crossings;
        sum.rays += c.rays;
    }
    if (meta)
        bake_detail::PassMetadata(*meta)
            .scene(scene)
            .run(nodes, sum.rays, seconds, threads)
            .text("method", "photons")
            .count("photons", int64_t(options.photons))
            .count("photon_batch_size", int64_t(batchSize))
            .text("photon_estimator", options.estimator == PhotonEstimator::Flux ? "flux" : "paper_cosine")
            .count("photon_segments", int64_t(sum.segments))
            .count("photon_face_crossings", int64_t(sum.crossings))
            .text("emitted_power",
                  std::to_string(power.x) + "," + std::to_string(power.y) + "," + std::to_string(power.z))
            .count("lights", int64_t(walker.emitter().lightCount()))
            .count("seed", int64_t(options.seed))
            .count("bounces", options.transport.maxBounces)
            .text("roulette", "from the first reflection, survival = max albedo component");

    if (stats) {
        stats->photons = traced;
        stats->segments = sum.segments;
        stats->crossings = sum.crossings;
        stats->rays = sum.rays;
        stats->seconds = seconds;
        stats->batches = runBatches;
        stats->batchSize = batchSize;
    }
    return out;
}

Volume bakePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                   Interrupter* interrupter, PhotonStats* stats) {
    if (options.tiles > 0) throw ValueError("a tile of a photon bake holds sums (tracePhotons), not a volume");
    Metadata meta;
    const PhotonSums sums = tracePhotons(scene, tracer, grid, options, interrupter, stats, &meta);
    return photonVolume(sums, std::move(meta));
}

}  // namespace vdblight
