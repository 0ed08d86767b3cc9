// The least-squares node fit (node_least_squares.h) against exact answers: a field that is
// linear in space over a domain that cuts cells is reproduced exactly at every sample and at
// every fully supported node (eq. 6 is not); a constant field stays constant with any
// Tikhonov weight; unsupported nodes keep their prior; and, through the anti-aliased bake, a
// constant sky still gives pi L with the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_util.h"
#include "bake/bake_antialiased.h"
#include "vdblight/core/errors.h"
#include "../libvdblight/src/bake/node_least_squares.h"  // internal
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {
GridSpec makeGrid(int nx, int ny, int nz) {
    GridSpec g;
    g.origin = {0.1, -0.2, 0.3};
    g.spacing = 0.5;
    g.nx = nx, g.ny = ny, g.nz = nz;
    return g;
}

/// Samples of a field over the grid's cells restricted to a domain, accumulated as the
/// anti-aliased pass does: per cell the 8x8 Gram block, per node sum b_i f and sum b_i.
struct Accumulated {
    NodeGram gram;
    std::vector<double> rhs, weight;
    std::vector<Vec3d> points;  ///< the accepted sample positions
};

template <class Field, class Domain>
Accumulated accumulate(const GridSpec& g, int perCell, Field f, Domain inDomain) {
    Accumulated a{NodeGram(g), std::vector<double>(g.nodeCount(), 0.0), std::vector<double>(g.nodeCount(), 0.0), {}};
    for (int ck = 0; ck + 1 < g.nz; ++ck)
        for (int cj = 0; cj + 1 < g.ny; ++cj)
            for (int ci = 0; ci + 1 < g.nx; ++ci) {
                double block[8][8] = {};
                const Vec3d lo = g.node(ci, cj, ck);
                for (int s = 0; s < perCell; ++s) {
                    const double t[3] = {radicalInverse(2, uint32_t(s)), radicalInverse(3, uint32_t(s)),
                                         radicalInverse(5, uint32_t(s))};
                    const Vec3d x = lo + Vec3d(t[0], t[1], t[2]) * g.spacing;
                    if (!inDomain(x)) continue;
                    a.points.push_back(x);
                    double w[8];
                    for (int c = 0; c < 8; ++c) {
                        w[c] = 1.0;
                        for (int axis = 0; axis < 3; ++axis) w[c] *= (c >> axis & 1) ? t[axis] : 1.0 - t[axis];
                        const std::size_t n = g.index(ci + (c & 1), cj + (c >> 1 & 1), ck + (c >> 2 & 1));
                        a.rhs[n] += w[c] * f(x);
                        a.weight[n] += w[c];
                    }
                    for (int c = 0; c < 8; ++c)
                        for (int d = 0; d < 8; ++d) block[c][d] += w[c] * w[d];
                }
                a.gram.addCell(ci, cj, ck, block);
            }
    return a;
}

/// The trilinear interpolation of node values at x.
double interpolate(const GridSpec& g, const std::vector<double>& c, const Vec3d& x) {
    double out = 0;
    const Vec3d u = (x - g.origin) / g.spacing;
    const int i = std::min(int(u.x), g.nx - 2), j = std::min(int(u.y), g.ny - 2), k = std::min(int(u.z), g.nz - 2);
    const double t[3] = {u.x - i, u.y - j, u.z - k};
    for (int corner = 0; corner < 8; ++corner) {
        double w = 1.0;
        for (int a = 0; a < 3; ++a) w *= (corner >> a & 1) ? t[a] : 1.0 - t[a];
        out += w * c[g.index(i + (corner & 1), j + (corner >> 1 & 1), k + (corner >> 2 & 1))];
    }
    return out;
}

std::vector<double> projection(const Accumulated& a) {
    std::vector<double> c(a.rhs.size(), 0.0);
    for (std::size_t n = 0; n < c.size(); ++n) c[n] = a.weight[n] > 0 ? a.rhs[n] / a.weight[n] : 0.0;
    return c;
}
}  // namespace

TEST(NodeLeastSquares, LinearFieldOverACutDomainIsReproducedExactly) {
    const GridSpec g = makeGrid(6, 5, 4);
    const auto f = [](const Vec3d& x) { return 2.0 + 0.7 * x.x - 1.3 * x.y + 0.4 * x.z; };
    // A slanted plane cuts cells (the domain of interest ends inside them, as at a wall).
    const auto inDomain = [](const Vec3d& x) { return x.x + 0.35 * x.y - 0.2 * x.z < 1.6; };
    const Accumulated a = accumulate(g, 64, f, inDomain);
    const std::vector<double> eq6 = projection(a);
    LeastSquaresStats st;
    const std::vector<double> fit = solveNodeLeastSquares(a.gram, a.rhs, eq6, 1, 0.0, &st);
    std::printf("  %zu samples in the domain, CG %d iterations, residual %.2g\n", a.points.size(), st.maxIterations,
                st.maxRelativeResidual);
    double worstFit = 0, worstEq6 = 0;
    for (const Vec3d& x : a.points) {
        worstFit = std::max(worstFit, std::abs(interpolate(g, fit, x) - f(x)));
        worstEq6 = std::max(worstEq6, std::abs(interpolate(g, eq6, x) - f(x)));
    }
    std::printf("  largest error at the samples: least squares %.3g, eq. 6 %.3g\n", worstFit, worstEq6);
    EXPECT_LT(worstFit, 1e-8);
    EXPECT_GT(worstEq6, 0.05);  // eq. 6 averages the field over a cut support: off at the cut
    // Nodes whose whole support lies in the domain hold the field's value exactly.
    int full = 0;
    for (int k = 1; k + 1 < g.nz; ++k)
        for (int j = 1; j + 1 < g.ny; ++j)
            for (int i = 1; i + 1 < g.nx; ++i) {
                const Vec3d p = g.node(i, j, k);
                bool inside = true;
                for (int corner = 0; corner < 8; ++corner)
                    inside = inside && inDomain(p + Vec3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1) * g.spacing);
                if (!inside) continue;
                ++full;
                EXPECT_NEAR(fit[g.index(i, j, k)], f(p), 1e-8) << "node " << i << " " << j << " " << k;
            }
    EXPECT_GT(full, 3);
}

TEST(NodeLeastSquares, ConstantStaysConstantAndUnsupportedNodesKeepTheirPrior) {
    const GridSpec g = makeGrid(5, 4, 4);
    const auto inDomain = [](const Vec3d& x) { return x.x < 1.2; };  // nodes with x > 1.6 get no sample
    const Accumulated a = accumulate(g, 32, [](const Vec3d&) { return 3.25; }, inDomain);
    std::vector<double> prior = projection(a);
    std::size_t unsupported = 0;
    for (std::size_t n = 0; n < prior.size(); ++n)
        if (a.weight[n] == 0) prior[n] = 7.0 + double(n), ++unsupported;  // a dilated value, say
        else EXPECT_NEAR(prior[n], 3.25, 1e-12);
    ASSERT_GT(unsupported, 0u);
    for (double tikhonov : {0.0, 0.05, 1.0}) {
        const std::vector<double> fit = solveNodeLeastSquares(a.gram, a.rhs, prior, 1, tikhonov);
        for (std::size_t n = 0; n < fit.size(); ++n)
            EXPECT_NEAR(fit[n], a.weight[n] > 0 ? 3.25 : prior[n], 1e-9) << "node " << n << " tikhonov " << tikhonov;
    }
}

TEST(NodeLeastSquares, TikhonovPullsTowardsThePriorAndColumnsAreIndependent) {
    const GridSpec g = makeGrid(4, 4, 3);
    const auto inDomain = [](const Vec3d& x) { return x.y < 0.5; };
    const auto f = [](const Vec3d& x) { return x.x * x.x - x.y; };  // not trilinear
    const Accumulated a = accumulate(g, 32, f, inDomain);
    const std::vector<double> eq6 = projection(a);
    const std::vector<double> free = solveNodeLeastSquares(a.gram, a.rhs, eq6, 1, 0.0);
    const std::vector<double> strong = solveNodeLeastSquares(a.gram, a.rhs, eq6, 1, 1e6);
    double moved = 0;
    for (std::size_t n = 0; n < eq6.size(); ++n) {
        EXPECT_NEAR(strong[n], eq6[n], 1e-4 * (1 + std::abs(eq6[n])));
        moved = std::max(moved, std::abs(free[n] - eq6[n]));
    }
    EXPECT_GT(moved, 1e-3);
    // Two columns at once give the same as each column alone.
    std::vector<double> rhs2(2 * eq6.size()), prior2(2 * eq6.size());
    for (std::size_t n = 0; n < eq6.size(); ++n) {
        rhs2[2 * n] = a.rhs[n], rhs2[2 * n + 1] = -2 * a.rhs[n];
        prior2[2 * n] = eq6[n], prior2[2 * n + 1] = -2 * eq6[n];
    }
    const std::vector<double> both = solveNodeLeastSquares(a.gram, rhs2, prior2, 2, 0.0);
    for (std::size_t n = 0; n < eq6.size(); ++n) {
        EXPECT_EQ(both[2 * n], free[n]);
        EXPECT_NEAR(both[2 * n + 1], -2 * free[n], 1e-9 * (1 + std::abs(free[n])));
    }
}

TEST(NodeLeastSquares, ALooserToleranceStopsEarlierWithinItsResidual) {
    // The bake solves to a relative residual of 1e-6 (AntialiasedOptions::fitTolerance): fewer
    // iterations than 1e-10, a residual within the tolerance, and values that differ from the
    // tight solve by far less than the Monte Carlo noise they carry.
    const GridSpec g = makeGrid(6, 5, 4);
    const auto inDomain = [](const Vec3d& x) { return x.x + 0.35 * x.y - 0.2 * x.z < 1.6; };
    const auto f = [](const Vec3d& x) { return 1.0 + x.x * x.x - x.y * x.z; };  // not trilinear
    const Accumulated a = accumulate(g, 32, f, inDomain);
    const std::vector<double> eq6 = projection(a);
    LeastSquaresStats tight, loose;
    const std::vector<double> exact = solveNodeLeastSquares(a.gram, a.rhs, eq6, 1, 0.05, &tight, 1e-10);
    const std::vector<double> rough = solveNodeLeastSquares(a.gram, a.rhs, eq6, 1, 0.05, &loose, 1e-6);
    std::printf("  CG iterations: %d to 1e-10, %d to 1e-6\n", tight.maxIterations, loose.maxIterations);
    EXPECT_LE(tight.maxRelativeResidual, 1e-10);
    EXPECT_LE(loose.maxRelativeResidual, 1e-6);
    EXPECT_LT(loose.maxIterations, tight.maxIterations);
    double scale = 0, worst = 0;
    for (std::size_t n = 0; n < exact.size(); ++n)
        scale = std::max(scale, std::abs(exact[n])), worst = std::max(worst, std::abs(rough[n] - exact[n]));
    EXPECT_LT(worst, 1e-4 * scale);
    EXPECT_GT(worst, 0.0);  // it did stop earlier
}

TEST(NodeLeastSquares, BadInputIsRejected) {
    const GridSpec g = makeGrid(3, 3, 3);
    const NodeGram gram(g);
    const std::vector<double> ok(g.nodeCount(), 1.0), shortVec(3, 1.0);
    EXPECT_THROW(solveNodeLeastSquares(gram, shortVec, shortVec, 1, 0.0), ValueError);
    EXPECT_THROW(solveNodeLeastSquares(gram, ok, ok, 1, -1.0), ValueError);
    EXPECT_THROW(solveNodeLeastSquares(gram, ok, ok, 0, 0.0), ValueError);
    std::vector<double> nan = ok;
    nan[4] = std::nan("");
    EXPECT_THROW(solveNodeLeastSquares(gram, nan, ok, 1, 0.0), ValueError);
    for (double tolerance : {0.0, -1e-6, std::nan(""), std::numeric_limits<double>::infinity()})
        EXPECT_THROW(solveNodeLeastSquares(gram, ok, ok, 1, 0.0, nullptr, tolerance), ValueError);
}

TEST(NodeLeastSquares, ConstantSkyThroughTheBakeGivesPiLWithTheSameBitsForAnyThreadCount) {
    const Rgb L{1.0f, 0.5f, 2.0f};
    const Scene s = test::makeConstantSky(L);
    const Tracer tracer(s);
    GridSpec g = makeGrid(3, 3, 3);
    AntialiasedOptions o;
    o.raysPerCell = 1u << 14;
    o.domain = DomainMode::All;
    o.fit = NodeFit::LeastSquares;
    o.threads = 1;
    const Volume one = bakeShAntialiased(s, tracer, g, o);
    o.threads = 2;
    const Volume two = bakeShAntialiased(s, tracer, g, o);
    EXPECT_EQ(one.levels[0].data, two.levels[0].data);
    // L_0 = 2 sqrt(pi) L is in the trilinear span (a constant): the fit keeps it.
    for (std::size_t n = 0; n < g.nodeCount(); ++n)
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(one.levels[0].nodeData(n, sh::kCoeffs)[ch], 2 * std::sqrt(kPi) * L[ch], 1e-5 * L[ch]);
    const IrradianceQuery q(one);
    for (const Vec3f nrm : {Vec3f(0, 0, 1), normalize(Vec3f(1, -2, 3))}) {
        const Rgb e = q.irradiance(Vec3f(g.node(13)) + Vec3f(0.1f, 0.2f, -0.1f), nrm);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(e[ch], kPi * L[ch], 0.02 * kPi * L[ch]);
    }
    EXPECT_EQ(metaString(one.meta, "fit", ""), "least-squares (Tikhonov towards eq. 6)");
    o.tikhonov = -1;
    EXPECT_THROW(bakeShAntialiased(s, tracer, g, o), ValueError);
    o.tikhonov = 0.05;
    o.fitTolerance = 0;
    EXPECT_THROW(bakeShAntialiased(s, tracer, g, o), ValueError);
}
