// Multi-bounce transfer (beyond the paper's single bounce, section 4.3.2 iterated).
//
// F is the sample-to-sample form-factor matrix with ray-traced visibility: F[r][j] is the
// irradiance at receiver r per unit radiance leaving sender j (diskTransfer, 0 if the pair
// does not see each other). With A = diag(albedo / pi) per colour channel, a direct
// irradiance vector u gives the bounces E_1 = F A u, E_b = F A E_(b-1). The bake applies
// this to every sender cluster's basis vectors at once (columns of U, one per (cluster, k)):
//   samples:  T = E_1 + ... + E_N                    (irradiance at receivers)
//   volume:   V = G A (U + E_1 + ... + E_(N-1))      (SH radiance at nodes)
// where G[(node, m)][j] = solid angle of sender j from the node * Y_m(direction), with
// visibility. Products are float GEMMs (Eigen) over fixed row blocks, so the result does
// not depend on the thread count.
// With sampled form factors (formFactorRays > 0, sampled_form_factors.cpp) F and G are
// sparse rows estimated by rays from each receiver; the same iteration runs with
// sparse x dense products, so the paper's 45 k samples need n * rays entries, not n^2.
#include <Eigen/Dense>
#include <cmath>

#include "pca.h"
#include "prt_internal.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "basis/sh.h"

namespace vdblight {

using namespace prt_detail;

namespace {

using MatF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MapF = Eigen::Map<const MatF>;
constexpr std::size_t kRowBlock = 64;   ///< rows of F per GEMM task (fixed: thread-count independent)
constexpr std::size_t kNodeBlock = 8;   ///< volume nodes per GEMM task
constexpr float kMaxClosureScale = 4.0f;  ///< cap on the closure normalisation of a row

/// out[c] = F * in[c] for the three channels, in fixed row blocks on `threads` threads.
void multiplyF(const std::vector<float>& F, std::size_t n, const MatF in[3], MatF out[3], int threads) {
    const MapF f(F.data(), Eigen::Index(n), Eigen::Index(n));
    for (int c = 0; c < 3; ++c) out[c].resize(in[c].rows(), in[c].cols());
    const std::size_t blocks = (n + kRowBlock - 1) / kRowBlock;
    parallelFor(blocks * 3, threads, [&](std::size_t t) {
        const int c = int(t % 3);
        const std::size_t r0 = (t / 3) * kRowBlock, len = std::min(kRowBlock, n - r0);
        out[c].middleRows(Eigen::Index(r0), Eigen::Index(len)).noalias() =
            f.middleRows(Eigen::Index(r0), Eigen::Index(len)) * in[c];
    });
}

/// out[c] = F * in[c] for a sparse F (width 1), in fixed row blocks: every output row is
/// summed in column order, so the bits do not depend on the thread count.
void multiplySparse(const SparseRows& F, const MatF in[3], MatF out[3], int threads) {
    const std::size_t n = F.rows();
    for (int c = 0; c < 3; ++c) out[c].resize(in[c].rows(), in[c].cols());
    const std::size_t blocks = (n + kRowBlock - 1) / kRowBlock;
    parallelFor(blocks * 3, threads, [&](std::size_t t) {
        const int c = int(t % 3);
        const std::size_t r0 = (t / 3) * kRowBlock, r1 = std::min(n, r0 + kRowBlock);
        for (std::size_t r = r0; r < r1; ++r) {
            auto row = out[c].row(Eigen::Index(r));
            row.setZero();
            for (std::size_t k = F.begin[r]; k < F.begin[r + 1]; ++k)
                row.noalias() += F.weight[k] * in[c].row(Eigen::Index(F.column[k]));
        }
    });
}

/// Scales row j of each channel by albedo_j / pi.
void applyAlbedo(const SurfaceSamples& s, MatF m[3]) {
    for (std::size_t j = 0; j < s.size(); ++j) {
        const Rgb a = s.albedo[j] * float(kInvPi);
        m[0].row(Eigen::Index(j)) *= a.x;
        m[1].row(Eigen::Index(j)) *= a.y;
        m[2].row(Eigen::Index(j)) *= a.z;
    }
}

}  // namespace

bool pairVisible(const SurfaceSamples& s, const Tracer& tracer, std::size_t a, std::size_t b) {
    if (a > b) std::swap(a, b);  // one canonical ray per pair: F is reciprocal
    return visibleBetween(tracer, s.position[a], s.normal[a], s.position[b], s.normal[b]);
}

namespace {

constexpr int kClosureGrid = 16;  ///< 256 equal-area directions per hemisphere for closure()

/// Cosine-weighted (cosine: true) or uniform fraction of the hemisphere around n at p whose
/// rays hit the scene, over the fixed equal-area direction grid.
float closure(const Tracer& tracer, const Vec3f& p, const Vec3f& n, bool offset, bool cosine) {
    Vec3f t1, t2;
    orthonormalBasis(n, t1, t2);
    double hit = 0, total = 0;
    for (int t = 0; t < kClosureGrid * kClosureGrid; ++t) {
        const Vec3f l = visibilityDirection(kClosureGrid, t);
        const Vec3f w = t1 * l.x + t2 * l.y + n * l.z;
        const double weight = cosine ? l.z : 1.0;
        total += weight;
        if (tracer.occluded(Ray{offset ? offsetRayOrigin(p, n, w) : p, w})) hit += weight;
    }
    return float(hit / total);
}

}  // namespace

float sampleClosure(const Tracer& tracer, const Vec3f& p, const Vec3f& n) { return closure(tracer, p, n, true, true); }

float nodeClosure(const Tracer& tracer, const Vec3f& x) {
    return 0.5f * (closure(tracer, x, Vec3f{0, 0, 1}, false, false) + closure(tracer, x, Vec3f{0, 0, -1}, false, false));
}

std::vector<float> sampleFormFactors(const SurfaceSamples& s, const Tracer& tracer, int threads,
                                     Interrupter* interrupter, bool normalise) {
    const std::size_t n = s.size();
    if (double(n) * double(n) * 4.0 > 8e9) {  // as the bake's budget (bake_prt.cpp)
        throw ValueError("the sample-pair form-factor matrix would take " +
                         std::to_string(uint64_t(double(n) * double(n) * 4.0 / 1e6)) + " MB for " + std::to_string(n) +
                         " samples");
    }
    std::vector<float> F(n * n, 0.0f);
    core::TaskProgress progress(interrupter, "PRT bake cancelled");  // the caller starts and ends the task
    // Row r traces the pairs (r, j > r) and writes both F[r][j] and F[j][r]: every entry has
    // exactly one writer.
    parallelFor(n, threads, [&](std::size_t r) {
        for (std::size_t j = r + 1; j < n; ++j) {
            const float frj = diskTransfer(s.position[r], s.normal[r], s.position[j], s.normal[j], s.area[j]);
            const float fjr = diskTransfer(s.position[j], s.normal[j], s.position[r], s.normal[r], s.area[r]);
            if (frj <= 0.0f && fjr <= 0.0f) continue;
            if (!pairVisible(s, tracer, r, j)) continue;
            F[r * n + j] = frj;
            F[j * n + r] = fjr;
        }
    }, &progress);
    if (normalise) {
        parallelFor(n, threads, [&](std::size_t r) {
            double sum = 0;
            for (std::size_t j = 0; j < n; ++j) sum += F[r * n + j];
            if (sum <= 0) return;
            const float scale = std::min(kMaxClosureScale, float(kPi * sampleClosure(tracer, s.position[r], s.normal[r]) / sum));
            for (std::size_t j = 0; j < n; ++j) F[r * n + j] *= scale;
        });
    }
    return F;
}

std::vector<Rgb> bounceIndirect(const SurfaceSamples& s, const std::vector<float>& F, const std::vector<Rgb>& direct,
                                int bounces, std::vector<Rgb>* senderIrradiance) {
    const std::size_t n = s.size();
    if (direct.size() != n || F.size() != n * n) throw ValueError("bounceIndirect: size mismatch");
    if (bounces < 1) throw ValueError("bounces must be at least 1");
    std::vector<Rgbd> cur(n), total(n, Rgbd{0, 0, 0}), next(n);
    for (std::size_t i = 0; i < n; ++i) cur[i] = Rgbd(direct[i]);
    if (senderIrradiance) *senderIrradiance = direct;
    for (int b = 1; b <= bounces; ++b) {
        for (std::size_t r = 0; r < n; ++r) {
            Rgbd acc{0, 0, 0};
            const float* row = F.data() + r * n;
            for (std::size_t j = 0; j < n; ++j) {
                if (row[j] == 0.0f) continue;
                const Rgbd a = Rgbd(s.albedo[j]) * (double(row[j]) * kInvPi);
                acc += Rgbd{a.x * cur[j].x, a.y * cur[j].y, a.z * cur[j].z};
            }
            next[r] = acc;
        }
        cur.swap(next);
        for (std::size_t r = 0; r < n; ++r) total[r] += cur[r];
        if (senderIrradiance && b < bounces)
            for (std::size_t r = 0; r < n; ++r) (*senderIrradiance)[r] += Rgb(cur[r]);
    }
    std::vector<Rgb> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = Rgb(total[i]);
    return out;
}

namespace {

/// The volume part of bakeMultiBounceTransfer with sampled form factors: per node, the SH
/// gather of the senders its rays found (sampledNodeGather) times their rows of Y.
template <typename Store>
void gatherSampledVolume(const PrtData& prt, const Tracer& tracer, const MatF Y[3], uint32_t rays, bool normalise,
                         uint64_t seed, int threads, Interrupter* in, const Store& store) {
    const std::size_t nodes = prt.volumeGrid.nodeCount();
    std::vector<Vec3f> x(nodes);
    for (std::size_t a = 0; a < nodes; ++a) x[a] = Vec3f(prt.volumeGrid.node(a));
    if (in) in->start("volume gather", nodes);
    const SparseRows G = sampledNodeGather(prt.samples, tracer, x, rays, normalise, seed, threads, in);
    if (in) in->end();
    parallelFor(nodes, threads, [&](std::size_t a) {
        const std::size_t b = G.begin[a], e = G.begin[a + 1], found = e - b;
        MatF g(sh::kCoeffs, Eigen::Index(found)), rows(Eigen::Index(found), Y[0].cols()), V[3];
        for (std::size_t k = 0; k < found; ++k)
            for (int m = 0; m < sh::kCoeffs; ++m) g(m, Eigen::Index(k)) = G.weight[(b + k) * sh::kCoeffs + std::size_t(m)];
        for (int c = 0; c < 3; ++c) {
            for (std::size_t k = 0; k < found; ++k) rows.row(Eigen::Index(k)) = Y[c].row(Eigen::Index(G.column[b + k]));
            V[c].noalias() = g * rows;
        }
        store(a, 1, V);
    });
}

}  // namespace

void bakeMultiBounceTransfer(PrtData& prt, const Tracer& tracer, int bounces, bool volume, bool normalise,
                             uint32_t formFactorRays, uint64_t seed, int threads, Interrupter* in) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t n = s.size(), clusters = s.clusters();
    const int stride = prt.transferStride;
    const std::size_t cols = clusters * std::size_t(stride);
    const bool sampled = formFactorRays > 0;
    if (in) in->start("transfer", n);
    const std::vector<float> F = sampled ? std::vector<float>() : sampleFormFactors(s, tracer, threads, in, normalise);
    const SparseRows Fs = sampled ? sampledSampleFormFactors(s, tracer, formFactorRays, normalise, seed, threads, in)
                                  : SparseRows();
    if (in) in->end();

    // U: column (c, k) = basis vector k of cluster c (k = 0: the mean), zero outside cluster c.
    MatF U = MatF::Zero(Eigen::Index(n), Eigen::Index(cols));
    for (std::size_t c = 0; c < clusters; ++c) {
        const PcaBasis& basis = prt.lightBasis[c];
        const uint32_t b = s.clusterBegin[c], e = s.clusterBegin[c + 1];
        const std::size_t nc = e - b;
        for (uint32_t j = b; j < e; ++j) {
            const std::size_t lj = j - b;
            U(Eigen::Index(j), Eigen::Index(c * std::size_t(stride))) = basis.mean[lj];
            for (int k = 1; k < stride; ++k)
                if (k - 1 < basis.count)
                    U(Eigen::Index(j), Eigen::Index(c * std::size_t(stride) + std::size_t(k))) =
                        basis.vectors[std::size_t(k - 1) * nc + lj];
        }
    }
    MatF X[3] = {U, U, U}, E[3], T[3], Y[3] = {U, U, U};
    for (int c = 0; c < 3; ++c) T[c] = MatF::Zero(U.rows(), U.cols());
    for (int b = 1; b <= bounces; ++b) {
        applyAlbedo(s, X);
        if (sampled)
            multiplySparse(Fs, X, E, threads);
        else
            multiplyF(F, n, X, E, threads);
        for (int c = 0; c < 3; ++c) {
            T[c] += E[c];
            if (b < bounces) Y[c] += E[c];
            X[c] = E[c];
        }
    }
    prt.transfer.assign(clusters, std::vector<Rgb>(std::size_t(stride) * n, Rgb{0, 0, 0}));
    for (std::size_t c = 0; c < clusters; ++c)
        for (int k = 0; k < stride; ++k) {
            const Eigen::Index col = Eigen::Index(c * std::size_t(stride) + std::size_t(k));
            for (std::size_t r = 0; r < n; ++r)
                prt.transfer[c][std::size_t(k) * n + r] =
                    Rgb{T[0](Eigen::Index(r), col), T[1](Eigen::Index(r), col), T[2](Eigen::Index(r), col)};
        }
    if (!volume) return;

    // Volume nodes: sender radiance A (U + E_1 + ... + E_(N-1)), gathered by G.
    applyAlbedo(s, Y);
    const std::size_t nodes = prt.volumeGrid.nodeCount();
    prt.volumeTransfer.assign(clusters, std::vector<Rgb>(std::size_t(stride) * nodes * sh::kCoeffs, Rgb{0, 0, 0}));
    // Rows a * 9 + m of V[c] (SH coefficient m of node n0 + a, all columns) into the transfer.
    const auto store = [&](std::size_t n0, std::size_t count, const MatF V[3]) {
        for (std::size_t a = 0; a < count; ++a)
            for (std::size_t cl = 0; cl < clusters; ++cl)
                for (int k = 0; k < stride; ++k) {
                    const Eigen::Index col = Eigen::Index(cl * std::size_t(stride) + std::size_t(k));
                    for (int m = 0; m < sh::kCoeffs; ++m) {
                        const Eigen::Index row = Eigen::Index(a * sh::kCoeffs + std::size_t(m));
                        prt.volumeTransfer[cl][(std::size_t(k) * nodes + n0 + a) * sh::kCoeffs + std::size_t(m)] =
                            Rgb{V[0](row, col), V[1](row, col), V[2](row, col)};
                    }
                }
    };
    if (sampled) {
        gatherSampledVolume(prt, tracer, Y, formFactorRays, normalise, seed, threads, in, store);
        return;
    }
    const std::size_t blocks = (nodes + kNodeBlock - 1) / kNodeBlock;
    core::TaskProgress progress(in, "volume transfer", blocks, "PRT bake cancelled");
    parallelFor(blocks, threads, [&](std::size_t blk) {
        const std::size_t n0 = blk * kNodeBlock, count = std::min(kNodeBlock, nodes - n0);
        MatF G = MatF::Zero(Eigen::Index(count * sh::kCoeffs), Eigen::Index(n));
        float y[sh::kCoeffs];
        for (std::size_t a = 0; a < count; ++a) {
            const Vec3f x(prt.volumeGrid.node(n0 + a));
            double covered = 0;
            for (std::size_t j = 0; j < n; ++j) {
                float omega;
                if (!senderShFromNode(s, tracer, x, j, y, omega)) continue;
                covered += omega;
                for (int m = 0; m < sh::kCoeffs; ++m)
                    G(Eigen::Index(a * sh::kCoeffs + std::size_t(m)), Eigen::Index(j)) = y[m];
            }
            if (normalise && covered > 0) {
                const float scale = std::min(kMaxClosureScale, float(4.0 * kPi * nodeClosure(tracer, x) / covered));
                G.middleRows(Eigen::Index(a * sh::kCoeffs), sh::kCoeffs) *= scale;
            }
        }
        MatF V[3];
        for (int c = 0; c < 3; ++c) V[c].noalias() = G * Y[c];
        store(n0, count, V);
    }, &progress);
}

}  // namespace vdblight
