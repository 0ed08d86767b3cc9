// Solid culling: connected regions of geometry-free leaf cells, classified by back-face rays.
#include "vdblight/bake/each_pass.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/union_find.h"
#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {

using Idx = core::Index3;

Idx unpack(const GridSpec& g, uint64_t linear) { return core::unflatten(linear, uint64_t(g.nx), uint64_t(g.ny)); }

bool contains(const std::vector<uint64_t>& sorted, uint64_t v) { return std::binary_search(sorted.begin(), sorted.end(), v); }

/// Cells of level l that exist: every cell of level 0; children of refined cells below.
std::vector<uint64_t> existingCells(const std::vector<LevelTopology>& levels, std::size_t l, int K) {
    std::vector<uint64_t> cells;
    const GridSpec& g = levels[l].grid;
    if (l == 0) {
        for (int k = 0; k + 1 < g.nz; ++k)
            for (int j = 0; j + 1 < g.ny; ++j)
                for (int i = 0; i + 1 < g.nx; ++i) cells.push_back(g.index(i, j, k));
        return cells;
    }
    const LevelTopology& parent = levels[l - 1];
    for (uint64_t p : parent.refinedCells) {
        const Idx c = unpack(parent.grid, p);
        for (int w = 0; w < K; ++w)
            for (int v = 0; v < K; ++v)
                for (int u = 0; u < K; ++u) cells.push_back(g.index(c.i * K + u, c.j * K + v, c.k * K + w));
    }
    std::sort(cells.begin(), cells.end());
    return cells;
}

/// True if the cell (i, j, k) of level l exists (see existingCells).
bool cellExists(const std::vector<LevelTopology>& levels, std::size_t l, int K, int i, int j, int k) {
    const GridSpec& g = levels[l].grid;
    if (i < 0 || j < 0 || k < 0 || i > g.nx - 2 || j > g.ny - 2 || k > g.nz - 2) return false;
    if (l == 0) return true;
    const LevelTopology& parent = levels[l - 1];
    return contains(parent.refinedCells, parent.grid.index(i / K, j / K, k / K));
}

using core::UnionFind;

/// Fixed spherical Fibonacci directions, tilted off the axes so that rays do not run along
/// axis-aligned walls or through mesh edges of axis-aligned quads.
std::vector<Vec3f> rayDirections(int n) {
    std::vector<Vec3f> dirs;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));
    for (int s = 0; s < n; ++s) {
        const double z = 1.0 - (2.0 * s + 1.0) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = golden * s + 0.3;
        dirs.emplace_back(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    }
    return dirs;
}

}  // namespace

std::vector<std::vector<uint64_t>> classifySolidCells(const LevelLayout& layout, const Tracer& tracer,
                                                      const SolidCullOptions& options, SolidCullStats* stats) {
    if (options.raysPerCell < 1 || options.maxCellsPerComponent < 1 || !(options.backfaceFraction > 0.0) ||
        options.backfaceFraction > 1.0)
        throw ValueError("solid culling needs at least one ray and one cell per region and a back-face fraction in (0, 1]");
    const std::vector<LevelTopology>& levels = layout.levels;
    const std::size_t L = levels.size();
    std::vector<std::vector<uint64_t>> solid(L);
    if (L < 2) return solid;
    if (!layout.hasFinestGeometry)
        throw ValueError("solid culling needs the finest level's geometry cells (LevelsPlacement::keepFinestGeometry)");
    const int K = layout.refine;

    // 1. Geometry-free leaf cells, per level (ascending), numbered consecutively.
    std::vector<std::vector<uint64_t>> leaves(L);
    std::vector<std::size_t> offset(L + 1, 0);
    SolidCullStats st;
    for (std::size_t l = 0; l < L; ++l) {
        for (uint64_t c : existingCells(levels, l, K)) {
            if (contains(levels[l].refinedCells, c)) continue;
            ++st.leafCells;
            if (l + 1 == L && contains(layout.finestGeometryCells, c)) continue;
            leaves[l].push_back(c);
        }
        offset[l + 1] = offset[l] + leaves[l].size();
    }
    st.freeLeafCells = offset[L];
    if (offset[L] >= UINT32_MAX) throw ValueError("solid culling: too many leaf cells");

    // 2. Regions: join each free leaf with the leaf just outside each of its face centres.
    UnionFind uf(offset[L]);
    const double eps = 0.25 * levels.back().grid.spacing;
    for (std::size_t l = 0; l < L; ++l) {
        const GridSpec& g = levels[l].grid;
        for (std::size_t n = 0; n < leaves[l].size(); ++n) {
            const Idx c = unpack(g, leaves[l][n]);
            const Vec3d centre = g.node(c.i, c.j, c.k) + Vec3d(0.5, 0.5, 0.5) * g.spacing;
            for (int face = 0; face < 6; ++face) {
                const int axis = face / 2;
                Vec3d p = centre;
                p[axis] += (face % 2 ? 1.0 : -1.0) * (0.5 * g.spacing + eps);
                const Bounds box = levels[0].grid.nodeBounds();
                if (!box.contains(p)) continue;
                int cell[3];
                double frac[3];
                const std::size_t m = finestCellAt(levels, K, p, cell, frac);
                const uint64_t linear = levels[m].grid.index(cell[0], cell[1], cell[2]);
                const auto it = std::lower_bound(leaves[m].begin(), leaves[m].end(), linear);
                if (it == leaves[m].end() || *it != linear) continue;  // a geometry cell
                uf.join(uint32_t(offset[l] + n), uint32_t(offset[m] + std::size_t(it - leaves[m].begin())));
            }
        }
    }
    std::vector<uint32_t> root(offset[L]);
    std::vector<std::vector<uint32_t>> members;  // per region, leaf numbers ascending
    std::vector<int64_t> regionOf(offset[L], -1);
    for (uint32_t a = 0; a < offset[L]; ++a) {
        const uint32_t r = uf.find(a);
        if (regionOf[r] < 0) regionOf[r] = int64_t(members.size()), members.emplace_back();
        members[std::size_t(regionOf[r])].push_back(a);
    }
    st.regions = members.size();

    // 3. Votes: rays from up to maxCellsPerComponent evenly spaced cells of each region.
    struct Sample {
        uint32_t region;
        Vec3f origin;
    };
    std::vector<Sample> samples;
    for (std::size_t r = 0; r < members.size(); ++r) {
        const std::vector<uint32_t>& m = members[r];
        const std::size_t count = std::min(m.size(), std::size_t(options.maxCellsPerComponent));
        for (std::size_t s = 0; s < count; ++s) {
            const uint32_t leaf = m[s * m.size() / count];
            const std::size_t l = std::size_t(std::upper_bound(offset.begin(), offset.end(), std::size_t(leaf)) - offset.begin()) - 1;
            const GridSpec& g = levels[l].grid;
            const Idx c = unpack(g, leaves[l][leaf - offset[l]]);
            samples.push_back({uint32_t(r), Vec3f(g.node(c.i, c.j, c.k) + Vec3d(0.5, 0.5, 0.5) * g.spacing)});
        }
    }
    const std::vector<Vec3f> dirs = rayDirections(options.raysPerCell);
    std::vector<int> back(samples.size(), 0), escaped(samples.size(), 0);
    tbb::parallel_for(std::size_t(0), samples.size(), [&](std::size_t s) {
        for (const Vec3f& d : dirs) {
            Ray ray;
            ray.origin = samples[s].origin;
            ray.direction = d;
            const Hit hit = tracer.intersect(ray);
            if (!hit.hit()) {
                ++escaped[s];
            } else if (dot(d, hit.geometricNormal) > 0.0f) {
                ++back[s];
            }
        }
    });
    std::vector<uint64_t> backs(members.size(), 0), rays(members.size(), 0), escapes(members.size(), 0);
    for (std::size_t s = 0; s < samples.size(); ++s) {
        backs[samples[s].region] += uint64_t(back[s]);
        escapes[samples[s].region] += uint64_t(escaped[s]);
        rays[samples[s].region] += dirs.size();
    }
    for (std::size_t r = 0; r < members.size(); ++r) {
        const bool isSolid = escapes[r] == 0 && double(backs[r]) >= options.backfaceFraction * double(rays[r]);
        if (!isSolid) continue;
        ++st.solidRegions;
        for (uint32_t leaf : members[r]) {
            const std::size_t l = std::size_t(std::upper_bound(offset.begin(), offset.end(), std::size_t(leaf)) - offset.begin()) - 1;
            solid[l].push_back(leaves[l][leaf - offset[l]]);
        }
    }
    for (auto& s : solid) {
        std::sort(s.begin(), s.end());
        st.solidCells += s.size();
    }
    if (stats) {
        stats->leafCells = st.leafCells;
        stats->freeLeafCells = st.freeLeafCells;
        stats->regions = st.regions;
        stats->solidRegions = st.solidRegions;
        stats->solidCells = st.solidCells;
    }
    return solid;
}

std::vector<uint64_t> culledNodes(const LevelLayout& layout, const std::vector<std::vector<uint64_t>>& solid,
                                  std::size_t l) {
    const std::vector<LevelTopology>& levels = layout.levels;
    const LevelTopology& level = levels.at(l);
    const GridSpec& g = level.grid;
    const int K = layout.refine;
    std::vector<uint64_t> out;
    if (solid.at(l).empty()) return out;
    const auto test = [&](uint64_t linear) {
        const Idx p = unpack(g, linear);
        bool any = false;
        for (int corner = 0; corner < 8; ++corner) {
            const int i = p.i - (corner & 1), j = p.j - ((corner >> 1) & 1), k = p.k - (corner >> 2);
            if (!cellExists(levels, l, K, i, j, k)) continue;
            if (!contains(solid[l], g.index(i, j, k))) return false;
            any = true;
        }
        return any;
    };
    if (level.sparse()) {
        for (uint64_t n : level.activeNodes)
            if (test(n)) out.push_back(n);
    } else {
        for (uint64_t n = 0; n < g.nodeCount(); ++n)
            if (test(n)) out.push_back(n);
    }
    return out;
}

uint64_t cullSolidNodes(LevelLayout& layout, const Tracer& tracer, const SolidCullOptions& options,
                        SolidCullStats* stats) {
    SolidCullStats st;
    st.nodesBefore = layout.totalNodes();
    st.culledPerLevel.assign(layout.levels.size(), 0);
    if (layout.levels.size() < 2) {
        if (stats) *stats = st;
        return 0;
    }
    const std::vector<std::vector<uint64_t>> solid = classifySolidCells(layout, tracer, options, &st);
    std::vector<std::vector<uint64_t>> culled(layout.levels.size());
    for (std::size_t l = 0; l < layout.levels.size(); ++l) culled[l] = culledNodes(layout, solid, l);
    for (std::size_t l = 0; l < layout.levels.size(); ++l) {
        if (culled[l].empty()) continue;
        LevelTopology& level = layout.levels[l];
        std::vector<uint64_t> kept;
        const auto keep = [&](uint64_t n) {
            if (!std::binary_search(culled[l].begin(), culled[l].end(), n)) kept.push_back(n);
        };
        if (level.sparse()) {
            for (uint64_t n : level.activeNodes) keep(n);
        } else {
            for (uint64_t n = 0; n < level.grid.nodeCount(); ++n) keep(n);
        }
        if (kept.empty()) throw ValueError("every node of level " + std::to_string(l) + " lies inside closed geometry");
        level.activeNodes = std::move(kept);
        st.culledPerLevel[l] = culled[l].size();
        st.nodesCulled += culled[l].size();
    }
    layout.culledNodes += st.nodesCulled;
    if (stats) *stats = st;
    return st.nodesCulled;
}

}  // namespace vdblight
