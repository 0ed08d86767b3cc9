// Least-squares fit of node values over the domain of interest (an option of the
// anti-aliased pass, bake_antialiased.h; docs/methods.md).
//
// Eq. 6 of Kontkanen & Laine divides each node's weighted sum r_i = sum_s b_i(x_s) f(x_s) by
// its lumped weight sum_s b_i(x_s). The least-squares fit instead minimises, over the same
// accepted samples, sum_s (f(x_s) - sum_k b_k(x_s) c_k)^2, i.e. the Monte Carlo estimate of
// the integral over the domain D of (f - sum_k b_k c_k)^2. Its normal equations G c = r use
// the consistent Gram ("mass") matrix G_ik = sum_s b_i(x_s) b_k(x_s), a 27-point stencil
// accumulated from 8x8 blocks per cell. A field that is trilinear over D is reproduced
// exactly; eq. 6 (G replaced by its row sums) is not.
//
// A Tikhonov term pulls every node towards a prior (the eq.-6 value, dilated where a node
// has no support): (G + lambda I) c = r + lambda prior with lambda = tikhonov * m, m the
// largest row sum of G (a node with full support). Nodes with little support in D follow the
// prior, nodes with full support barely feel it. Solved per value column by conjugate
// gradients with a Jacobi preconditioner, serially: the same bits for any thread count.
//
// Internal to the bake module (tests include it as "../libvdblight/src/bake/node_least_squares.h").
#pragma once

#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"

namespace vdblight {

/// The Gram matrix of the trilinear basis functions of a grid's nodes: for each node, its
/// coupling to the 27 nodes (di, dj, dk) in {-1, 0, 1}^3 around it.
class NodeGram {
public:
    explicit NodeGram(const GridSpec& grid);

    const GridSpec& grid() const { return grid_; }
    /// Adds the 8x8 block of cell (ci, cj, ck): block[a][b] = sum over the cell's samples of
    /// b_a b_b, corners numbered as in the anti-aliased pass (bit 0 = +x, 1 = +y, 2 = +z).
    /// Corners beyond a flat axis (one node) are skipped.
    void addCell(int ci, int cj, int ck, const double block[8][8]);
    /// Entry G(n, m) for node m = n + (di, dj, dk).
    double at(std::size_t n, int di, int dj, int dk) const { return entries_[n * 27 + slot(di, dj, dk)]; }
    /// Sum of row n (eq. 6's lumped weight of node n).
    double rowSum(std::size_t n) const;

private:
    static int slot(int di, int dj, int dk) { return (di + 1) + 3 * (dj + 1) + 9 * (dk + 1); }
    GridSpec grid_;
    std::vector<double> entries_;
    friend std::vector<double> solveNodeLeastSquares(const NodeGram&, const std::vector<double>&,
                                                     const std::vector<double>&, int, double, struct LeastSquaresStats*,
                                                     double);
};

struct LeastSquaresStats {
    int maxIterations = 0;        ///< most CG iterations any column needed
    double maxRelativeResidual = 0;  ///< largest final |A c - b| / |b| over the columns
};

/// Solves (G + lambda I) c = rhs + lambda prior, lambda = tikhonov * max_n rowSum(n), for
/// `values` columns stored node-major (rhs[n * values + v]); returns c in the same layout.
/// With tikhonov == 0 a node whose row of G is zero keeps its prior. Throws ValueError for
/// sizes that do not match the grid, tikhonov < 0, tolerance <= 0 or a non-finite input.
/// Each column's CG stops when its residual |A c - b| / |b| is at most `tolerance`.
std::vector<double> solveNodeLeastSquares(const NodeGram& gram, const std::vector<double>& rhs,
                                          const std::vector<double>& prior, int values, double tikhonov,
                                          LeastSquaresStats* stats = nullptr, double tolerance = 1e-10);

}  // namespace vdblight
