// Placing bilevel / n-level layouts: which cells contain geometry, which nodes exist.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {

using CellIndex = core::Index3;

CellIndex unpack(const GridSpec& g, uint64_t linear) { return core::unflatten(linear, uint64_t(g.nx), uint64_t(g.ny)); }

/// The cell's box, pushed out by `margin` on the sides that lie on the node box border,
/// then grown by `grow` (LevelsPlacement::refineDistance) on every side.
Bounds cellTestBox(const GridSpec& g, const CellIndex& c, double margin, double grow = 0.0) {
    Bounds b;
    b.lo = g.node(c.i, c.j, c.k);
    b.hi = b.lo + Vec3d(g.spacing, g.spacing, g.spacing);
    const int idx[3] = {c.i, c.j, c.k}, dims[3] = {g.nx, g.ny, g.nz};
    for (int a = 0; a < 3; ++a) {
        if (idx[a] == 0) b.lo[a] -= margin;
        if (idx[a] == dims[a] - 2) b.hi[a] += margin;
        b.lo[a] -= grow;
        b.hi[a] += grow;
    }
    return b;
}

struct Triangle {
    Vec3d a, b, c;
};

/// (cell, triangle) pairs of one level, sorted by cell: the geometry of each refined cell.
using CellTriangles = std::vector<std::pair<uint64_t, uint32_t>>;

void sortPairs(CellTriangles& pairs) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

std::vector<uint64_t> cellsOf(const CellTriangles& pairs) {
    std::vector<uint64_t> cells;
    for (const auto& p : pairs)
        if (cells.empty() || cells.back() != p.first) cells.push_back(p.first);
    return cells;
}

CellTriangles level0Geometry(const GridSpec& g, const std::vector<Triangle>& tris, double margin, double grow) {
    CellTriangles pairs;
    const int dims[3] = {g.nx, g.ny, g.nz};
    for (uint32_t t = 0; t < tris.size(); ++t) {
        const Triangle& tri = tris[t];
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const double mn = std::min({tri.a[a], tri.b[a], tri.c[a]}), mx = std::max({tri.a[a], tri.b[a], tri.c[a]});
            const double u0 = (mn - g.origin[a]) / g.spacing, u1 = (mx - g.origin[a]) / g.spacing;
            const double reach = std::ceil(grow / g.spacing);
            lo[a] = int(std::clamp(std::floor(u0) - 1.0 - reach, 0.0, double(dims[a] - 2)));
            hi[a] = int(std::clamp(std::floor(u1) + 1.0 + reach, 0.0, double(dims[a] - 2)));
        }
        for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i)
                    if (triangleOverlapsBox(tri.a, tri.b, tri.c, cellTestBox(g, {i, j, k}, margin, grow)))
                        pairs.emplace_back(g.index(i, j, k), t);
    }
    sortPairs(pairs);
    return pairs;
}

/// The node estimate of placeLevels: each refined cell brings at most (K + 1)^3 nodes.
struct NodeEstimate {
    double placed = 0;                 ///< the nodes of the levels placed so far
    double perCell = 0;                ///< (K + 1)^3
    double limit = INFINITY;           ///< LevelsPlacement::maxNodes
    double withCells(double cells) const { return placed + cells * perCell; }
    bool over(double cells) const { return withCells(cells) > limit; }
};

/// The geometry of the children (in `fine`) of every cell listed in `coarse`. Returns 0, or,
/// as soon as so many children have geometry that refining them is over `estimate`, their
/// count: with a large LevelsPlacement::refineDistance nearly every child has geometry, next to
/// every triangle of its parent, and classifying them all would take minutes before the next
/// level's estimate refused it.
double childGeometry(const GridSpec& coarseGrid, const GridSpec& fine, int K, const CellTriangles& coarse,
                     const std::vector<Triangle>& tris, double margin, double grow, const NodeEstimate& estimate,
                     CellTriangles& pairs) {
    pairs.clear();
    double cells = 0;  // children with geometry (a parent's children are no other parent's)
    for (std::size_t begin = 0; begin < coarse.size();) {
        std::size_t end = begin;
        while (end < coarse.size() && coarse[end].first == coarse[begin].first) ++end;
        const CellIndex p = unpack(coarseGrid, coarse[begin].first);
        for (int w = 0; w < K; ++w)
            for (int v = 0; v < K; ++v)
                for (int u = 0; u < K; ++u) {
                    const CellIndex c{p.i * K + u, p.j * K + v, p.k * K + w};
                    const Bounds box = cellTestBox(fine, c, margin, grow);
                    const std::size_t before = pairs.size();
                    for (std::size_t n = begin; n < end; ++n) {
                        const Triangle& tri = tris[coarse[n].second];
                        if (triangleOverlapsBox(tri.a, tri.b, tri.c, box))
                            pairs.emplace_back(fine.index(c.i, c.j, c.k), coarse[n].second);
                    }
                    if (pairs.size() > before && estimate.over(++cells)) return cells;
                }
        begin = end;
    }
    sortPairs(pairs);
    return 0;
}

/// Corners of the children of every refined cell: the active nodes of the finer level.
std::vector<uint64_t> childNodes(const GridSpec& coarseGrid, const GridSpec& fine, int K,
                                 const std::vector<uint64_t>& refined) {
    std::vector<uint64_t> nodes;
    nodes.reserve(refined.size() * std::size_t(K + 1) * (K + 1) * (K + 1));
    for (uint64_t cell : refined) {
        const CellIndex p = unpack(coarseGrid, cell);
        for (int w = 0; w <= K; ++w)
            for (int v = 0; v <= K; ++v)
                for (int u = 0; u <= K; ++u) nodes.push_back(fine.index(p.i * K + u, p.j * K + v, p.k * K + w));
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    return nodes;
}

std::string tooLarge(double nodes, std::size_t bytesPerNode, uint64_t limit, const char* what,
                     const char* bound = "up to") {
    std::ostringstream s;
    s << what << " would have " << bound << " " << std::fixed << std::setprecision(0) << nodes << " nodes (about "
      << std::defaultfloat << std::setprecision(4) << nodes * double(bytesPerNode) / (1024.0 * 1024.0)
      << " MiB); the limit is " << limit << " nodes (use fewer levels, a smaller --refine or a coarser first level)";
    return s.str();
}

}  // namespace

LayoutKind parseLayoutKind(const std::string& name) {
    if (name == "uniform") return LayoutKind::Uniform;
    if (name == "bilevel") return LayoutKind::Bilevel;
    if (name == "adaptive") return LayoutKind::Adaptive;
    throw ValueError("unknown layout '" + name + "' (expected uniform, bilevel or adaptive)");
}

const char* layoutName(LayoutKind kind) {
    switch (kind) {
        case LayoutKind::Uniform: return "uniform";
        case LayoutKind::Bilevel: return "bilevel";
        default: return "adaptive";
    }
}

uint64_t LevelLayout::totalNodes() const {
    uint64_t n = 0;
    for (const LevelTopology& l : levels) n += l.storedNodes();
    return n;
}

double LevelLayout::denseEquivalentNodes() const {
    return levels.empty() ? 0.0 : double(levels.back().grid.nodeCount());
}

int64_t findNode(const LevelTopology& level, uint64_t linear) {
    if (!level.sparse()) return linear < level.grid.nodeCount() ? int64_t(linear) : -1;
    const auto it = std::lower_bound(level.activeNodes.begin(), level.activeNodes.end(), linear);
    return it != level.activeNodes.end() && *it == linear ? int64_t(it - level.activeNodes.begin()) : -1;
}

bool isRefined(const LevelTopology& level, uint64_t cell) {
    return std::binary_search(level.refinedCells.begin(), level.refinedCells.end(), cell);
}

LevelLayout placeLevels(const GridSpec& level0, const std::vector<Vec3f>& positions,
                        const std::vector<uint32_t>& indices, const LevelsPlacement& p, std::size_t bytesPerNode) {
    const int K = p.refine;
    int levelCount = p.kind == LayoutKind::Uniform ? 1 : (p.kind == LayoutKind::Bilevel ? 2 : p.levels);
    if (p.kind != LayoutKind::Uniform && K < 2) throw ValueError("refinement must be at least 2, got " + std::to_string(K));
    if (levelCount < 1) throw ValueError("level count must be at least 1, got " + std::to_string(levelCount));
    if (!(p.refineDistance >= 0.0) || !std::isfinite(p.refineDistance))
        throw ValueError("refine distance must be finite and >= 0, got " + std::to_string(p.refineDistance));
    LevelLayout out;
    out.kind = p.kind;
    out.refine = levelCount > 1 ? K : 1;
    LevelTopology first;
    first.grid = level0;
    out.levels.push_back(first);
    if (levelCount == 1) return out;
    if (level0.nx < 2 || level0.ny < 2 || level0.nz < 2)
        throw ValueError("a multi-level layout needs at least 2 first-level nodes along every axis");

    // The finest level's index range must fit (int dims, 56-bit linear indices).
    double finestAxis[3] = {double(level0.nx), double(level0.ny), double(level0.nz)};
    for (int l = 1; l < levelCount; ++l)
        for (double& n : finestAxis) n = (n - 1) * K + 1;
    const double finestBox = finestAxis[0] * finestAxis[1] * finestAxis[2];
    if (!(std::max({finestAxis[0], finestAxis[1], finestAxis[2]}) < 2e9 && finestBox < 7e16)) {
        std::ostringstream s;
        s.precision(4);
        s << levelCount << " levels refined by " << K << " span " << finestBox
          << " node positions at the finest level, beyond the index range (use fewer levels or a smaller --refine)";
        throw ValueError(s.str());
    }

    std::vector<Triangle> tris(indices.size() / 3);
    for (std::size_t t = 0; t < tris.size(); ++t)
        tris[t] = {Vec3d(positions[indices[3 * t]]), Vec3d(positions[indices[3 * t + 1]]),
                   Vec3d(positions[indices[3 * t + 2]])};
    const double margin = 0.5 * level0.spacing;

    double total = double(level0.nodeCount());
    const double grow = p.refineDistance;
    CellTriangles geometry = level0Geometry(level0, tris, margin, grow);
    for (int l = 1; l < levelCount; ++l) {
        LevelTopology& coarse = out.levels.back();
        coarse.refinedCells = cellsOf(geometry);
        if (coarse.refinedCells.empty()) {
            out.hasFinestGeometry = true;  // the last level placed has no geometry
            break;
        }
        // Estimate before allocating.
        const NodeEstimate next{total, std::pow(K + 1.0, 3.0), double(p.maxNodes)};
        const double estimate = next.withCells(double(coarse.refinedCells.size()));
        if (next.over(double(coarse.refinedCells.size())))
            throw ValueError(tooLarge(estimate, bytesPerNode, p.maxNodes, "the layout"));
        LevelTopology fine;
        fine.grid.origin = level0.origin;
        fine.grid.spacing = coarse.grid.spacing / K;
        fine.grid.nx = (coarse.grid.nx - 1) * K + 1;
        fine.grid.ny = (coarse.grid.ny - 1) * K + 1;
        fine.grid.nz = (coarse.grid.nz - 1) * K + 1;
        fine.activeNodes = childNodes(coarse.grid, fine.grid, K, coarse.refinedCells);
        total += double(fine.activeNodes.size());
        const bool finest = l + 1 == levelCount;
        if (!finest || p.keepFinestGeometry) {
            // The next level's estimate is checked while its cells are found (the finest
            // level's geometry is only kept, never refined: no limit).
            const NodeEstimate after{total, next.perCell, finest ? INFINITY : double(p.maxNodes)};
            CellTriangles found;
            if (const double cells = childGeometry(coarse.grid, fine.grid, K, geometry, tris, margin, grow, after, found))
                throw ValueError(tooLarge(after.withCells(cells), bytesPerNode, p.maxNodes, "the layout", "more than"));
            geometry = std::move(found);
        }
        out.levels.push_back(std::move(fine));
        if (finest && p.keepFinestGeometry) out.finestGeometryCells = cellsOf(geometry), out.hasFinestGeometry = true;
    }
    return out;
}

}  // namespace vdblight
