// vdblight_bench_accuracy: the representation floor, the light at each point projected into
// SH order 2 and the six irradiance vectors with no interpolation (the decomposition's first
// term).
#include "accuracy.h"

#include <tbb/parallel_for.h>

#include "vdblight/basis/basis.h"
#include "vdblight/query/query.h"

namespace vdblight::accuracy {

namespace {
const Basis& sh4Basis() {
    static const std::unique_ptr<Basis> basis = makeBasis("sh:4");
    return *basis;
}
}  // namespace

Rgb sh4Irradiance(const AtPoint& a, const Vec3f& n) {
    const Basis& b = sh4Basis();
    int channels[25];
    float weights[25];
    const int terms = b.terms(n, channels, weights);
    Rgbd e{0, 0, 0};
    for (int k = 0; k < terms; ++k) e += a.sh4[channels[k]] * double(weights[k]);
    return Rgb(e);
}

AtPoint projectAtPoint(const RadianceEstimator& est, const Vec3f& x, const Vec3f& n, uint32_t rays, uint64_t stream) {
    AtPoint a;
    auto add = [&](const Vec3f& d, const Rgbd& w) {
        float y[sh::kCoeffs];
        sh::evalUnrolled(d, y);
        for (int j = 0; j < sh::kCoeffs; ++j) a.sh[j] += w * double(y[j]);
        sh4Basis().accumulate(d, w, 1.0, a.sh4);
        for (int axis = 0; axis < 3; ++axis) {
            const int dir = iv::direction(axis, d[axis] < 0.0f);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) a.iv[iv::channel(dir, c) * 3 + k] += w[c] * double(d[k]);
        }
        a.e += w * double(std::max(0.0f, dot(d, n)));
    };
    Rng rng(stream, 4);
    RayCount count;
    constexpr float kSpherePdf = float(1.0 / (4.0 * kPi));
    const double lightOffset = toUnitDouble(hashCombine(stream, 3));
    for (uint32_t i = 0; i < rays; ++i) {
        float u, v;
        sobol02(i, hashCombine(stream, 1), u, v);
        const Vec3f d = uniformSphere(u, v);
        add(d, Rgbd(est.gatherRadiance(x, d, kSpherePdf, rng, count)) * (4.0 * kPi / rays));
        if (!est.hasEmissiveTriangles()) continue;
        sobol02(i, hashCombine(stream, 2), u, v);
        double w = radicalInverse(3, i) + lightOffset;
        w -= std::floor(w);
        LightSample s;
        if (est.sampleEmissiveTriangles(x, u, v, w, s, count) && !est.skipsAtReceiver(s))
            add(s.direction, Rgbd(s.weight * misWeight(s.pdf, kSpherePdf)) / double(rays));
    }
    std::vector<LightSample> punctual;
    est.punctualLights(x, punctual, count);
    for (const LightSample& s : punctual)
        if (!est.skipsAtReceiver(s)) add(s.direction, Rgbd(s.weight));
    return a;
}

Floor floorAt(const Scene& s, const Tracer& tracer, const Points& p, uint32_t rays, int refBounces) {
    TransportOptions t;
    t.maxBounces = refBounces;
    const RadianceEstimator est(s, tracer, t);
    const std::vector<double> zeros(p.x.size());
    Floor f{zeros, zeros, zeros, zeros, zeros};
    tbb::parallel_for(std::size_t(0), p.x.size(), [&](std::size_t i) {
        const AtPoint a = projectAtPoint(est, p.x[i], normalize(p.n[i]), rays, hashCombine(777, i));
        Rgb c[sh::kCoeffs];
        for (int j = 0; j < sh::kCoeffs; ++j) c[j] = Rgb(a.sh[j]);
        f.sh[i] = luminance(sh::irradiance(c, normalize(p.n[i])));
        float v[iv::kFloatsPerNode];
        for (int k = 0; k < iv::kFloatsPerNode; ++k) v[k] = float(a.iv[k]);
        const Vec3f n = normalize(p.n[i]);
        f.iv[i] = luminance(iv::irradiance(v, n));
        f.ivPaper[i] = luminance(iv::irradiance(v, n, iv::Blend::Paper));
        f.ivQuadratic[i] = luminance(iv::irradiance(v, n, iv::Blend::Quadratic));
        f.e[i] = luminance(Rgb(a.e));
    });
    return f;
}

/// An irradiance-vector volume on the uniform grid of `resolution` whose nodes hold the six
/// vectors projected at the node itself (projectAtPoint, `rays` rays, `bounces`), not the photon
/// pass's face-averaged flux: it separates what trilinear interpolation of the six vectors
/// costs from what the photon estimator adds (issue 15, item 5).
Volume ivPointVolume(const Scene& s, const Tracer& tracer, int resolution, uint32_t rays, int bounces) {
    TransportOptions t;
    t.maxBounces = bounces;
    const RadianceEstimator est(s, tracer, t);
    Volume v;
    v.basis = iv::basis();
    v.levels.resize(1);
    VolumeLevel& level = v.levels[0];
    level.grid = gridFor(s, resolution);
    level.data.assign(level.grid.nodeCount() * iv::kFloatsPerNode, 0.0f);
    tbb::parallel_for(std::size_t(0), level.grid.nodeCount(), [&](std::size_t n) {
        const AtPoint a = projectAtPoint(est, Vec3f(level.grid.node(n)), {0, 1, 0}, rays, hashCombine(991, n));
        for (int k = 0; k < iv::kFloatsPerNode; ++k) level.data[n * iv::kFloatsPerNode + k] = float(a.iv[k]);
    });
    return v;
}

}  // namespace vdblight::accuracy
