// Least-squares node values over the domain of interest (node_least_squares.h): the
// 27-point Gram stencil and its Tikhonov-regularised solve by Jacobi-preconditioned CG.
#include "vdblight/node_least_squares.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "vdblight/errors.h"

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
/// y = (G + lambda I) x for one column (x, y indexed by node).
void multiply(const GridSpec& g, const std::vector<double>& entries, double lambda, const std::vector<double>& x,
              std::vector<double>& y) {
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                const std::size_t n = g.index(i, j, k);
                const double* row = &entries[n * 27];
                double sum = lambda * x[n];
                for (int dk = -1; dk <= 1; ++dk) {
                    if (k + dk < 0 || k + dk >= g.nz) continue;
                    for (int dj = -1; dj <= 1; ++dj) {
                        if (j + dj < 0 || j + dj >= g.ny) continue;
                        for (int di = -1; di <= 1; ++di) {
                            if (i + di < 0 || i + di >= g.nx) continue;
                            const double a = row[(di + 1) + 3 * (dj + 1) + 9 * (dk + 1)];
                            if (a != 0.0) sum += a * x[g.index(i + di, j + dj, k + dk)];
                        }
                    }
                }
                y[n] = sum;
            }
}

double dotProduct(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t n = 0; n < a.size(); ++n) s += a[n] * b[n];
    return s;
}
}  // namespace

std::vector<double> solveNodeLeastSquares(const NodeGram& gram, const std::vector<double>& rhs,
                                          const std::vector<double>& prior, int values, double tikhonov,
                                          LeastSquaresStats* stats) {
    const GridSpec& g = gram.grid();
    const std::size_t nodes = g.nodeCount();
    if (values <= 0) throw ValueError("the least-squares fit needs at least one value per node");
    if (rhs.size() != nodes * std::size_t(values) || prior.size() != rhs.size())
        throw ValueError("least-squares fit: " + std::to_string(rhs.size()) + " right-hand sides and " +
                         std::to_string(prior.size()) + " priors for " + std::to_string(nodes) + " nodes x " +
                         std::to_string(values) + " values");
    if (!(tikhonov >= 0) || !std::isfinite(tikhonov))
        throw ValueError("the Tikhonov weight must be finite and >= 0, got " + std::to_string(tikhonov));
    for (std::size_t q = 0; q < rhs.size(); ++q)
        if (!std::isfinite(rhs[q]) || !std::isfinite(prior[q]))
            throw ValueError("least-squares fit: non-finite input at node " + std::to_string(q / std::size_t(values)));

    double largestRow = 0;
    std::vector<double> diagonal(nodes);
    std::vector<uint8_t> free(nodes, 0);  // nodes the solve changes
    for (std::size_t n = 0; n < nodes; ++n) {
        largestRow = std::max(largestRow, gram.rowSum(n));
        diagonal[n] = gram.at(n, 0, 0, 0);
    }
    const double lambda = tikhonov * largestRow;
    for (std::size_t n = 0; n < nodes; ++n) free[n] = diagonal[n] + lambda > 0.0;

    // Nodes outside the solve (no support, no regularisation) keep their prior; their
    // couplings (zero: a node without support has a zero row and column) move nothing.
    std::vector<double> out(rhs.size());
    std::vector<double> x(nodes), b(nodes), r(nodes), z(nodes), p(nodes), ap(nodes);
    const int maxIterations = int(std::min<std::size_t>(10 * nodes + 100, 100000));
    LeastSquaresStats st;
    for (int v = 0; v < values; ++v) {
        for (std::size_t n = 0; n < nodes; ++n) {
            const double pr = prior[n * std::size_t(values) + std::size_t(v)];
            x[n] = pr;  // start from the prior: CG then solves for the (small) correction
            b[n] = free[n] ? rhs[n * std::size_t(values) + std::size_t(v)] + lambda * pr : pr;
        }
        const double bNorm = std::sqrt(dotProduct(b, b));
        multiply(g, gram.entries_, lambda, x, ap);
        for (std::size_t n = 0; n < nodes; ++n) {
            r[n] = free[n] ? b[n] - ap[n] : 0.0;
            z[n] = free[n] ? r[n] / (diagonal[n] + lambda) : 0.0;
            p[n] = z[n];
        }
        double rz = dotProduct(r, z);
        int it = 0;
        double residual = bNorm > 0 ? std::sqrt(dotProduct(r, r)) / bNorm : 0.0;
        while (residual > 1e-10 && it < maxIterations) {
            multiply(g, gram.entries_, lambda, p, ap);
            for (std::size_t n = 0; n < nodes; ++n)
                if (!free[n]) ap[n] = 0.0;
            const double pap = dotProduct(p, ap);
            if (!(pap > 0)) break;
            const double alpha = rz / pap;
            for (std::size_t n = 0; n < nodes; ++n) {
                x[n] += alpha * p[n];
                r[n] -= alpha * ap[n];
                z[n] = free[n] ? r[n] / (diagonal[n] + lambda) : 0.0;
            }
            const double rzNext = dotProduct(r, z);
            for (std::size_t n = 0; n < nodes; ++n) p[n] = z[n] + (rzNext / rz) * p[n];
            rz = rzNext;
            ++it;
            residual = std::sqrt(dotProduct(r, r)) / bNorm;
        }
        st.maxIterations = std::max(st.maxIterations, it);
        st.maxRelativeResidual = std::max(st.maxRelativeResidual, residual);
        for (std::size_t n = 0; n < nodes; ++n) out[n * std::size_t(values) + std::size_t(v)] = x[n];
    }
    if (stats) *stats = st;
    return out;
}

}  // namespace vdblight
