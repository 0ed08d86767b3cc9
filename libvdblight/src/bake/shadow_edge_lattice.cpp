// bakeShadowEdgesOnLattice (shadow_edge_lattice.h): one centre ray per node first, the full
// search only where the neighbourhood says a lookup reads its answer.

#include "shadow_edge_lattice.h"

#include <algorithm>

#include "basis/shadow_edges.h"
#include "core/grid_index.h"
#include "parallel_nodes.h"
#include "shadow_edge_search.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/volume.h"

namespace vdblight::bake_detail {

namespace {

bool isSoft(const SceneLight& l) { return l.light.kind == DirectLight::Kind::Polygon; }

/// The nodes' index box, widened by one node on every side (their neighbours), in the grid.
struct IndexBox {
    int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // inclusive
    int size(int a) const { return hi[a] - lo[a] + 1; }
    std::size_t count() const { return std::size_t(size(0)) * std::size_t(size(1)) * std::size_t(size(2)); }
    std::size_t at(int i, int j, int k) const {
        return std::size_t(i - lo[0]) + std::size_t(size(0)) * (std::size_t(j - lo[1]) + std::size_t(size(1)) * std::size_t(k - lo[2]));
    }
    core::Index3 node(std::size_t b) const {
        const core::Index3 r = core::unflatten(b, uint64_t(size(0)), uint64_t(size(1)));
        return {r.i + lo[0], r.j + lo[1], r.k + lo[2]};
    }
};

IndexBox neighbourhoodBox(const GridSpec& grid, const std::vector<std::size_t>& nodes) {
    IndexBox box;
    const int n[3] = {grid.nx, grid.ny, grid.nz};
    if (nodes.empty()) {
        for (int a = 0; a < 3; ++a) box.hi[a] = n[a] - 1;
        return box;
    }
    for (int a = 0; a < 3; ++a) box.lo[a] = n[a], box.hi[a] = -1;
    for (const std::size_t node : nodes) {
        const core::Index3 p = core::unflatten(node, uint64_t(grid.nx), uint64_t(grid.ny));
        const int q[3] = {p.i, p.j, p.k};
        for (int a = 0; a < 3; ++a) box.lo[a] = std::min(box.lo[a], q[a]), box.hi[a] = std::max(box.hi[a], q[a]);
    }
    for (int a = 0; a < 3; ++a) box.lo[a] = std::max(0, box.lo[a] - 1), box.hi[a] = std::min(n[a] - 1, box.hi[a] + 1);
    return box;
}

}  // namespace

bool edgeSearchSkippable(const GridSpec& grid, int i, int j, int k, bool soft, const std::function<bool(int, int, int)>& blocked,
                         const std::function<float(int, int, int)>& visibility) {
    const bool own = blocked(i, j, k);
    const float ownVisibility = soft ? visibility(i, j, k) : 0.0f;
    if (soft && ownVisibility != 0.0f && ownVisibility != 1.0f) return false;  // in a penumbra
    for (int c = std::max(0, k - 1); c <= std::min(grid.nz - 1, k + 1); ++c)
        for (int b = std::max(0, j - 1); b <= std::min(grid.ny - 1, j + 1); ++b)
            for (int a = std::max(0, i - 1); a <= std::min(grid.nx - 1, i + 1); ++a) {
                if (blocked(a, b, c) != own) return false;
                if (soft && visibility(a, b, c) != ownVisibility) return false;
            }
    return true;
}

EdgeLatticeRun bakeShadowEdgesOnLattice(const Scene& scene, const Tracer& tracer, const std::vector<SceneLight>& lights,
                                        VolumeLevel& level, const std::vector<std::size_t>& nodes,
                                        const std::function<float(std::size_t, std::size_t, RayCount&)>& visibilityAt, int threads,
                                        Interrupter* interrupter) {
    const GridSpec& grid = level.grid;
    const std::size_t count = lights.size();
    if (level.lightShadowEdges.size() != level.heldNodes() * count * shadow_edge::kFloatsPerLight)
        throw ValueError("the shadow edges' storage does not match the volume");
    // 1. The centre ray (and a polygon light's visibility) at the nodes and their neighbours.
    const IndexBox box = neighbourhoodBox(grid, nodes);
    std::vector<uint8_t> blocked(box.count() * count, 0);
    std::vector<float> visibility(box.count() * count, 1.0f);
    EdgeLatticeRun result;
    const ParallelRun first = forEachItemInParallel(box.count(), threads, interrupter, [&](std::size_t b, RayCount& rays) {
        const core::Index3 p = box.node(b);
        const std::size_t n = grid.index(p.i, p.j, p.k);
        const Vec3f x(grid.node(n));
        // A tile's neighbours are its own neighbours' rays too: counted once, by their tile,
        // so that the merged count is the single bake's (volume/tiles.h).
        RayCount neighbours;
        const bool own = nodes.empty() || std::binary_search(nodes.begin(), nodes.end(), n);
        RayCount& counted = own ? rays : neighbours;
        for (std::size_t l = 0; l < count; ++l) {
            blocked[b * count + l] = centreRayBlocked(tracer, lights[l], x, counted) ? 1 : 0;
            if (isSoft(lights[l])) visibility[b * count + l] = visibilityAt(n, l, counted);
        }
    });
    // 2. The search where a lookup reads it.
    const std::size_t items = nodes.empty() ? grid.nodeCount() : nodes.size();
    std::vector<uint8_t> searched(items * count, 0);
    const ParallelRun second = forEachItemInParallel(items, threads, interrupter, [&](std::size_t item, RayCount& rays) {
        const std::size_t n = nodes.empty() ? item : nodes[item];
        const core::Index3 p = core::unflatten(n, uint64_t(grid.nx), uint64_t(grid.ny));
        for (std::size_t l = 0; l < count; ++l) {
            const auto blockedAt = [&](int i, int j, int k) { return blocked[box.at(i, j, k) * count + l] != 0; };
            const auto visibilityOf = [&](int i, int j, int k) { return visibility[box.at(i, j, k) * count + l]; };
            float* out = &level.lightShadowEdges[(level.held(n) * count + l) * shadow_edge::kFloatsPerLight];
            if (lights[l].light.kind != DirectLight::Kind::Mesh &&
                edgeSearchSkippable(grid, p.i, p.j, p.k, isSoft(lights[l]), blockedAt, visibilityOf)) {
                std::fill(out, out + shadow_edge::kFloatsPerLight, 0.0f);  // no direction, no far side
                out[shadow_edge::kDistance] = blockedAt(p.i, p.j, p.k) ? -shadow_edge::kRange : shadow_edge::kRange;
                continue;
            }
            storeShadowEdge(findShadowEdge(scene, tracer, lights[l], Vec3f(grid.node(n)), grid.spacing, rays), out);
            searched[item * count + l] = 1;
        }
    });
    for (const uint8_t s : searched) (s ? result.searched : result.skipped) += 1;
    result.rays = first.rays;
    result.rays += second.rays;
    result.seconds = first.seconds + second.seconds;
    return result;
}

}  // namespace vdblight::bake_detail
