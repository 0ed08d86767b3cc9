// vdblight_bench_accuracy --probe-study R0: where the probe pass's bias comes from.
#include "accuracy.h"

#include <cstring>

#include <tbb/parallel_for.h>

#include "../libvdblight/src/bake/surface_cache.h"  // the probe pass's own cache
#include "vdblight/bake/each_pass.h"
#include "vdblight/light/light.h"

namespace vdblight::accuracy {

// ---------------------------------------------------------------------------------------
// --probe-study R0: where the probe pass's bias comes from (issue 15). The probe pass ends a
// node's paths at their first hit p with a surface cache: the irradiance of pass 0's reflected
// light at p. Here the probe estimator runs at each point itself (K cosine-sampled directions,
// no SH at the point, no interpolation of the result) with the cache replaced in turn by:
//   library   the library's cache (bake/surface_cache.h) of pass 0 at R0 rays per node;
//   nodes     the same nodes, weights and visibility tests, each node's stored light replaced by
//             its exact reflected irradiance for the normal (M cosine-sampled paths from the node);
//   exact     the exact reflected irradiance at p itself (M paths from p): an unbiased cache,
//             so this is path tracing and checks the estimator's own bookkeeping;
// and without a cache (plain paths). library - nodes = how the cache represents a node's light
// (SH order 2 before issue 15's fourth session); nodes - exact = the nodes standing for p
// (their positions, weights); exact - truth = the rest.

namespace {
enum class CacheKind { NodesExact, Exact };

/// The exact variants of the library's cache (above), with its lookup's node weights and tests.
class StudyCache : public SurfaceIrradianceCache {
public:
    StudyCache(const Tracer& tracer, const RadianceEstimator& plain, const GridSpec& grid, CacheKind kind, int paths)
        : tracer_(tracer), plain_(plain), grid_(grid), kind_(kind), paths_(paths) {}

    bool irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const override {
        Rng rng(hashOf(p, n), 9);
        if (kind_ == CacheKind::Exact) {
            out = exactReflected(p, n, rng, rays);
            return true;
        }
        Rgb sum{0, 0, 0};
        const float weight = bake_detail::forEachVisibleNode(tracer_, grid_, p, n, rays, [&](std::size_t, const Vec3f& node, float w) {
            sum += exactReflected(node, n, rng, rays) * w;
        });
        if (!(weight > 0)) return false;
        out = sum / weight;
        out = Rgb(std::max(0.0f, out.x), std::max(0.0f, out.y), std::max(0.0f, out.z));
        return true;
    }

private:
    static uint64_t hashOf(const Vec3f& p, const Vec3f& n) {
        uint64_t h = 0x9b;
        for (int k = 0; k < 3; ++k) {
            uint32_t a, b;
            const float pk = p[k], nk = n[k];
            std::memcpy(&a, &pk, 4);
            std::memcpy(&b, &nk, 4);
            h = hashCombine(hashCombine(h, a), b);
        }
        return h;
    }
    /// Irradiance of reflected light and sky at q for normal n (emission seen directly left
    /// out): `paths_` cosine-sampled full paths.
    Rgb exactReflected(const Vec3f& q, const Vec3f& n, Rng& rng, RayCount& rays) const {
        Vec3f t, b;
        orthonormalBasis(n, t, b);
        Rgb sum{0, 0, 0};
        for (int i = 0; i < paths_; ++i) {
            const Vec3f l = cosineHemisphere(rng.uniform(), rng.uniform());
            const Vec3f dir = t * l.x + b * l.y + n * l.z;
            Rgb emitted;
            const Rgb r = plain_.gatherRadiance(q, dir, l.z * float(kInvPi), rng, rays, nullptr, &emitted);
            sum += r - emitted;
        }
        return sum * float(kPi / paths_);
    }
    const Tracer& tracer_;
    const RadianceEstimator& plain_;
    GridSpec grid_;
    CacheKind kind_;
    int paths_;
};
}  // namespace

void probeCacheStudy(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
                     const Settings& st, uint32_t passZeroRays, uint32_t pointRays, int paths) {
    const Scene& s = as.scene;
    const double t0 = bench::now();
    const DefaultPlan dp = defaultPlan(s, tracer, st);
    const GridSpec& grid = dp.grid;
    const TransportOptions& tr = dp.transport;
    // Pass 0 of the default's probe pass: stage 0 of a staged bake holds its reflected SH.
    GatherOptions g;
    g.raysPerNode = passZeroRays;
    g.seed = 1;
    g.threads = st.threads;
    g.transport = tr;
    g.probePasses = 1;
    g.stage = 0;
    const Volume stage0 = bakeShGather(s, tracer, grid, g);
    std::printf("  probe cache study (grid %d x %d x %d, spacing %.3f; pass 0 at %u rays: %.1f s; %u cosine samples per point, "
                "%d paths per exact value)\n", grid.nx, grid.ny, grid.nz, grid.spacing, passZeroRays, bench::now() - t0, pointRays,
                paths);
    const RadianceEstimator plain(s, tracer, tr);
    const std::size_t np = pts.x.size();
    std::vector<double> direct(np);
    tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) { direct[i] = luminance(exactDirectAt(s, tracer, dp, pts, i)); });
    struct Variant {
        const char* name;
        std::unique_ptr<SurfaceIrradianceCache> cache;
        std::vector<double> e;
        double seconds = 0;
    };
    std::vector<Variant> vars;
    vars.push_back({"plain (no cache)", nullptr, {}});
    vars.push_back({"cache: library", std::make_unique<bake_detail::VolumeSurfaceCache>(tracer, grid, stage0.levels[0].data.data()), {}});
    vars.push_back({"cache: nodes, exact E", std::make_unique<StudyCache>(tracer, plain, grid, CacheKind::NodesExact, paths), {}});
    vars.push_back({"cache: exact E at p", std::make_unique<StudyCache>(tracer, plain, grid, CacheKind::Exact, paths), {}});
    for (Variant& v : vars) {
        RadianceEstimator est(s, tracer, tr);
        est.setSurfaceCache(v.cache.get());
        v.e.assign(np, 0.0);
        const double t1 = bench::now();
        tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) {
            const Vec3f n = normalize(pts.n[i]), x = pts.x[i];
            Vec3f tb, bb;
            orthonormalBasis(n, tb, bb);
            const uint64_t stream = hashCombine(31337, i);
            Rng rng(stream, 4);
            RayCount rc;
            Rgb sum{0, 0, 0};
            for (uint32_t k = 0; k < pointRays; ++k) {
                float u, w;
                sobol02(k, hashCombine(stream, 1), u, w);
                const Vec3f l = cosineHemisphere(u, w);
                const Vec3f dir = tb * l.x + bb * l.y + n * l.z;
                sum += est.gatherRadiance(x, dir, l.z * float(kInvPi), rng, rc) * float(kPi);
                if (!est.hasEmissiveTriangles()) continue;
                sobol02(k, hashCombine(stream, 2), u, w);
                LightSample ls;
                if (est.sampleEmissiveTriangles(x, u, w, rng.uniform(), ls, rc, &n) && !est.skipsAtReceiver(ls)) {
                    const float c = std::max(0.0f, dot(n, ls.direction));
                    sum += ls.weight * (c * misWeight(ls.pdf, c * float(kInvPi)));
                }
            }
            std::vector<LightSample> punctual;
            est.punctualLights(x, punctual, rc);
            Rgb p{0, 0, 0};
            for (const LightSample& ls : punctual)
                if (!est.skipsAtReceiver(ls)) p += ls.weight * std::max(0.0f, dot(n, ls.direction));
            v.e[i] = luminance(sum / float(pointRays) + p) + direct[i];
        });
        v.seconds = bench::now() - t1;
    }
    auto report = [&](const char* region, const std::vector<std::size_t>& idx) {
        std::printf("    %-10s %3zu points (bias +- its standard error over the points; RMS):\n", region, idx.size());
        for (const Variant& v : vars) {
            double m = 0, m2 = 0;
            for (std::size_t i : idx) {
                const double r = (v.e[i] - truth.e[i]) / truth.denominator(i);
                m += r, m2 += r * r;
            }
            const double n = double(idx.size()), mean = m / n, rms = std::sqrt(m2 / n);
            const double se = std::sqrt(std::max(0.0, m2 / n - mean * mean) / std::max(1.0, n - 1));
            std::printf("      %-28s vs truth: bias %+6.2f %% +- %4.2f %%, RMS %5.1f %%  (%.1f s)\n", v.name, 100 * mean, 100 * se,
                        100 * rms, v.seconds);
        }
        // Paired differences (common direction samples): sh - nodes, nodes - exact.
        for (const auto& [a, b] : {std::pair{1, 2}, std::pair{2, 3}, std::pair{1, 3}}) {
            double m = 0, m2 = 0;
            for (std::size_t i : idx) {
                const double r = (vars[std::size_t(a)].e[i] - vars[std::size_t(b)].e[i]) / truth.denominator(i);
                m += r, m2 += r * r;
            }
            const double n = double(idx.size()), mean = m / n;
            const double se = std::sqrt(std::max(0.0, m2 / n - mean * mean) / std::max(1.0, n - 1));
            std::printf("      [%s] - [%s]: %+6.2f %% +- %4.2f %%\n", vars[std::size_t(a)].name, vars[std::size_t(b)].name, 100 * mean,
                        100 * se);
        }
    };
    std::vector<std::size_t> all(np);
    for (std::size_t i = 0; i < np; ++i) all[i] = i;
    report("all", all);
    for (const bench::AccuracyRegion& region : as.regions) {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < np; ++i)
            if (region.contains(pts.x[i])) idx.push_back(i);
        if (!idx.empty()) report(region.name.c_str(), idx);
    }
}

}  // namespace vdblight::accuracy
