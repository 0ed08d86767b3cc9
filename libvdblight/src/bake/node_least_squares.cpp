// Least-squares node values over the domain of interest (node_least_squares.h): the
// 27-point Gram stencil and its Tikhonov-regularised solve by Jacobi-preconditioned CG.
#include "node_least_squares.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "layout/grid_neighbours.h"
#include "vdblight/core/errors.h"

namespace vdblight {

NodeGram::NodeGram(const GridSpec& grid) : grid_(grid), entries_(grid.nodeCount() * 27, 0.0) {}

void NodeGram::addCell(int ci, int cj, int ck, const double block[8][8]) {
    for (int a = 0; a < 8; ++a) {
        const int ia = ci + (a & 1), ja = cj + (a >> 1 & 1), ka = ck + (a >> 2 & 1);
        if (ia >= grid_.nx || ja >= grid_.ny || ka >= grid_.nz) continue;  // flat axis
        const std::size_t n = grid_.index(ia, ja, ka);
        for (int b = 0; b < 8; ++b) {
            const int ib = ci + (b & 1), jb = cj + (b >> 1 & 1), kb = ck + (b >> 2 & 1);
            if (ib >= grid_.nx || jb >= grid_.ny || kb >= grid_.nz) continue;
            entries_[n * 27 + slot(ib - ia, jb - ja, kb - ka)] += block[a][b];
        }
    }
}

double NodeGram::rowSum(std::size_t n) const {
    double s = 0;
    for (int q = 0; q < 27; ++q) s += entries_[n * 27 + q];
    return s;
}

namespace {
/// Y = (G + lambda I) X for all `values` columns at once (node-major, like the inputs); per
/// column the sums run in the same order as for a single column (and for any V: the bits of
/// a column do not depend on how many columns are solved with it). V > 0 is the column count
/// known at compile time (the bake's 27: the inner loops then vectorise), 0 reads `values`.
template <int VC>
void multiplyT(const GridSpec& g, const std::vector<double>& entries, double lambda, int values,
               const std::vector<double>& x, std::vector<double>& y) {
    const std::size_t V = VC > 0 ? std::size_t(VC) : std::size_t(values);
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const std::size_t n = g.index(i, j, k);
                const double* row = &entries[n * 27];
                double* __restrict out = &y[n * V];
                const double* self = &x[n * V];
                for (std::size_t v = 0; v < V; ++v) out[v] = lambda * self[v];
                forEachNodeAround(g, i, j, k, 1, [&](int a, int b, int c, int di, int dj, int dk) {
                    const double w = row[(di + 1) + 3 * (dj + 1) + 9 * (dk + 1)];
                    if (w == 0.0) return;
                    const double* __restrict in = &x[g.index(a, b, c) * V];
                    for (std::size_t v = 0; v < V; ++v) out[v] += w * in[v];
                });
            }
}

void multiply(const GridSpec& g, const std::vector<double>& entries, double lambda, int values,
              const std::vector<double>& x, std::vector<double>& y) {
    if (values == 27) multiplyT<27>(g, entries, lambda, values, x, y);
    else multiplyT<0>(g, entries, lambda, values, x, y);
}

/// Per column v: out[v] = sum over nodes of a[n, v] * b[n, v], in node order.
void columnDots(const std::vector<double>& a, const std::vector<double>& b, std::size_t V, std::vector<double>& out) {
    std::fill(out.begin(), out.end(), 0.0);
    for (std::size_t q = 0; q < a.size(); q += V)
        for (std::size_t v = 0; v < V; ++v) out[v] += a[q + v] * b[q + v];
}
}  // namespace

std::vector<double> solveNodeLeastSquares(const NodeGram& gram, const std::vector<double>& rhs,
                                          const std::vector<double>& prior, int values, double tikhonov,
                                          LeastSquaresStats* stats, double tolerance) {
    const GridSpec& g = gram.grid();
    const std::size_t nodes = g.nodeCount();
    if (values <= 0) throw ValueError("the least-squares fit needs at least one value per node");
    if (rhs.size() != nodes * std::size_t(values) || prior.size() != rhs.size())
        throw ValueError("least-squares fit: " + std::to_string(rhs.size()) + " right-hand sides and " +
                         std::to_string(prior.size()) + " priors for " + std::to_string(nodes) + " nodes x " +
                         std::to_string(values) + " values");
    if (!(tikhonov >= 0) || !std::isfinite(tikhonov))
        throw ValueError("the Tikhonov weight must be finite and >= 0, got " + std::to_string(tikhonov));
    if (!(tolerance > 0) || !std::isfinite(tolerance))
        throw ValueError("the least-squares tolerance must be finite and > 0, got " + std::to_string(tolerance));
    for (std::size_t q = 0; q < rhs.size(); ++q)
        if (!std::isfinite(rhs[q]) || !std::isfinite(prior[q]))
            throw ValueError("least-squares fit: non-finite input at node " + std::to_string(q / std::size_t(values)));

    double largestRow = 0;
    std::vector<double> diagonal(nodes);
    for (std::size_t n = 0; n < nodes; ++n) {
        largestRow = std::max(largestRow, gram.rowSum(n));
        diagonal[n] = gram.at(n, 0, 0, 0);
    }
    const double lambda = tikhonov * largestRow;
    // Nodes outside the solve (no support, no regularisation) keep their prior; their
    // couplings (zero: a node without support has a zero row and column) move nothing.
    std::vector<uint8_t> free(nodes);
    std::vector<double> inverse(nodes, 0.0);  // Jacobi preconditioner: 1 / diagonal of G + lambda I
    for (std::size_t n = 0; n < nodes; ++n) {
        free[n] = diagonal[n] + lambda > 0.0;
        if (free[n]) inverse[n] = 1.0 / (diagonal[n] + lambda);
    }

    // Jacobi-preconditioned CG, the `values` columns in lockstep (each with its own scalars;
    // a converged column stops changing). Starts from the prior: CG solves for the correction.
    const std::size_t V = std::size_t(values), size = nodes * V;
    std::vector<double> x(prior), b(size), r(size), z(size), p(size), ap(size);
    for (std::size_t n = 0; n < nodes; ++n)
        for (std::size_t v = 0; v < V; ++v) b[n * V + v] = free[n] ? rhs[n * V + v] + lambda * prior[n * V + v] : prior[n * V + v];
    std::vector<double> bNorm(V), rz(V), rzNext(V), pap(V), rr(V), residual(V);
    std::vector<int> iterations(V, 0);
    std::vector<uint8_t> active(V, 1);
    columnDots(b, b, V, bNorm);
    multiply(g, gram.entries_, lambda, values, x, ap);
    for (std::size_t n = 0; n < nodes; ++n)
        for (std::size_t v = 0; v < V; ++v) {
            const std::size_t q = n * V + v;
            r[q] = free[n] ? b[q] - ap[q] : 0.0;
            z[q] = free[n] ? r[q] * inverse[n] : 0.0;
            p[q] = z[q];
        }
    columnDots(r, z, V, rz);
    columnDots(r, r, V, rr);
    for (std::size_t v = 0; v < V; ++v) {
        bNorm[v] = std::sqrt(bNorm[v]);
        residual[v] = bNorm[v] > 0 ? std::sqrt(rr[v]) / bNorm[v] : 0.0;
        active[v] = residual[v] > tolerance;
    }
    const int maxIterations = int(std::min<std::size_t>(10 * nodes + 100, 100000));
    for (int it = 0; it < maxIterations && std::count(active.begin(), active.end(), 1) > 0; ++it) {
        multiply(g, gram.entries_, lambda, values, p, ap);
        for (std::size_t n = 0; n < nodes; ++n)
            if (!free[n])
                for (std::size_t v = 0; v < V; ++v) ap[n * V + v] = 0.0;
        columnDots(p, ap, V, pap);
        for (std::size_t v = 0; v < V; ++v)
            if (active[v] && !(pap[v] > 0)) active[v] = 0;
        for (std::size_t n = 0; n < nodes; ++n)
            for (std::size_t v = 0; v < V; ++v) {
                if (!active[v]) continue;
                const std::size_t q = n * V + v;
                const double alpha = rz[v] / pap[v];
                x[q] += alpha * p[q];
                r[q] -= alpha * ap[q];
                z[q] = free[n] ? r[q] * inverse[n] : 0.0;
            }
        columnDots(r, z, V, rzNext);
        columnDots(r, r, V, rr);
        for (std::size_t n = 0; n < nodes; ++n)
            for (std::size_t v = 0; v < V; ++v)
                if (active[v]) p[n * V + v] = z[n * V + v] + (rzNext[v] / rz[v]) * p[n * V + v];
        for (std::size_t v = 0; v < V; ++v) {
            if (!active[v]) continue;
            rz[v] = rzNext[v];
            ++iterations[v];
            residual[v] = std::sqrt(rr[v]) / bNorm[v];
            active[v] = residual[v] > tolerance;
        }
    }
    LeastSquaresStats st;
    for (std::size_t v = 0; v < V; ++v) {
        st.maxIterations = std::max(st.maxIterations, iterations[v]);
        st.maxRelativeResidual = std::max(st.maxRelativeResidual, residual[v]);
    }
    if (stats) *stats = st;
    return x;
}

}  // namespace vdblight
