// Consistency of a multi-level volume's structure (docs/format.md, "Levels").
#include <algorithm>
#include <cmath>

#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

namespace {

std::string levelName(std::size_t l) { return "level " + std::to_string(l); }

bool strictlyAscending(const std::vector<uint64_t>& v) {
    for (std::size_t i = 1; i < v.size(); ++i)
        if (v[i - 1] >= v[i]) return false;
    return true;
}

void unpack(const GridSpec& g, uint64_t linear, int& i, int& j, int& k) {
    const core::Index3 c = core::unflatten(linear, uint64_t(g.nx), uint64_t(g.ny));
    i = c.i, j = c.j, k = c.k;
}

void checkGeometry(const GridSpec& g0, const GridSpec& coarse, const GridSpec& fine, int K, std::size_t l) {
    const double ratio = coarse.spacing / fine.spacing;
    if (std::abs(ratio - K) > 1e-9 * K) {
        throw FormatError(levelName(l) + " has spacing " + std::to_string(fine.spacing) + ", expected " +
                          levelName(l - 1) + "'s spacing / " + std::to_string(K));
    }
    const double tol = 1e-9 * (g0.spacing + std::max({std::abs(g0.origin.x), std::abs(g0.origin.y), std::abs(g0.origin.z)}));
    for (int a = 0; a < 3; ++a)
        if (std::abs(fine.origin[a] - g0.origin[a]) > tol)
            throw FormatError(levelName(l) + " has an origin different from level 0's (mismatched transforms)");
    const int64_t want[3] = {int64_t(coarse.nx - 1) * K + 1, int64_t(coarse.ny - 1) * K + 1, int64_t(coarse.nz - 1) * K + 1};
    if (fine.nx != want[0] || fine.ny != want[1] || fine.nz != want[2]) {
        throw FormatError(levelName(l) + " has dims " + std::to_string(fine.nx) + "x" + std::to_string(fine.ny) + "x" +
                          std::to_string(fine.nz) + ", expected " + std::to_string(want[0]) + "x" +
                          std::to_string(want[1]) + "x" + std::to_string(want[2]));
    }
}

void checkRefinedCells(const std::vector<VolumeLevel>& levels, std::size_t l, int K) {
    const VolumeLevel& level = levels[l];
    const GridSpec& g = level.grid;
    if (!strictlyAscending(level.refinedCells))
        throw FormatError(levelName(l) + " lists its refined cells out of order or twice");
    for (uint64_t cell : level.refinedCells) {
        int i, j, k;
        unpack(g, cell, i, j, k);
        if (cell >= g.nodeCount() || i > g.nx - 2 || j > g.ny - 2 || k > g.nz - 2)
            throw FormatError(levelName(l) + " marks a refined cell outside its cell range");
        if (l > 0) {
            const VolumeLevel& parent = levels[l - 1];
            const uint64_t p = parent.grid.index(i / K, j / K, k / K);
            if (!std::binary_search(parent.refinedCells.begin(), parent.refinedCells.end(), p))
                throw FormatError(levelName(l) + " marks a refined cell whose parent cell is not refined");
        }
    }
}

/// Culled volumes (metadata culling = solid-regions): level l's active nodes are a subset of
/// the full set (the box for level 0, the corners of the children of level l-1's refined
/// cells below) that holds every corner of level l's own refined cells.
void checkCulledNodes(const std::vector<VolumeLevel>& levels, std::size_t l, int K) {
    const VolumeLevel& level = levels[l];
    const GridSpec& g = level.grid;
    if (!level.sparse()) return;  // dense level 0: nothing culled there
    if (!strictlyAscending(level.activeNodes))
        throw FormatError(levelName(l) + " lists its active nodes out of order or twice");
    if (level.activeNodes.back() >= g.nodeCount()) throw FormatError(levelName(l) + " has active nodes outside its box");
    for (uint64_t node : level.activeNodes) {
        if (l == 0) break;
        int i, j, k;
        unpack(g, node, i, j, k);
        bool inChild = false;  // node is a corner of a child of a refined cell of level l-1
        const VolumeLevel& parent = levels[l - 1];
        for (int c = 0; c < 8 && !inChild; ++c) {
            const int ci = (i - (c & 1)) / K, cj = (j - ((c >> 1) & 1)) / K, ck = (k - (c >> 2)) / K;
            if (i - (c & 1) < 0 || j - ((c >> 1) & 1) < 0 || k - (c >> 2) < 0) continue;
            if (ci > parent.grid.nx - 2 || cj > parent.grid.ny - 2 || ck > parent.grid.nz - 2) continue;
            inChild = std::binary_search(parent.refinedCells.begin(), parent.refinedCells.end(), parent.grid.index(ci, cj, ck));
        }
        if (!inChild) throw FormatError(levelName(l) + " has an active node outside every refined cell of " + levelName(l - 1));
    }
    for (uint64_t cell : level.refinedCells) {
        int i, j, k;
        unpack(g, cell, i, j, k);
        for (int c = 0; c < 8; ++c)
            if (!std::binary_search(level.activeNodes.begin(), level.activeNodes.end(),
                                    g.index(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2))))
                throw FormatError(levelName(l) + " misses a corner of one of its refined cells (culled nodes must not touch refined cells)");
    }
}

/// Active nodes of level l must be exactly the corners of the children of level l-1's refined cells.
void checkActiveNodes(const std::vector<VolumeLevel>& levels, std::size_t l, int K) {
    const VolumeLevel& coarse = levels[l - 1];
    const VolumeLevel& fine = levels[l];
    if (!strictlyAscending(fine.activeNodes))
        throw FormatError(levelName(l) + " lists its active nodes out of order or twice");
    std::vector<uint64_t> want;
    for (uint64_t cell : coarse.refinedCells) {
        int i, j, k;
        unpack(coarse.grid, cell, i, j, k);
        for (int w = 0; w <= K; ++w)
            for (int v = 0; v <= K; ++v)
                for (int u = 0; u <= K; ++u) want.push_back(fine.grid.index(i * K + u, j * K + v, k * K + w));
    }
    std::sort(want.begin(), want.end());
    want.erase(std::unique(want.begin(), want.end()), want.end());
    if (want != fine.activeNodes) {
        throw FormatError(levelName(l) + " has " + std::to_string(fine.activeNodes.size()) +
                          " active nodes, but the refined cells of " + levelName(l - 1) + " need exactly " +
                          std::to_string(want.size()) + " (mask and nodes disagree)");
    }
}

}  // namespace

void validateLevelStructure(const Volume& volume) {
    const std::vector<VolumeLevel>& levels = volume.levels;
    if (levels.empty()) return;
    const bool culled = levels.size() > 1 && metaString(volume.meta, "culling") == "solid-regions";
    if (levels[0].sparse() && !culled)
        throw FormatError("level 0 must be dense (every node of its box active) unless a multi-level volume is culled");
    if (levels.size() == 1) {
        if (!levels[0].refinedCells.empty()) throw FormatError("a single-level volume has refined cells but no level 1");
        return;
    }
    const GridSpec& g0 = levels[0].grid;
    if (g0.nx < 2 || g0.ny < 2 || g0.nz < 2)
        throw FormatError("a multi-level volume needs at least 2 level-0 nodes along every axis");
    const int K = volume.refineFactor();
    if (K < 2) throw FormatError("level 1's spacing is not level 0's divided by an integer >= 2");
    for (std::size_t l = 1; l < levels.size(); ++l) {
        checkGeometry(g0, levels[l - 1].grid, levels[l].grid, K, l);
        if (!levels[l].sparse()) throw FormatError(levelName(l) + " has no active nodes");
        if (levels[l - 1].refinedCells.empty())
            throw FormatError(levelName(l - 1) + " has no refined cells (missing mask) but " + levelName(l) + " exists");
    }
    for (std::size_t l = 0; l < levels.size(); ++l) checkRefinedCells(levels, l, K);
    if (!levels.back().refinedCells.empty())
        throw FormatError("the finest level (" + levelName(levels.size() - 1) + ") has refined cells");
    for (std::size_t l = culled ? 0 : 1; l < levels.size(); ++l) {
        if (culled) checkCulledNodes(levels, l, K);
        else checkActiveNodes(levels, l, K);
    }
}

}  // namespace vdblight
