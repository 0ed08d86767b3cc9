// The direct-light basis with vectors added from one-sided example lights
// (PrtOptions::orientedTraining, orientedCoeffs): the indirect light of one-sided (cosine) area
// lights gets better and that of held-out point lights does not get worse, against the
// uncompressed one-bounce reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/prt/pca.h"  // internal: pcaProject, pcaReconstruct
#include "../libvdblight/src/prt/prt_internal.h"  // internal: trainingLights

namespace vdblight {
namespace {

struct Box {
    Scene scene = loadScene(defaultScenePath());
    Tracer tracer{scene};
};
Box& box() {
    static Box b;
    return b;
}

PrtOptions options(float oriented) {
    PrtOptions o;
    o.samples = 400;
    o.clusterSize = 100;
    o.visDirs = 256;
    o.visCoeffs = 24;
    o.trainLights = 60;
    o.transferCoeffs = 32;
    o.bounces = 1;
    o.closureNormalise = false;  // as referenceIndirect
    o.orientedTraining = oriented;
    return o;
}

/// One-sided squares (10 cm, 4 x 4 points through the compressed visibility) of the Cornell box (0.556 x 0.549 x 0.559): two
/// under the ceiling facing down, one on the left wall facing +x, one tilted in the air, one
/// near the floor facing up and tilted. None is a training light (those are Halton points),
/// none is inside a solid (tested below).
const DirectLight kOneSided[5] = {
    squareLight(Vec3d(Vec3f{0.28f, 0.40f, 0.28f}), {0, -1, 0}, 0.1, Rgb{1, 1, 1}),
    squareLight(Vec3d(Vec3f{0.12f, 0.50f, 0.40f}), {0, -1, 0}, 0.1, Rgb{1, 1, 1}),
    squareLight(Vec3d(Vec3f{0.05f, 0.30f, 0.30f}), {1, 0, 0}, 0.1, Rgb{1, 1, 1}),
    squareLight(Vec3d(Vec3f{0.45f, 0.40f, 0.12f}), Vec3d(Vec3f{-0.5f, -0.5f, 0.7f}), 0.1, Rgb{1, 1, 1}),
    squareLight(Vec3d(Vec3f{0.08f, 0.06f, 0.50f}), Vec3d(Vec3f{0.3f, 1, -0.3f}), 0.1, Rgb{1, 1, 1}),
};
const Vec3f kPoints[5] = {{0.28f, 0.40f, 0.28f}, {0.12f, 0.30f, 0.45f}, {0.45f, 0.48f, 0.10f},
                          {0.30f, 0.15f, 0.05f}, {0.50f, 0.20f, 0.15f}};

struct Errors {
    double oneSided[5];
    double oneSidedMean = 0, pointMean = 0;
};

Errors measure(const PrtData& prt) {
    Errors e;
    for (int i = 0; i < 5; ++i) {
        const std::vector<float> exact = exactDirectLight(prt.samples, box().scene, box().tracer, kOneSided[i]);
        e.oneSided[i] = rmsRelativeError(prtTransfer(prt, prtDirectLight(prt, kOneSided[i], 4)),
                                         referenceIndirect(prt.samples, box().tracer, exact));
        e.oneSidedMean += e.oneSided[i] / 5;
        const std::vector<float> pt = exactDirectUnit(prt.samples, box().scene, box().tracer, kPoints[i]);
        e.pointMean += rmsRelativeError(prtTransfer(prt, prtDirectUnit(prt, kPoints[i])),
                                        referenceIndirect(prt.samples, box().tracer, pt)) / 5;
    }
    return e;
}

TEST(PrtOriented, OneSidedExamplesFaceAwayFromTheNearestSurface) {
    const std::vector<PrtPointLight> lights = trainingLights(box().scene, box().tracer, 60, 1.0f);
    ASSERT_EQ(lights.size(), 120u);
    const std::vector<Vec3f> positions = trainingLightPositions(box().scene, box().tracer, 120);
    for (std::size_t k = 0; k < lights.size(); ++k) {
        EXPECT_EQ(lights[k].position, positions[k]);  // the same Halton points, first 60 isotropic
        if (k < 60) {
            EXPECT_EQ(lights[k].normal, Vec3f(0, 0, 0)) << k;
            continue;
        }
        const Vec3f& n = lights[k].normal;
        EXPECT_NEAR(length(n), 1.0f, 1e-6f);
        // It faces away from the nearest surface along the six axes.
        const Vec3f p = positions[k];
        const Hit h = box().tracer.intersect(Ray{p, n * -1.0f});
        ASSERT_TRUE(h.hit()) << k;
        for (const Vec3f& d : {Vec3f{1, 0, 0}, Vec3f{-1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, -1, 0}, Vec3f{0, 0, 1},
                               Vec3f{0, 0, -1}}) {
            const Hit o = box().tracer.intersect(Ray{p, d});
            if (o.hit()) {
                EXPECT_LE(h.t, o.t) << k;
            }
        }
    }
}

TEST(PrtOriented, OneSidedLightsImproveAndPointLightsDoNot) {
    const PrtData points = bakePrt(box().scene, box().tracer, options(0.0f));
    const PrtData mixed = bakePrt(box().scene, box().tracer, options(PrtOptions{}.orientedTraining));
    EXPECT_EQ(mixed.trainLights, 60u);
    EXPECT_EQ(mixed.orientedTraining, PrtOptions{}.orientedTraining);
    EXPECT_EQ(mixed.orientedCoeffs, int(PrtOptions{}.orientedCoeffs));
    EXPECT_EQ(mixed.transferStride, points.transferStride + mixed.orientedCoeffs);
    // The point lights' vectors are kept bit for bit; the added ones are unit and orthogonal
    // to them, so every point light's direct light projects at least as well as before.
    for (std::size_t c = 0; c < mixed.samples.clusters(); ++c) {
        const PcaBasis& p = points.lightBasis[c];
        const PcaBasis& m = mixed.lightBasis[c];
        ASSERT_EQ(m.dim, p.dim);
        ASSERT_GT(m.count, p.count) << c;
        ASSERT_LE(m.count, p.count + mixed.orientedCoeffs) << c;
        for (int k = 0; k < p.count * p.dim; ++k) ASSERT_EQ(m.vectors[std::size_t(k)], p.vectors[std::size_t(k)]);
        for (int a = p.count; a < m.count; ++a)
            for (int k = 0; k <= a; ++k) {
                double d = 0;
                for (int j = 0; j < m.dim; ++j)
                    d += double(m.vectors[std::size_t(a * m.dim + j)]) * m.vectors[std::size_t(k * m.dim + j)];
                EXPECT_NEAR(d, a == k ? 1.0 : 0.0, 1e-4) << "cluster " << c << " vectors " << a << ", " << k;
            }
    }
    for (const Vec3f& l : kPoints) {
        const std::vector<float> d = exactDirectUnit(mixed.samples, box().scene, box().tracer, l);
        for (std::size_t c = 0; c < mixed.samples.clusters(); ++c) {
            double err[2];
            for (int which = 0; which < 2; ++which) {
                const PcaBasis& b = (which ? mixed : points).lightBasis[c];
                const float* x = d.data() + mixed.samples.clusterBegin[c];
                std::vector<float> coeffs(std::size_t(b.count)), y(std::size_t(b.dim));
                pcaProject(b, x, coeffs.data());
                pcaReconstruct(b, coeffs.data(), y.data());
                err[which] = 0;
                for (int j = 0; j < b.dim; ++j) err[which] += double(y[std::size_t(j)] - x[j]) * (y[std::size_t(j)] - x[j]);
            }
            EXPECT_LE(err[1], err[0] * (1 + 1e-4) + 1e-12) << "cluster " << c;
        }
    }
    for (const DirectLight& l : kOneSided) ASSERT_FALSE(insideSolid(box().tracer, Vec3f(l.position)));
    const Errors a = measure(points), b = measure(mixed);
    for (int i = 0; i < 5; ++i)
        std::printf("one-sided light %d: indirect RMS relative error %.4f (point-light basis) -> %.4f\n", i,
                    a.oneSided[i], b.oneSided[i]);
    std::printf("mean: one-sided %.4f -> %.4f, held-out point lights %.4f -> %.4f\n", a.oneSidedMean, b.oneSidedMean,
                a.pointMean, b.pointMean);
    // Measured (Release, this seed): one-sided mean 0.231 -> 0.171, the ceiling light 0.527 ->
    // 0.329; held-out point lights 0.134 -> 0.125. Bounds: at least 15 % better on the mean
    // and 30 % on the ceiling light, point lights at most 5 % worse.
    EXPECT_LT(b.oneSidedMean, 0.85 * a.oneSidedMean);
    EXPECT_LT(b.oneSided[0], 0.7 * a.oneSided[0]);
    EXPECT_LT(b.pointMean, 1.05 * a.pointMean);
    EXPECT_LT(b.oneSidedMean, 0.2);
    EXPECT_LT(b.pointMean, 0.15);
}

TEST(PrtOriented, PaperBasisHasPointLightsOnly) {
    PrtOptions o = options(1.0f);
    o.paperBasis = true;
    o.transferCoeffs = 8;
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    EXPECT_EQ(prt.orientedTraining, 0.0f);
    o.orientedTraining = -1;
    EXPECT_THROW(bakePrt(box().scene, box().tracer, o), ValueError);
}

}  // namespace
}  // namespace vdblight
