// Sampled form factors: the sample-to-sample (and node-to-sample) transfer estimated with
// rays from each receiver instead of one visibility ray per pair, so that the bake scales
// to the paper's 45 k samples (the pair matrix would hold n^2 = 2e9 floats there).
//
// A receiver casts M stratified rays (cosine-distributed over a sample's hemisphere,
// uniform over a node's sphere). A ray that hits the front of a surface is assigned to the
// sample standing for the hit point: the nearest sample facing the same side (SampleGrid,
// the rule that gave the samples their areas). Row r of F then holds, for every sender j
// found, pi / M times the number of rays that found j: the irradiance at r per unit
// radiance leaving j, the quantity the pair matrix holds (multi_bounce.cpp). A node's row
// holds 4 pi / M times the sum of Y_m over the rays that found j.
//
// With `normalise`, a row is scaled by (rays that hit a surface) / (rays that found a
// sample), capped at 4, as the pair matrix is scaled to the covered hemisphere.
//
// Determinism: receiver r draws its jitter from the stream (seed, r) and sums its rays in
// ray order after a stable sort by sender; rows are independent, so the result has the
// same bits for any thread count.
#include <algorithm>
#include <cmath>

#include "prt_internal.h"
#include "sample_grid.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "basis/sh.h"

namespace vdblight::prt_detail {

namespace {

constexpr float kMaxRowScale = 4.0f;  ///< as kMaxClosureScale of the pair matrix

/// One ray's sender and the ray's index (for ordered sums).
struct Found {
    uint32_t sender;
    uint32_t ray;
};

/// The sender a ray from `origin` along `dir` finds, kNone if none; `covered` is set if the
/// ray hit any surface.
uint32_t senderAlong(const Tracer& tracer, const SampleGrid& grid, const Vec3f& origin, const Vec3f& dir,
                     bool& covered) {
    const Hit h = tracer.intersect(Ray{origin, dir});
    covered = h.hit();
    if (!covered || dot(h.geometricNormal, dir) >= 0.0f) return SampleGrid::kNone;  // missed, or a back face
    return grid.nearestFacing(origin + dir * h.t, normalize(h.geometricNormal));
}

/// Stratified, jittered point of cell `k` of a g x g grid of the unit square.
void stratum(int g, int k, Rng& rng, float& u, float& v) {
    u = std::min((float(k % g) + rng.uniform()) / float(g), 0.99999994f);
    v = std::min((float(k / g) + rng.uniform()) / float(g), 0.99999994f);
}

/// Runs row(r, entries) for every receiver in parallel, then packs the rows in order.
template <typename RowFn>
SparseRows buildRows(std::size_t receivers, int width, int threads, Interrupter* in, RowFn&& row) {
    std::vector<std::vector<uint32_t>> cols(receivers);
    std::vector<std::vector<float>> weights(receivers);
    core::TaskProgress progress(in, "PRT bake cancelled");  // the caller starts and ends the task
    parallelFor(receivers, threads, [&](std::size_t r) { row(r, cols[r], weights[r]); }, &progress);
    SparseRows out;
    out.width = width;
    out.begin.assign(receivers + 1, 0);
    for (std::size_t r = 0; r < receivers; ++r) out.begin[r + 1] = out.begin[r] + cols[r].size();
    out.column.reserve(out.begin.back());
    out.weight.reserve(out.begin.back() * std::size_t(width));
    for (std::size_t r = 0; r < receivers; ++r) {
        out.column.insert(out.column.end(), cols[r].begin(), cols[r].end());
        out.weight.insert(out.weight.end(), weights[r].begin(), weights[r].end());
        std::vector<uint32_t>().swap(cols[r]);
        std::vector<float>().swap(weights[r]);
    }
    return out;
}

/// Row scale for `covered` rays that hit a surface of which `found` found a sender.
float rowScale(bool normalise, uint32_t covered, uint32_t found) {
    if (!normalise || found == 0) return 1.0f;
    return std::min(kMaxRowScale, float(covered) / float(found));
}

}  // namespace

SparseRows sampledSampleFormFactors(const SurfaceSamples& s, const Tracer& tracer, uint32_t rays, bool normalise,
                                    uint64_t seed, int threads, Interrupter* in) {
    const int g = std::max(1, int(std::ceil(std::sqrt(double(rays)))));
    const uint32_t m = uint32_t(g * g);
    const SampleGrid grid(s.position, s.normal, float(s.radius));
    return buildRows(s.size(), 1, threads, in, [&](std::size_t r, std::vector<uint32_t>& cols, std::vector<float>& w) {
        Rng rng(hashCombine(seed, 0xf0f0f0u), r);
        Vec3f t1, t2;
        orthonormalBasis(s.normal[r], t1, t2);
        std::vector<Found> found;
        uint32_t covered = 0;
        for (uint32_t k = 0; k < m; ++k) {
            float u, v;
            stratum(g, int(k), rng, u, v);
            const Vec3f l = cosineHemisphere(u, v);
            const Vec3f dir = t1 * l.x + t2 * l.y + s.normal[r] * l.z;
            bool hit = false;
            const uint32_t j = senderAlong(tracer, grid, offsetRayOrigin(s.position[r], s.normal[r], dir), dir, hit);
            covered += hit;
            if (j != SampleGrid::kNone && j != r) found.push_back({j, k});
        }
        std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.sender < b.sender; });
        const float unit = float(kPi) / float(m) * rowScale(normalise, covered, uint32_t(found.size()));
        for (std::size_t i = 0; i < found.size();) {
            std::size_t e = i;
            while (e < found.size() && found[e].sender == found[i].sender) ++e;
            cols.push_back(found[i].sender);
            w.push_back(unit * float(e - i));
            i = e;
        }
    });
}

SparseRows sampledNodeGather(const SurfaceSamples& s, const Tracer& tracer, const std::vector<Vec3f>& nodes,
                             uint32_t rays, bool normalise, uint64_t seed, int threads, Interrupter* in) {
    const int g = std::max(1, int(std::ceil(std::sqrt(double(rays)))));
    const uint32_t m = uint32_t(g * g);
    const SampleGrid grid(s.position, s.normal, float(s.radius));
    return buildRows(nodes.size(), sh::kCoeffs, threads, in,
                     [&](std::size_t r, std::vector<uint32_t>& cols, std::vector<float>& w) {
        Rng rng(hashCombine(seed, 0x0f0f0fu), r);
        std::vector<Found> found;
        std::vector<Vec3f> dirs(m);
        uint32_t covered = 0;
        for (uint32_t k = 0; k < m; ++k) {
            float u, v;
            stratum(g, int(k), rng, u, v);
            dirs[k] = uniformSphere(u, v);
            bool hit = false;
            const uint32_t j = senderAlong(tracer, grid, nodes[r], dirs[k], hit);
            covered += hit;
            if (j != SampleGrid::kNone) found.push_back({j, k});
        }
        std::stable_sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.sender < b.sender; });
        const float unit = float(4.0 * kPi) / float(m) * rowScale(normalise, covered, uint32_t(found.size()));
        float y[sh::kCoeffs];
        for (std::size_t i = 0; i < found.size();) {
            float acc[sh::kCoeffs] = {};
            std::size_t e = i;
            for (; e < found.size() && found[e].sender == found[i].sender; ++e) {
                sh::evalUnrolled(dirs[found[e].ray], y);
                for (int c = 0; c < sh::kCoeffs; ++c) acc[c] += y[c];
            }
            cols.push_back(found[i].sender);
            for (int c = 0; c < sh::kCoeffs; ++c) w.push_back(unit * acc[c]);
            i = e;
        }
    });
}

}  // namespace vdblight::prt_detail
