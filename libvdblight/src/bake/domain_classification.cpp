// Per-cell candidate rays and their point classification (Kontkanen & Laine, Algorithm 2),
// with a fallback check of the accepted origins in cells where back-faces were seen.
#include <algorithm>
#include <cmath>

#include "domain_classification.h"
#include "bake/bake_antialiased.h"
#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "sampling/radical_inverse_fast.h"
#include "vdblight/scene/scene.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// Independent scrambles of one cell's sample dimensions (the anti-aliased pass uses more).
enum CellDimension : uint64_t {
    kShiftX = 11, kShiftY = 12, kShiftZ = 13, kShiftU = 14, kShiftV = 15,  // Algorithm 2's candidates
    kProbeU = 16, kProbeV = 17, kTriangleU = 18, kTriangleV = 19,          // the fallback
};

/// Sample i of the cell's 5-D Halton point set (bases 2, 3 for the direction, 5, 7, 11 for
/// the position), Cranley-Patterson rotated by the cell's shifts. A scrambled Sobol (0,2)
/// direction paired with Halton positions correlates (the trilinearly weighted SH sums of a
/// constant sky then converge more slowly than with random samples); all-Halton does not.
/// (Table radical inverses, radical_inverse_fast.h: the five digit-by-digit inverses per
/// candidate were 8 % of the bake's instructions.)
template <uint32_t Base>
double haltonShifted(uint32_t i, double shift) {
    const double u = radicalInverseFast<Base>(i) + shift;
    return u - std::floor(u);
}

bool isBackFace(const Hit& hit, const Vec3f& direction) {
    return hit.hit() && dot(hit.geometricNormal, direction) > 0.0f;
}

/// True if the query ray from `origin` towards back-face point `target` first meets a back-face.
/// `blockedAt` (optional) receives the hit's t (in units of target - origin) when a front face
/// blocks the ray, and infinity if it meets nothing.
bool seesBackFace(const Tracer& tracer, const Vec3f& origin, const Vec3f& target, RayCount& count,
                  float* blockedAt = nullptr) {
    const Vec3f dir = target - origin;
    if (!(dot(dir, dir) > 0.0f)) return true;  // the origin is the back-face point itself
    ++count.intersect;
    const Hit hit = tracer.intersect(Ray{origin, dir});
    if (blockedAt) *blockedAt = hit.t;
    return isBackFace(hit, dir);
}

}  // namespace

void cellDims(const GridSpec& grid, int& cx, int& cy, int& cz) {
    cx = std::max(grid.nx - 1, 1);
    cy = std::max(grid.ny - 1, 1);
    cz = std::max(grid.nz - 1, 1);
}

std::size_t cellCount(const GridSpec& grid) {
    int cx, cy, cz;
    cellDims(grid, cx, cy, cz);
    return std::size_t(cx) * std::size_t(cy) * std::size_t(cz);
}

std::vector<CellSample> classifyCell(const Scene& scene, const Tracer& tracer, const GridSpec& grid, std::size_t cell,
                                     uint32_t rays, uint64_t seed, DomainMode domain, RayCount& count,
                                     std::vector<Hit>* hits, const DomainFallback& fallback) {
    int cx, cy, cz;
    cellDims(grid, cx, cy, cz);
    if (cell >= cellCount(grid)) throw ValueError("cell index " + std::to_string(cell) + " is out of range");
    const core::Index3 c = core::unflatten(cell, uint64_t(cx), uint64_t(cy));
    const int ci = c.i, cj = c.j, ck = c.k;
    const Vec3d lo = grid.node(ci, cj, ck);
    // A flat axis (one node) has cells of zero extent along it.
    const Vec3d extent(grid.nx > 1 ? grid.spacing : 0.0, grid.ny > 1 ? grid.spacing : 0.0,
                       grid.nz > 1 ? grid.spacing : 0.0);
    const uint64_t stream = hashCombine(seed, cell);
    const double shift[3] = {toUnitDouble(hashCombine(stream, kShiftX)), toUnitDouble(hashCombine(stream, kShiftY)),
                             toUnitDouble(hashCombine(stream, kShiftZ))};
    const double shiftU = toUnitDouble(hashCombine(stream, kShiftU)), shiftV = toUnitDouble(hashCombine(stream, kShiftV));

    std::vector<CellSample> samples(rays);
    if (hits) hits->assign(rays, Hit{});
    std::vector<Vec3f> backFacePoints;
    std::vector<float> blocked(rays, -1.0f);  // t of the query to backFacePoints[0]
    std::vector<uint32_t> backFaceTriangles;  // distinct triangles of the back-face points, in order found
    const auto addBackFacePoint = [&](const Vec3f& b, uint32_t triangle) {
        backFacePoints.push_back(b);
        if (std::find(backFaceTriangles.begin(), backFaceTriangles.end(), triangle) == backFaceTriangles.end())
            backFaceTriangles.push_back(triangle);
    };
    for (uint32_t i = 0; i < rays; ++i) {
        CellSample& s = samples[i];
        Vec3d p;
        p[0] = lo[0] + extent[0] * haltonShifted<5>(i, shift[0]);
        p[1] = lo[1] + extent[1] * haltonShifted<7>(i, shift[1]);
        p[2] = lo[2] + extent[2] * haltonShifted<11>(i, shift[2]);
        s.origin = Vec3f(p);
        s.direction = uniformSphere(float(haltonShifted<2>(i, shiftU)), float(haltonShifted<3>(i, shiftV)));
        if (domain == DomainMode::All) {
            s.accepted = true;
            if (hits) {
                ++count.intersect;
                (*hits)[i] = tracer.intersect(Ray{s.origin, s.direction});
            }
            continue;
        }
        // Known back-face points visible from this origin reject it without a sampling ray.
        bool rejected = false;
        for (const Vec3f& b : backFacePoints)
            if (seesBackFace(tracer, s.origin, b, count, &b == &backFacePoints[0] ? &blocked[i] : nullptr)) {
                rejected = true;
                break;
            }
        if (rejected) continue;
        ++count.intersect;
        const Hit hit = tracer.intersect(Ray{s.origin, s.direction});
        if (!isBackFace(hit, s.direction)) {
            s.accepted = true;
            if (hits) (*hits)[i] = hit;
            continue;
        }
        // A new back-face point: re-test the origins accepted so far against it.
        const Vec3f b = s.origin + s.direction * hit.t;
        addBackFacePoint(b, hit.triangle);
        for (uint32_t k = 0; k < i; ++k)
            if (samples[k].accepted &&
                seesBackFace(tracer, samples[k].origin, b, count, backFacePoints.size() == 1 ? &blocked[k] : nullptr))
                samples[k].accepted = false;
    }
    if (backFacePoints.empty()) return samples;  // no back-face seen: the whole cell is in the domain
    if (fallback.trianglePoints == 0 && fallback.probes == 0) return samples;  // Algorithm 2 alone

    // The fallback (docs/methods.md), step 1, the screen: an accepted origin whose query ray
    // to the first back-face point b0 was blocked by a front face is continued past that face
    // towards b0. If the continuation meets a back-face before b0, the line left the solid it
    // entered, so the blocker is a surface between the origin and back-faces on the origin's
    // own side (a wall end poking out of a room), not the solid b0 lies in: a suspect. So is
    // an origin whose query met nothing. Others (their line to b0 runs inside the blocking
    // solid up to b0, or reaches b0's surface from the front) are not.
    const Vec3f b0 = backFacePoints[0];
    std::vector<uint8_t> suspect(rays, 0);
    for (uint32_t i = 0; i < rays; ++i) {
        if (!samples[i].accepted) continue;
        const Vec3f dir = b0 - samples[i].origin;
        const float eps = 1e-4f / std::sqrt(dot(dir, dir));  // 1e-4 scene units along the ray
        if (!(blocked[i] >= 0.0f && blocked[i] < 1.0f - eps)) {
            suspect[i] = !(blocked[i] >= 1.0f - eps && std::isfinite(blocked[i]));
            continue;
        }
        Ray continuation{samples[i].origin, dir};
        continuation.tnear = blocked[i] + eps;
        continuation.tfar = 1.0f - eps;
        ++count.intersect;
        suspect[i] = isBackFace(tracer.intersect(continuation), dir);
    }
    // Step 2: Algorithm 2 accepts an origin from which none of the cell's few known back-face
    // points is visible and whose own ray met no back-face. Where a surface hides those points
    // (wall ends poking through a room's faces), origins outside the domain slip through. So
    // every suspect shoots query rays towards points on the back-facing triangles found so far
    // and probe rays in further directions; a back-face hit rejects it, and the hit becomes a
    // back-face point against which the other accepted origins are tested (Algorithm 2's rule).
    const auto test = [&](uint32_t i, const Vec3f& dir) {
        ++count.intersect;
        const Hit hit = tracer.intersect(Ray{samples[i].origin, dir});
        if (!isBackFace(hit, dir)) return;
        samples[i].accepted = false;
        const Vec3f b = samples[i].origin + dir * hit.t;
        addBackFacePoint(b, hit.triangle);
        for (uint32_t k = 0; k < rays; ++k)
            if (k != i && samples[k].accepted && seesBackFace(tracer, samples[k].origin, b, count))
                samples[k].accepted = false;
    };
    const double triU = toUnitDouble(hashCombine(stream, kTriangleU)), triV = toUnitDouble(hashCombine(stream, kTriangleV));
    for (uint32_t i = 0; i < rays; ++i)
        for (uint32_t p = 0; p < fallback.trianglePoints && samples[i].accepted && suspect[i]; ++p) {
            // Point `index` of a 2-D Halton set on the triangles, cycling through them.
            const uint32_t index = i * fallback.trianglePoints + p;
            const uint32_t tri = backFaceTriangles[index % backFaceTriangles.size()];
            float b1, b2;
            uniformTriangle(float(haltonShifted<2>(index, triU)), float(haltonShifted<3>(index, triV)), b1, b2);
            const Vec3f target = scene.vertex(tri, 0) * (1 - b1 - b2) + scene.vertex(tri, 1) * b1 + scene.vertex(tri, 2) * b2;
            test(i, target - samples[i].origin);
        }
    const double probeU = toUnitDouble(hashCombine(stream, kProbeU)), probeV = toUnitDouble(hashCombine(stream, kProbeV));
    for (uint32_t i = 0; i < rays; ++i)
        for (uint32_t p = 0; p < fallback.probes && samples[i].accepted && suspect[i]; ++p) {
            const uint32_t index = i * fallback.probes + p;
            test(i, uniformSphere(float(haltonShifted<2>(index, probeU)), float(haltonShifted<3>(index, probeV))));
        }
    return samples;
}

}  // namespace vdblight
