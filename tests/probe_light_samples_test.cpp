// Several emitter samples where the probe pass's cache ends a path (issue 32, session 25;
// TransportOptions::cacheEndLightSamples, `bake --probe-light-samples`): each weighted 1 / n,
// they keep the estimator's mean and lower its noise. Measured on the Cornell box, whose
// light reaches the probe pass's hits straight from its ceiling panel: gathered paths from a
// point in the box to the floor, ended at their first hit by a cache of uniform irradiance, as
// the probe pass ends them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "vdblight/light/light.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {
namespace {

/// The same irradiance at every surface point: the path's end is NEE, the cosine ray's MIS
/// share of the emitters, and this.
class UniformCache : public SurfaceIrradianceCache {
public:
    bool irradiance(const Vec3f&, const Vec3f&, Rgb& out, RayCount&) const override {
        out = Rgb(0.05f, 0.05f, 0.05f);
        return true;
    }
};

struct Moments {
    double mean = 0, variance = 0, standardError = 0;
};

/// Luminance of `count` gathered paths from x along `dir`, each ended at its first hit by
/// `cache`, with `samples` light samples there: what varies is the light sampled at the hit
/// and the cosine ray's share of the emitters (the direction's own variance, which the
/// samples do not touch, is left out).
Moments probeEstimates(const Scene& scene, const Tracer& tracer, const SurfaceIrradianceCache& cache, int samples,
                       const Vec3f& x, const Vec3f& dir, int count) {
    TransportOptions t;
    t.cacheEndLightSamples = samples;
    RadianceEstimator estimator(scene, tracer, t);
    estimator.setSurfaceCache(&cache);
    Rng rng(uint64_t(samples), 9);
    RayCount rays;
    double sum = 0, squares = 0;
    for (int i = 0; i < count; ++i) {
        const double y = luminance(estimator.gatherRadiance(x, dir, float(kInvPi), rng, rays));
        sum += y;
        squares += y * y;
    }
    Moments m;
    m.mean = sum / count;
    m.variance = squares / count - m.mean * m.mean;
    m.standardError = std::sqrt(m.variance / count);
    return m;
}

TEST(ProbeLightSamples, KeepTheMeanAndLowerTheNoise) {
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const UniformCache cache;
    const Bounds b = scene.bounds();
    // A floor point in the box's open middle, which the ceiling panel lights.
    const Vec3f x(b.lo + b.size() * Vec3d(0.4, 0.3, 0.55));
    const Vec3f down(0, -1, 0);
    constexpr int kPaths = 100000;
    const Moments one = probeEstimates(scene, tracer, cache, 1, x, down, kPaths);
    for (const int samples : {2, 3, 8}) {
        const Moments more = probeEstimates(scene, tracer, cache, samples, x, down, kPaths);
        const double se = std::hypot(one.standardError, more.standardError);
        std::printf("[ info ] %d light samples: mean %.5f +- %.5f (1 sample: %.5f +- %.5f, %+.1f standard errors), "
                    "variance %.3g of one sample's\n",
                    samples, more.mean, more.standardError, one.mean, one.standardError, (more.mean - one.mean) / se,
                    more.variance / one.variance);
        // Unbiased: the same mean within 4 standard errors (each sample weighted 1 / n; their
        // sum unscaled would be n times the direct part).
        EXPECT_NEAR(more.mean, one.mean, 4 * se) << samples << " samples";
        // Independent samples: the variance falls as 1 / n (measured 0.499, 0.334, 0.125; the
        // cosine ray's share of the emitters, which stays one sample, is small here).
        EXPECT_LT(more.variance, 1.15 / samples * one.variance) << samples << " samples";
    }
}

}  // namespace
}  // namespace vdblight
