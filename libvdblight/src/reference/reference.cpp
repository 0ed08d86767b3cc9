// Ground-truth irradiance by direct hemisphere integration (no SH, no grid).
#include "vdblight/reference/reference.h"

#include <algorithm>
#include <cmath>

#include "core/parallel_for.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// Samples are processed in fixed chunks so that one point with many samples still uses
// every thread; chunk sums are reduced in chunk order, so results do not depend on threads.
constexpr uint32_t kChunk = 4096;

struct ChunkSum {
    Rgbd sum, sumSquares;
};

ChunkSum integrateChunk(const RadianceEstimator& estimator, const ReferencePoint& point, const Vec3f& n,
                        uint64_t stream, uint32_t first, uint32_t count, bool punctualExactAtPoint, RayCount& rays) {
    Rng rng(stream, first);
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    const double lightOffset = toUnitDouble(hashCombine(stream, 3));
    const double punctualOffset = toUnitDouble(hashCombine(stream, 4));
    ChunkSum s;
    for (uint32_t i = first; i < first + count; ++i) {
        float u, v;
        sobol02(i, hashCombine(stream, 1), u, v);
        const Vec3f local = cosineHemisphere(u, v);
        const Vec3f dir = t * local.x + b * local.y + n * local.z;
        // Cosine-weighted: L cos / (cos / pi) = pi L.
        Rgbd value = Rgbd(estimator.gatherRadiance(point.position, dir, local.z * float(kInvPi), rng, rays)) * kPi;
        if (estimator.hasEmissiveTriangles()) {
            sobol02(i, hashCombine(stream, 2), u, v);
            double w = radicalInverse(3, i) + lightOffset;
            w -= std::floor(w);
            LightSample ls;
            // TransportOptions::skipAtReceiver: the indirect-only reference (bench_direct's ground truth).
            if (estimator.sampleEmissiveTriangles(point.position, u, v, float(w), ls, rays) && !estimator.skipsAtReceiver(ls)) {
                const float cosine = std::max(0.0f, dot(n, ls.direction));
                value += Rgbd(ls.weight) * double(cosine * misWeight(ls.pdf, cosine * float(kInvPi)));
            }
        }
        if (estimator.samplesPunctualLights() && !punctualExactAtPoint) {
            // Many point/spot lights: one chosen per sample (light.h), part of the variance.
            double w = radicalInverse(5, i) + punctualOffset;
            w -= std::floor(w);
            LightSample ls;
            if (estimator.samplePunctualLight(point.position, w, ls, rays) && !estimator.skipsAtReceiver(ls))
                value += Rgbd(ls.weight) * double(std::max(0.0f, dot(n, ls.direction)));
        }
        s.sum += value;
        s.sumSquares += value * value;
    }
    return s;
}
}  // namespace

std::vector<ReferenceResult> referenceIrradiance(const Scene& scene, const Tracer& tracer,
                                                 const std::vector<ReferencePoint>& points,
                                                 const ReferenceOptions& options, Interrupter* interrupter) {
    if (options.samples == 0) throw ValueError("reference needs at least one sample per point");
    std::vector<Vec3f> normals(points.size());
    for (std::size_t p = 0; p < points.size(); ++p) {
        const float len = length(points[p].normal);
        if (!(len > 0) || !isFinite(points[p].normal) || !isFinite(points[p].position))
            throw ValueError("reference point " + std::to_string(p + 1) + " has a zero or non-finite normal/position");
        normals[p] = points[p].normal / len;
    }

    const RadianceEstimator estimator(scene, tracer, options.transport);
    // Many point/spot lights: at the point itself each is evaluated once, exactly (no variance),
    // when that costs at most one shadow ray per sample; bounce vertices still sample one.
    const bool exactAtPoint = options.punctualExactAtPoint && estimator.samplesPunctualLights() &&
                              estimator.pointAndSpotLightCount() <= options.samples;
    const uint32_t chunksPerPoint = (options.samples + kChunk - 1) / kChunk;
    const std::size_t tasks = points.size() * chunksPerPoint;
    std::vector<ChunkSum> chunks(tasks);
    {
        core::TaskProgress progress(interrupter, "reference", tasks, "reference cancelled");
        core::parallelFor(tasks, options.threads, [&](std::size_t task) {
            const std::size_t p = task / chunksPerPoint;
            const uint32_t chunk = uint32_t(task % chunksPerPoint);
            const uint32_t first = chunk * kChunk;
            const uint32_t count = std::min(kChunk, options.samples - first);
            RayCount rays;
            chunks[task] = integrateChunk(estimator, points[p], normals[p], hashCombine(options.seed, p), first,
                                          count, exactAtPoint, rays);
        }, &progress);
    }

    std::vector<ReferenceResult> results(points.size());
    std::vector<LightSample> punctual;
    for (std::size_t p = 0; p < points.size(); ++p) {
        ChunkSum total;
        for (uint32_t c = 0; c < chunksPerPoint; ++c) {
            total.sum += chunks[p * chunksPerPoint + c].sum;
            total.sumSquares += chunks[p * chunksPerPoint + c].sumSquares;
        }
        const double n = options.samples;
        const Rgbd mean = total.sum / n;
        Rgbd variance = total.sumSquares / n - mean * mean;
        variance = vmax(variance, Rgbd(0, 0, 0)) * (n / std::max(1.0, n - 1.0));
        results[p].irradiance = mean;
        results[p].standardError = {std::sqrt(variance.x / n), std::sqrt(variance.y / n), std::sqrt(variance.z / n)};
        // Punctual lights evaluated exactly (all, or the directional ones when point and
        // spot lights are sampled above, exactAtPoint false): no variance.
        punctual.clear();
        RayCount rays;
        estimator.punctualLights(points[p].position, punctual, rays, !exactAtPoint);
        for (const LightSample& s : punctual)
            if (!estimator.skipsAtReceiver(s)) results[p].irradiance += Rgbd(s.weight) * double(std::max(0.0f, dot(normals[p], s.direction)));
    }
    return results;
}

}  // namespace vdblight
