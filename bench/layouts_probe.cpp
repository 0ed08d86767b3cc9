// vdblight_bench_layouts (layouts.h): the layouts matched to a node budget, the error metric
// over the probe points, the bakes in each directional basis and the floor of each basis.
// Shared by the table at one budget (bench_layouts.cpp) and the sweep (layouts_sweep.cpp), so
// both compare layouts on the same points, reference and metric.
#include "layouts.h"

#include <tbb/parallel_for.h>

#include "vdblight/bake/each_pass.h"
#include "bake/bake_bins.h"
#include "query/bins_lookup.h"
#include "vdblight/core/errors.h"
#include "vdblight/light/light.h"
#include "query/query_levels.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "../libvdblight/src/bake/bins_gather.h"  // internal: gatherBinRadiance
#include "../libvdblight/src/bake/project_incident.h"  // internal: projectIncidentRadiance

namespace vdblight::bench_layouts {

LevelLayout makeLayout(const Scene& scene, LayoutKind kind, int resolution, int refine, int levels,
                       double refineDistanceInH0) {
    GridPlacement p;
    p.resolution = resolution;
    const GridSpec g0 = placeUniformGrid(scene.bounds(), p, 1);
    LevelsPlacement lp;
    lp.kind = kind;
    lp.refine = refine;
    lp.levels = levels;
    lp.refineDistance = refineDistanceInH0 * g0.spacing;
    return placeLevels(g0, scene.positions, scene.indices, lp, 1);
}

LevelLayout makeCulledLayout(const Scene& scene, const Tracer& tracer, LayoutKind kind, int resolution, int refine,
                             int levels) {
    GridPlacement p;
    p.resolution = resolution;
    const GridSpec g0 = placeUniformGrid(scene.bounds(), p, 1);
    LevelsPlacement lp;
    lp.kind = kind;
    lp.refine = refine;
    lp.levels = levels;
    lp.keepFinestGeometry = true;
    LevelLayout layout = placeLevels(g0, scene.positions, scene.indices, lp, 1);
    cullSolidNodes(layout, tracer);
    return layout;
}

LevelLayout closestLayout(const LayoutMaker& make, uint64_t target) {
    LevelLayout best;
    double bestGap = 1e300;
    for (int r = 2; r <= 64; ++r) {
        LevelLayout l;
        try {
            l = make(r);
        } catch (const ValueError&) {  // too few first-level nodes on a short axis
            continue;
        }
        const double gap = std::abs(std::log(double(l.totalNodes()) / double(target)));
        if (gap < bestGap) bestGap = gap, best = std::move(l);
        if (l.totalNodes() > 4 * target) break;
    }
    return best;
}

LevelLayout closestLayout(const Scene& scene, LayoutKind kind, int refine, int levels, uint64_t target) {
    return closestLayout([&](int r) { return makeLayout(scene, kind, r, refine, levels); }, target);
}

BasisChoice shBasis() { return {"sh2", true, {}}; }
BasisChoice binsBasis(int resolution) {
    BasisChoice b{"bins:" + std::to_string(resolution), false, bins::parseBasisSpec("bins:" + std::to_string(resolution))};
    return b;
}

std::vector<char> nearPoints(const Probe& probe, const LevelLayout& bilevel) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels = volumeLevels(bilevel.levels);
    for (VolumeLevel& l : v.levels) l.data.assign(l.storedNodes() * 27, 0.0f);
    const ShLevelsLookup mask(v, OutsidePolicy::Clamp);
    std::vector<char> near(probe.points.size());
    for (std::size_t i = 0; i < near.size(); ++i) near[i] = mask.levelAt(probe.points[i].position) > 0;
    return near;
}

double rmsNearOf(const Probe& probe, const std::vector<Rgb>& e, const std::vector<char>& near, double* maxNear,
                 double* rmsAll) {
    ErrorStats all, n;
    for (std::size_t i = 0; i < e.size(); ++i) {
        const double rel = probe.relError(i, e[i]);
        all.add(rel);
        if (near[i]) n.add(rel);
    }
    if (maxNear) *maxNear = n.max;
    if (rmsAll) *rmsAll = all.rmsValue();
    return n.rmsValue();
}

std::pair<double, double> bootstrapRatio(const Probe& probe, const std::vector<Rgb>& a, const std::vector<Rgb>& b,
                                         const std::vector<char>& near) {
    std::vector<double> ea, eb;
    for (std::size_t i = 0; i < near.size(); ++i)
        if (near[i]) ea.push_back(probe.relError(i, a[i])), eb.push_back(probe.relError(i, b[i]));
    if (ea.empty()) return {0.0, 0.0};
    Rng rng(77);
    std::vector<double> ratios(2000);
    for (double& r : ratios) {
        double sa = 0, sb = 0;
        for (std::size_t k = 0; k < ea.size(); ++k) {
            const std::size_t j = std::min(ea.size() - 1, std::size_t(rng.uniform() * double(ea.size())));
            sa += ea[j] * ea[j], sb += eb[j] * eb[j];
        }
        r = sa > 0 ? std::sqrt(sb / sa) : 0.0;
    }
    std::sort(ratios.begin(), ratios.end());
    return {ratios[100], ratios[1899]};
}

std::vector<Rgb> bakeAndQuery(const Probe& probe, const LevelLayout& layout, const BasisChoice& basis, uint32_t rays,
                              int threads, double* seconds) {
    LevelsBakeStats stats;
    std::vector<Rgb> e(probe.points.size());
    if (basis.sh) {
        GatherOptions o;
        o.raysPerNode = rays;
        o.threads = threads;
        const Volume v = bakeShGatherLevels(probe.scene, probe.tracer, layout, o, nullptr, &stats);
        const IrradianceQuery q(v);
        for (std::size_t i = 0; i < e.size(); ++i) e[i] = q.irradiance(probe.points[i].position, probe.points[i].normal);
    } else {
        BinsBakeOptions o;
        o.basis = basis.spec;
        o.samplesPerBin = basis.samplesPerBin(rays);
        o.threads = threads;
        const Volume v = bakeBins(probe.scene, probe.tracer, layout, o, nullptr, &stats);
        const BinsLookup q(v, OutsidePolicy::Clamp);
        for (std::size_t i = 0; i < e.size(); ++i) e[i] = q.irradiance(probe.points[i].position, probe.points[i].normal);
    }
    if (seconds) *seconds = stats.seconds;
    return e;
}

std::vector<Rgb> projectAtPoints(const Probe& probe, const BasisChoice& basis, uint32_t rays) {
    const RadianceEstimator estimator(probe.scene, probe.tracer, TransportOptions{});
    const uint64_t seed = GatherOptions{}.seed;
    std::vector<Rgb> e(probe.points.size());
    if (basis.sh) {
        tbb::parallel_for(std::size_t(0), e.size(), [&](std::size_t i) {
            Rgbd c[sh::kCoeffs];
            RayCount count;
            projectIncidentRadiance(estimator, probe.points[i].position, rays, seed, 1'000'000 + i, c, count);
            Rgb f[sh::kCoeffs];
            for (int j = 0; j < sh::kCoeffs; ++j) f[j] = Rgb(c[j]);
            e[i] = sh::irradiance(f, probe.points[i].normal);
        });
        return e;
    }
    const int bins = basis.spec.binCount(), R = basis.spec.resolution;
    const std::vector<float> w = bins::quadratureWeights(basis.spec);
    const uint32_t samples = basis.samplesPerBin(rays);
    tbb::parallel_for(std::size_t(0), e.size(), [&](std::size_t i) {
        std::vector<Rgbd> integral(static_cast<std::size_t>(bins));
        RayCount count;
        const Vec3f x = probe.points[i].position;
        gatherBinRadiance(estimator, x, R, samples, seed, 1'000'000 + i, integral.data(), count);
        // The quadrature of bakeBins: H_j = sum_i W_ji Lbar_i, in float, summed over i in order.
        const double invOmega = 1.0 / bins::binSolidAngle(R);
        std::vector<float> node(std::size_t(bins) * 3, 0.0f);
        for (int b = 0; b < bins; ++b) {
            const Rgbd& I = integral[std::size_t(b)];
            const float l[3] = {float(I.x * invOmega), float(I.y * invOmega), float(I.z * invOmega)};
            if (l[0] == 0.0f && l[1] == 0.0f && l[2] == 0.0f) continue;
            for (int j = 0; j < bins; ++j)
                for (int c = 0; c < 3; ++c) node[std::size_t(j) * 3 + c] += w[std::size_t(j) * bins + b] * l[c];
        }
        Volume v;
        v.basis = bins::basis(basis.spec);
        v.levels.resize(1);
        GridSpec& g = v.levels[0].grid;
        g.spacing = 1e-3;
        g.origin = Vec3d(x) - Vec3d(0.5e-3, 0.5e-3, 0.5e-3);
        g.nx = g.ny = g.nz = 2;
        for (int n = 0; n < 8; ++n) v.levels[0].data.insert(v.levels[0].data.end(), node.begin(), node.end());
        e[i] = BinsLookup(v, OutsidePolicy::Clamp).irradiance(x, probe.points[i].normal);
    });
    return e;
}

}  // namespace vdblight::bench_layouts
