// Per-cell candidate rays and their point classification (Kontkanen & Laine, Algorithm 2).
#include <cmath>

#include "vdblight/bake_antialiased.h"
#include "vdblight/errors.h"
#include "vdblight/sampling.h"
#include "vdblight/trace.h"

namespace vdblight {

namespace {
// Independent scrambles of one cell's sample dimensions (the anti-aliased pass uses more).
enum CellDimension : uint64_t { kShiftX = 11, kShiftY = 12, kShiftZ = 13, kShiftU = 14, kShiftV = 15 };

/// Sample i of the cell's 5-D Halton point set (bases 2, 3 for the direction, 5, 7, 11 for
/// the position), Cranley-Patterson rotated by the cell's shifts. A scrambled Sobol (0,2)
/// direction paired with Halton positions correlates (the trilinearly weighted SH sums of a
/// constant sky then converge more slowly than with random samples); all-Halton does not.
double haltonShifted(uint32_t base, uint32_t i, double shift) {
    const double u = radicalInverse(base, i) + shift;
    return u - std::floor(u);
}

bool isBackFace(const Hit& hit, const Vec3f& direction) {
    return hit.hit() && dot(hit.geometricNormal, direction) > 0.0f;
}

/// True if the query ray from `origin` towards back-face point `target` first meets a back-face.
bool seesBackFace(const Tracer& tracer, const Vec3f& origin, const Vec3f& target, RayCount& count) {
    const Vec3f dir = target - origin;
    if (!(dot(dir, dir) > 0.0f)) return true;  // the origin is the back-face point itself
    ++count.intersect;
    return isBackFace(tracer.intersect(Ray{origin, dir}), dir);
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

std::vector<CellSample> classifyCell(const Tracer& tracer, const GridSpec& grid, std::size_t cell, uint32_t rays,
                                     uint64_t seed, DomainMode domain, RayCount& count, std::vector<Hit>* hits) {
    int cx, cy, cz;
    cellDims(grid, cx, cy, cz);
    if (cell >= cellCount(grid)) throw ValueError("cell index " + std::to_string(cell) + " is out of range");
    const int ci = int(cell % std::size_t(cx)), cj = int(cell / std::size_t(cx) % std::size_t(cy)),
              ck = int(cell / (std::size_t(cx) * std::size_t(cy)));
    const Vec3d lo = grid.node(ci, cj, ck);
    // A flat axis (one node) has cells of zero extent along it.
    const Vec3d extent(grid.nx > 1 ? grid.spacing : 0.0, grid.ny > 1 ? grid.spacing : 0.0,
                       grid.nz > 1 ? grid.spacing : 0.0);
    const uint64_t stream = hashCombine(seed, cell);
    const double shift[3] = {toUnitDouble(hashCombine(stream, kShiftX)), toUnitDouble(hashCombine(stream, kShiftY)),
                             toUnitDouble(hashCombine(stream, kShiftZ))};
    const double shiftU = toUnitDouble(hashCombine(stream, kShiftU)), shiftV = toUnitDouble(hashCombine(stream, kShiftV));
    const uint32_t bases[3] = {5, 7, 11};

    std::vector<CellSample> samples(rays);
    if (hits) hits->assign(rays, Hit{});
    std::vector<Vec3f> backFacePoints;
    for (uint32_t i = 0; i < rays; ++i) {
        CellSample& s = samples[i];
        Vec3d p;
        for (int a = 0; a < 3; ++a) p[a] = lo[a] + extent[a] * haltonShifted(bases[a], i, shift[a]);
        s.origin = Vec3f(p);
        s.direction = uniformSphere(float(haltonShifted(2, i, shiftU)), float(haltonShifted(3, i, shiftV)));
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
            if (seesBackFace(tracer, s.origin, b, count)) {
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
        backFacePoints.push_back(b);
        for (uint32_t k = 0; k < i; ++k)
            if (samples[k].accepted && seesBackFace(tracer, samples[k].origin, b, count)) samples[k].accepted = false;
    }
    return samples;
}

}  // namespace vdblight
