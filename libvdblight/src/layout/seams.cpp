// Seam nodes: fine nodes touching a coarser cell that is not refined take the coarse
// interpolation, so that the multi-level reconstruction is continuous (C0). Here: which
// nodes are seams and where the coarse level interpolates them (topology only); the
// values are written by applySeamConstraints (volume/seam_constraints.cpp).
#include <cmath>

#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {

using Node = core::Index3;

Node unpackNode(const GridSpec& g, uint64_t linear) { return core::unflatten(linear, uint64_t(g.nx), uint64_t(g.ny)); }

/// Coarse cell indices along one axis whose closed extent contains fine index p.
int coarseCandidates(int p, int K, int coarseCells, int out[2]) {
    int n = 0;
    const int c = p / K;
    if (p % K != 0) {
        out[n++] = c;
    } else {
        if (c - 1 >= 0) out[n++] = c - 1;
        if (c < coarseCells) out[n++] = c;
    }
    return n;
}

/// Visits the coarse cells (lower-corner linear index) containing fine node p; stops early
/// when `visit` returns false.
template <typename F>
void forCoarseCells(const GridSpec& coarse, int K, const Node& p, F visit) {
    int ci[2], cj[2], ck[2];
    const int ni = coarseCandidates(p.i, K, coarse.nx - 1, ci);
    const int nj = coarseCandidates(p.j, K, coarse.ny - 1, cj);
    const int nk = coarseCandidates(p.k, K, coarse.nz - 1, ck);
    for (int c = 0; c < nk; ++c)
        for (int b = 0; b < nj; ++b)
            for (int a = 0; a < ni; ++a)
                if (!visit(Node{ci[a], cj[b], ck[c]})) return;
}

}  // namespace

std::vector<std::size_t> seamNodes(const LevelTopology& coarse, const LevelTopology& fine, int K) {
    std::vector<std::size_t> seams;
    for (std::size_t n = 0; n < fine.activeNodes.size(); ++n) {
        const Node p = unpackNode(fine.grid, fine.activeNodes[n]);
        bool seam = false;
        forCoarseCells(coarse.grid, K, p, [&](const Node& c) {
            seam = !isRefined(coarse, coarse.grid.index(c.i, c.j, c.k));
            return !seam;
        });
        if (seam) seams.push_back(n);
    }
    return seams;
}

std::vector<SeamStencil> seamStencils(const LevelTopology& coarse, const LevelTopology& fine, int K, int level) {
    std::vector<SeamStencil> out;
    for (std::size_t n : seamNodes(coarse, fine, K)) {
        const Node p = unpackNode(fine.grid, fine.activeNodes[n]);
        // A refined coarse cell containing p: all its corners exist on the coarse level.
        Node cell{-1, -1, -1};
        forCoarseCells(coarse.grid, K, p, [&](const Node& c) {
            if (!isRefined(coarse, coarse.grid.index(c.i, c.j, c.k))) return true;
            cell = c;
            return false;
        });
        if (cell.i < 0) throw FormatError("level " + std::to_string(level) + " has a node outside every refined cell");
        out.push_back({n,
                       {cell.i, cell.j, cell.k},
                       {double(p.i - K * cell.i) / K, double(p.j - K * cell.j) / K, double(p.k - K * cell.k) / K}});
    }
    return out;
}

}  // namespace vdblight
