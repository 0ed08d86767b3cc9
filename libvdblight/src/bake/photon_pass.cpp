// The photon pass: photons from the lights, traced with Embree, walked through the node
// lattice into irradiance vectors (photons.h).
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <sstream>
#include <vector>

#include "vdblight/errors.h"
#include "vdblight/interrupter.h"
#include "vdblight/irradiance_vectors.h"
#include "vdblight/photon_emitter.h"
#include "vdblight/photons.h"
#include "vdblight/sampling.h"
#include "vdblight/scene.h"
#include "vdblight/trace.h"

namespace vdblight {

namespace {
// Independent Cranley-Patterson shifts of the emission dimensions.
enum Dimension : uint64_t { kChoose = 1, kPos1, kPos2, kDir1, kDir2, kPath };

struct Counters {
    uint64_t segments = 0, crossings = 0;
    RayCount rays;
};

/// Everything a worker needs to trace photons; read-only, shared by all threads.
class PhotonWalker {
public:
    PhotonWalker(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options)
        : scene_(scene), tracer_(tracer), grid_(grid), options_(options), emitter_(scene, cover(scene, grid)) {
        dims_[0] = grid.nx, dims_[1] = grid.ny, dims_[2] = grid.nz;
        invSpacing_ = 1.0 / grid.spacing;
        for (int k = 0; k < 6; ++k) shift_[k] = toUnitDouble(hashCombine(options.seed, uint64_t(k + 1)));
        // Rays that escape end beyond the far side of the beam sphere.
        const Bounds b = cover(scene, grid);
        farDistance_ = float(4.0 * length(b.size()) + 4.0 * length(b.center()) + 1.0);
    }

    /// Traces photon `index` and adds its crossings to `sums` (kFloatsPerNode per node).
    void trace(uint64_t index, float* sums, Counters& count) const {
        const double invN = 1.0 / double(options_.photons);
        auto qmc = [&](uint32_t base, int dim) {
            double v = radicalInverse(base, index) + shift_[dim];
            return float(v - std::floor(v));
        };
        Rng rng(hashCombine(options_.seed, index), kPath);
        Photon p = emitter_.emit(qmc(2, 0), qmc(3, 1), qmc(5, 2), qmc(7, 3), qmc(11, 4), rng.uniform());
        Rgb power = p.power * float(invN);
        Vec3f origin = p.origin, dir = p.direction;
        for (int bounce = 0;; ++bounce) {
            ++count.rays.intersect;
            const Hit hit = tracer_.intersect(Ray{origin, dir, 0.0f, std::numeric_limits<float>::infinity()});
            const float t = hit.hit() ? hit.t : farDistance_;
            const Vec3f end = origin + dir * t;
            walk(origin, end, dir, power, sums, count);
            if (!hit.hit() || bounce >= options_.transport.maxBounces) return;
            // Diffuse reflection by albedo, Russian roulette on the largest component.
            const Rgb albedo = scene_.material(hit.triangle).albedo;
            const float survive = maxComponent(albedo);
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
        float add[3][9];
        int target[3];
        for (int a = 0; a < 3; ++a) {
            const float scale = options_.estimator == PhotonEstimator::Flux && dir[a] != 0.0f ? 1.0f / std::abs(dir[a]) : 1.0f;
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) add[a][3 * c + k] = -power[c] * dir[k] * scale;
            target[a] = iv::direction(a, dir[a] > 0.0f) * 9;
        }
        const Vec3d g0 = (Vec3d(from) - grid_.origin) * invSpacing_;
        const Vec3d g1 = (Vec3d(to) - grid_.origin) * invSpacing_;
        uint64_t crossings = 0;
        forEachFaceCrossing(g0, g1, dims_, [&](int a, int i, int j, int k) {
            float* dst = sums + grid_.index(i, j, k) * iv::kFloatsPerNode + target[a];
            for (int f = 0; f < 9; ++f) dst[f] += add[a][f];
            ++crossings;
        });
        count.crossings += crossings;
    }

    const Scene& scene_;
    const Tracer& tracer_;
    GridSpec grid_;
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

/// Divides the photon sums by the dual-face areas (halved on the node box's boundary).
void normalise(const std::vector<double>& total, const GridSpec& g, std::vector<float>& out) {
    out.resize(total.size());
    const int dims[3] = {g.nx, g.ny, g.nz};
    tbb::parallel_for(0, g.nz, [&](int k) {
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const int idx[3] = {i, j, k};
                const std::size_t base = g.index(i, j, k) * iv::kFloatsPerNode;
                for (int d = 0; d < iv::kDirections; ++d) {
                    const int a = d / 2;
                    double area = g.spacing * g.spacing;
                    for (int b = 0; b < 3; ++b)
                        if (b != a && (idx[b] == 0 || idx[b] == dims[b] - 1)) area *= 0.5;
                    for (int f = 0; f < 9; ++f) out[base + 9 * d + f] = float(total[base + 9 * d + f] / area);
                }
            }
    });
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

Volume bakePhotons(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const PhotonOptions& options,
                   Interrupter* interrupter, PhotonStats* stats) {
    checkOptions(grid, options);
    const PhotonWalker walker(scene, tracer, grid, options);
    const std::size_t nodes = grid.nodeCount();
    const std::size_t floats = nodes * iv::kFloatsPerNode;
    const uint64_t batchSize = photonBatchSize(options.photons, nodes);
    const uint64_t batches = (options.photons + batchSize - 1) / batchSize;

    const int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
    const uint64_t slots = std::min<uint64_t>(uint64_t(threads), batches);
    std::vector<std::vector<float>> buffers(slots, std::vector<float>(floats));
    std::vector<double> total(floats, 0.0);
    std::vector<Counters> batchCounts(batches);
    if (interrupter) interrupter->start("tracing photons", options.photons);

    const auto start = std::chrono::steady_clock::now();
    tbb::task_arena arena(threads);
    uint64_t done = 0;
    for (uint64_t first = 0; first < batches; first += slots) {
        const uint64_t round = std::min(slots, batches - first);
        arena.execute([&] {
            tbb::parallel_for(uint64_t(0), round, [&](uint64_t s) {
                const uint64_t b = first + s;
                float* sums = buffers[s].data();
                std::memset(sums, 0, floats * sizeof(float));
                const uint64_t end = std::min(options.photons, (b + 1) * batchSize);
                for (uint64_t i = b * batchSize; i < end; ++i) walker.trace(i, sums, batchCounts[b]);
            });
            // Add the round's buffers in batch order (per element: same order, same bits).
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, floats, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
                for (uint64_t s = 0; s < round; ++s) {
                    const float* src = buffers[s].data();
                    for (std::size_t e = r.begin(); e != r.end(); ++e) total[e] += double(src[e]);
                }
            });
        });
        done = std::min(options.photons, (first + round) * batchSize);
        if (interrupter) {
            interrupter->progress(done);
            if (interrupter->wasInterrupted()) {
                interrupter->end();
                throw Cancelled("bake cancelled");
            }
        }
    }
    if (interrupter) interrupter->end();

    Volume volume;
    volume.basis = iv::basis();
    volume.levels.resize(1);
    volume.levels[0].grid = grid;
    normalise(total, grid, volume.levels[0].data);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    Counters sum;
    for (const Counters& c : batchCounts) {
        sum.segments += c.segments;
        sum.crossings += c.crossings;
        sum.rays += c.rays;
    }
    const Rgb power = walker.emitter().totalPower();
    Metadata& m = volume.meta;
    m["scene_name"] = scene.name;
    m["scene_hash"] = scene.contentHash();
    m["scene_triangles"] = int64_t(scene.triangleCount());
    m["method"] = std::string("photons");
    m["photons"] = int64_t(options.photons);
    m["photon_batch_size"] = int64_t(batchSize);
    m["photon_estimator"] = std::string(options.estimator == PhotonEstimator::Flux ? "flux" : "paper_cosine");
    m["photon_segments"] = int64_t(sum.segments);
    m["photon_face_crossings"] = int64_t(sum.crossings);
    m["emitted_power"] = std::to_string(power.x) + "," + std::to_string(power.y) + "," + std::to_string(power.z);
    m["lights"] = int64_t(walker.emitter().lightCount());
    m["seed"] = int64_t(options.seed);
    m["bounces"] = int64_t(options.transport.maxBounces);
    m["roulette"] = std::string("from the first reflection, survival = max albedo component");
    m["nodes"] = int64_t(nodes);
    m["rays_intersect"] = int64_t(sum.rays.intersect);
    m["rays_occluded"] = int64_t(sum.rays.occluded);
    m["bake_seconds"] = seconds;
    m["threads"] = int64_t(threads);

    if (stats) {
        stats->photons = options.photons;
        stats->segments = sum.segments;
        stats->crossings = sum.crossings;
        stats->rays = sum.rays;
        stats->seconds = seconds;
        stats->batches = batches;
        stats->batchSize = batchSize;
    }
    return volume;
}

}  // namespace vdblight
