// PRT (Leonhardt & Bohn): PCA round trips, sample distribution, visibility lookup, and the
// relit direct and indirect light against uncompressed references on a Cornell box.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "default_scene.h"
#include "prt_fixtures.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/sampling/sampling.h"
#include "basis/sh.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "../libvdblight/src/prt/pca.h"  // internal: fitPca, pcaProject, pcaReconstruct

#include "support/office_scene.h"
#include "support/scene_generators.h"

namespace vdblight {
namespace {

std::vector<float> randomRows(int n, int d, uint64_t seed) {
    std::vector<float> a(std::size_t(n) * std::size_t(d));
    Rng rng(seed);
    // Correlated data: a few smooth patterns plus noise, so that PCA has structure.
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < d; ++j)
            a[std::size_t(i) * std::size_t(d) + std::size_t(j)] =
                float(std::sin(0.1 * j * (1 + i % 3)) * (i + 1) * 0.1 + 0.3 * rng.uniform());
    return a;
}

double reconstructionError(const std::vector<float>& a, int n, int d, int keep) {
    const PcaBasis b = fitPca(a, n, d, keep);
    std::vector<float> c(std::size_t(std::max(b.count, 1))), x(static_cast<std::size_t>(d));
    double err = 0;
    for (int i = 0; i < n; ++i) {
        pcaProject(b, a.data() + std::size_t(i) * std::size_t(d), c.data());
        pcaReconstruct(b, c.data(), x.data());
        for (int j = 0; j < d; ++j) {
            const double e = x[std::size_t(j)] - a[std::size_t(i) * std::size_t(d) + std::size_t(j)];
            err += e * e;
        }
    }
    return std::sqrt(err / (n * d));
}

TEST(Pca, AllComponentsRoundTripExactly) {
    const int n = 30, d = 20;
    const std::vector<float> a = randomRows(n, d, 3);
    EXPECT_LT(reconstructionError(a, n, d, d), 1e-5);
    const PcaBasis b = fitPca(a, n, d, d);
    for (int k = 0; k < b.count; ++k)
        for (int l = 0; l < b.count; ++l) {
            double s = 0;
            for (int j = 0; j < d; ++j) s += double(b.vectors[std::size_t(k * d + j)]) * b.vectors[std::size_t(l * d + j)];
            EXPECT_NEAR(s, k == l ? 1.0 : 0.0, 1e-5) << k << "," << l;
        }
}

TEST(Pca, ErrorFallsMonotonicallyWithComponents) {
    const int n = 40, d = 25;
    const std::vector<float> a = randomRows(n, d, 5);
    double prev = 1e30;
    for (int keep = 0; keep <= d; ++keep) {
        const double e = reconstructionError(a, n, d, keep);
        EXPECT_LE(e, prev + 1e-7) << "keep " << keep;
        prev = e;
    }
    // The residual equals the discarded singular values: sum_{k >= keep} s_k^2 = n d e^2.
    const PcaBasis b = fitPca(a, n, d, 5);
    double tail = 0;
    for (std::size_t k = 5; k < b.singularValues.size(); ++k) tail += b.singularValues[k] * b.singularValues[k];
    EXPECT_NEAR(reconstructionError(a, n, d, 5), std::sqrt(tail / (n * d)), 1e-5);
}

TEST(Pca, RefusesEmptyInput) {
    EXPECT_THROW(fitPca({}, 0, 3, 1), ValueError);
}

TEST(Visibility, DirectionsAreUnitEqualAreaAndFoundAgain) {
    const int g = 16;
    double meanZ = 0;
    for (int t = 0; t < g * g; ++t) {
        const Vec3f d = visibilityDirection(g, t);
        EXPECT_NEAR(length(d), 1.0f, 1e-5f);
        EXPECT_GT(d.z, 0.0f);
        meanZ += d.z / (g * g);
        int idx[4];
        float w[4];
        visibilityNeighbours(g, d, idx, w);
        float wSelf = 0, wSum = 0;
        for (int k = 0; k < 4; ++k) {
            wSum += w[k];
            if (idx[k] == t) wSelf += w[k];
        }
        EXPECT_NEAR(wSum, 1.0f, 1e-5f);
        EXPECT_NEAR(wSelf, 1.0f, 1e-3f) << "direction " << t;
    }
    // Uniform over the hemisphere: E[z] = 1/2 (the midpoint rule adds 1/g^2 since z is
    // quadratic in the disk radius).
    EXPECT_NEAR(meanZ, 0.5, 1.01 / (g * g));
}

Scene quadScene(int subdivisions) {
    // The unit square z = 0 split into a deliberately uneven fan of thin triangles.
    Scene s;
    const uint32_t m = addMaterial(s, Material{"white", Rgb{0.5f, 0.5f, 0.5f}});
    const Vec3f c{0.9f, 0.9f, 0};
    const Vec3f corners[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int e = 0; e < 4; ++e)
        for (int k = 0; k < subdivisions; ++k) {
            const Vec3f a = corners[e] + (corners[(e + 1) % 4] - corners[e]) * (float(k) / subdivisions);
            const Vec3f b = corners[e] + (corners[(e + 1) % 4] - corners[e]) * (float(k + 1) / subdivisions);
            addTriangle(s, a, b, c, m);
        }
    return s;
}

TEST(Samples, UniformIndependentOfTessellation) {
    for (int sub : {1, 16}) {
        const Scene scene = quadScene(sub);
        const SurfaceSamples s = generateSurfaceSamples(scene, 0, 600, 100, 7);
        EXPECT_GT(s.size(), 450u);
        EXPECT_LT(s.size(), 750u);
        // Fraction of samples in the left half equals its area fraction (the fan's apex is
        // far right, so tessellation-biased sampling would fail this).
        std::size_t left = 0;
        for (const Vec3f& p : s.position) left += p.x < 0.5f;
        EXPECT_NEAR(double(left) / s.size(), 0.5, 0.04) << "subdivisions " << sub;
        // Poisson-disk property.
        for (std::size_t i = 0; i < s.size(); ++i)
            for (std::size_t j = i + 1; j < s.size(); ++j)
                ASSERT_GE(length(s.position[i] - s.position[j]), float(s.radius) * 0.999f);
        // Clusters: every sample joins its nearest root; clusters are contiguous.
        EXPECT_EQ(s.clusters(), std::size_t(std::lround(s.size() / 100.0)));
        for (std::size_t i = 0; i < s.size(); ++i) {
            const float own = length(s.position[i] - s.clusterRoot[s.cluster[i]]);
            for (const Vec3f& r : s.clusterRoot) EXPECT_LE(own, length(s.position[i] - r) + 1e-6f);
            EXPECT_GE(i, s.clusterBegin[s.cluster[i]]);
            EXPECT_LT(i, s.clusterBegin[s.cluster[i] + 1]);
        }
    }
    EXPECT_THROW(generateSurfaceSamples(quadScene(1), 0, 0, 100, 1), ValueError);
    EXPECT_THROW(generateSurfaceSamples(quadScene(1), 1e-6, 0, 100, 1), ValueError);
}

TEST(Transfer, WhiteFurnaceOneBounce) {
    // Inside a closed box every sample sees only other samples: with uniform direct
    // irradiance E0 the one-bounce irradiance is rho E0 (up to the disk approximation).
    const Scene scene = test::greyUnitBox();
    const Tracer tracer(scene);
    const SurfaceSamples s = generateSurfaceSamples(scene, 0, 1500, 2000, 3);
    const std::vector<Rgb> e = referenceIndirect(s, tracer, std::vector<float>(s.size(), 1.0f));
    // Point-to-disk form factors miss the near field at grazing angles, so samples close to
    // an edge of the box receive too little; away from the edges the sum must be rho E0.
    double mean = 0, interior = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        mean += e[i].x / e.size();
        if (test::distanceToUnitBoxEdge(s, i) < 3.0f * float(s.radius)) continue;
        interior += e[i].x;
        ++count;
    }
    interior /= double(count);
    std::printf("furnace: one-bounce irradiance %.4f over %zu interior samples, %.4f over all (exact 0.5)\n", interior,
                count, mean);
    EXPECT_GT(count, s.size() / 4);
    EXPECT_NEAR(interior, 0.5, 0.01);
    EXPECT_NEAR(mean, 0.5, 0.06);
}

TEST(Transfer, WhiteFurnaceVolume) {
    // Nodes inside a closed box with uniform direct irradiance 1 on albedo 0.5 walls: the
    // one-bounce radiance is 0.5 / pi from every direction, irradiance 0.5 for any normal.
    const Scene scene = test::greyUnitBox();
    const Tracer tracer(scene);
    const SurfaceSamples s = generateSurfaceSamples(scene, 0, 3000, 4000, 3);
    GridSpec grid;
    grid.origin = {0.3, 0.3, 0.3};
    grid.spacing = 0.2;
    grid.nx = grid.ny = grid.nz = 3;
    const std::vector<Rgb> v = referenceVolume(s, grid, tracer, std::vector<float>(s.size(), 1.0f));
    for (std::size_t node = 0; node < grid.nodeCount(); ++node) {
        for (const Vec3f& n : {Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, normalize(Vec3f{1, -1, 1})}) {
            const Rgb e = sh::irradiance(v.data() + node * sh::kCoeffs, n);
            EXPECT_NEAR(e.x, 0.5f, 0.01f) << "node " << node;
        }
    }
}

const test::DefaultScene& box() { return test::defaultScene(); }

PrtOptions smallOptions() {
    PrtOptions o = test::smallPrtOptions();
    o.transferCoeffs = 32;
    o.bounces = 1;  // the one-bounce references below; multi-bounce has its own tests
    return o;
}

const Vec3f kHeldOut[5] = {{0.28f, 0.40f, 0.28f}, {0.12f, 0.30f, 0.45f}, {0.45f, 0.48f, 0.10f},
                           {0.30f, 0.15f, 0.05f}, {0.50f, 0.20f, 0.15f}};

TEST(Prt, TrainingLightIsExactWithAllCoefficients) {
    PrtOptions o = smallOptions();
    o.transferCoeffs = o.trainLights;  // complete basis of the training data
    o.orientedTraining = 0;            // (the isotropic training lights only)
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    const Vec3f light = trainingLightPositions(box().scene, box().tracer, o.trainLights)[7];
    const std::vector<float> direct = exactDirectUnit(prt.samples, box().scene, box().tracer, light);
    const std::vector<Rgb> ref = referenceIndirect(prt.samples, box().tracer, direct);
    const double err = rmsRelativeError(prtTransfer(prt, direct), ref);
    std::printf("training light, all coefficients: RMS relative indirect error %.2e\n", err);
    EXPECT_LT(err, 1e-3);
}

TEST(Prt, HeldOutLightsErrorBoundedAndFallsWithCoefficients) {
    std::vector<double> projErr, indErr;
    for (uint32_t k : {2u, 8u, 32u}) {
        PrtOptions o = smallOptions();
        o.transferCoeffs = k;
        const PrtData prt = bakePrt(box().scene, box().tracer, o);
        double pe = 0, ie = 0;
        for (const Vec3f& light : kHeldOut) {
            ASSERT_FALSE(insideSolid(box().tracer, light));
            const std::vector<float> direct = exactDirectUnit(prt.samples, box().scene, box().tracer, light);
            const std::vector<Rgb> ref = referenceIndirect(prt.samples, box().tracer, direct);
            ie += rmsRelativeError(prtTransfer(prt, direct), ref) / 5;
            // Projection error of the direct light itself (nested subspaces: monotonic).
            double num = 0, den = 0;
            for (std::size_t c = 0; c < prt.samples.clusters(); ++c) {
                const PcaBasis& b = prt.lightBasis[c];
                const float* x = direct.data() + prt.samples.clusterBegin[c];
                std::vector<float> coeffs(std::size_t(b.count)), y(std::size_t(b.dim));
                pcaProject(b, x, coeffs.data());
                pcaReconstruct(b, coeffs.data(), y.data());
                for (int j = 0; j < b.dim; ++j) {
                    num += (y[std::size_t(j)] - x[j]) * (y[std::size_t(j)] - x[j]);
                    den += x[j] * x[j];
                }
            }
            pe += std::sqrt(num / den) / 5;
        }
        std::printf("transfer coeffs %2u: held-out direct projection error %.4f, indirect RMS relative error %.4f\n",
                    k, pe, ie);
        projErr.push_back(pe);
        indErr.push_back(ie);
    }
    EXPECT_LT(projErr[1], projErr[0]);
    EXPECT_LT(projErr[2], projErr[1]);
    EXPECT_LT(indErr[2], indErr[0]);
    EXPECT_LT(indErr[1], indErr[0]);
    EXPECT_LT(indErr[2], 0.25);
}

TEST(Prt, CompressedVisibilityAgreesWithShadowRays) {
    PrtOptions o = smallOptions();
    o.visDirs = 1024;  // the paper keeps 50 of ~2000 directions
    o.visCoeffs = 50;
    o.transferCoeffs = 1;
    PrtData prt = bakePrt(box().scene, box().tracer, o);
    Rng rng(11);
    std::size_t wrong = 0, total = 0;
    for (int l = 0; l < 20; ++l) {
        const Bounds b = box().scene.bounds();
        const Vec3f p(Vec3d{b.lo.x + 0.1 + 0.35 * rng.uniform(), b.lo.y + 0.05 + 0.45 * rng.uniform(),
                            b.lo.z + 0.05 + 0.45 * rng.uniform()});
        if (insideSolid(box().tracer, p)) continue;
        const std::vector<float> exact = exactDirectUnit(prt.samples, box().scene, box().tracer, p);
        const std::vector<float> pcaDirect = prtDirectUnit(prt, p);
        for (std::size_t i = 0; i < exact.size(); ++i) {
            const Vec3f w = p - prt.samples.position[i];
            const float cosine = dot(prt.samples.normal[i], normalize(w));
            if (cosine <= 0.0f) continue;  // the light is behind the sample
            const float unshadowed = cosine / dot(w, w);
            ++total;
            // Misclassified if the reconstructed visibility is on the wrong side of 1/2.
            if ((exact[i] > 0) != (pcaDirect[i] > 0.5f * unshadowed)) ++wrong;
        }
    }
    const double rate = double(wrong) / double(total);
    std::printf("visibility: %zu of %zu lit-side sample-light pairs misclassified (%.2f%%)\n", wrong, total, 100 * rate);
    EXPECT_GT(total, 1000u);
    EXPECT_LT(rate, 0.05);
}

TEST(Prt, RelightEndToEndAgainstReference) {
    const PrtData prt = bakePrt(box().scene, box().tracer, smallOptions());
    double worst = 0;
    for (const Vec3f& light : kHeldOut) {
        const PrtLighting lit = relightPrt(prt, {test::pointLight(light, Rgb{1, 0.5f, 0.25f})});
        const std::vector<float> direct = exactDirectUnit(prt.samples, box().scene, box().tracer, light);
        std::vector<Rgb> refDirect(direct.size());
        for (std::size_t i = 0; i < direct.size(); ++i) refDirect[i] = Rgb{1, 0.5f, 0.25f} * direct[i];
        std::vector<Rgb> ref = referenceIndirect(prt.samples, box().tracer, direct);
        for (Rgb& v : ref) v = v * Rgb{1, 0.5f, 0.25f};
        const double ed = rmsRelativeError(lit.direct, refDirect), ei = rmsRelativeError(lit.indirect, ref);
        std::printf("light (%.2f %.2f %.2f): direct RMS rel. error %.4f, indirect %.4f\n", light.x, light.y, light.z, ed,
                    ei);
        worst = std::max(worst, ei);
        EXPECT_LT(ed, 0.25);
    }
    EXPECT_LT(worst, 0.25);
}

TEST(Prt, RelightableVolumeAgainstReference) {
    PrtOptions o = smallOptions();
    o.volumeResolution = 4;
    o.transferCoeffs = o.trainLights;
    o.orientedTraining = 0;  // complete basis of the isotropic training lights
    const PrtData full = bakePrt(box().scene, box().tracer, o);
    ASSERT_TRUE(full.hasVolume());
    const std::size_t nodes = full.volumeGrid.nodeCount();
    // Complete basis + training light: exact.
    const Vec3f train = trainingLightPositions(box().scene, box().tracer, o.trainLights)[3];
    std::vector<float> direct = exactDirectUnit(full.samples, box().scene, box().tracer, train);
    double err = rmsRelativeError(prtVolumeTransfer(full, direct), referenceVolume(full.samples, full.volumeGrid, box().tracer, direct));
    std::printf("volume, training light, all coefficients: RMS relative error %.2e\n", err);
    EXPECT_LT(err, 1e-3);
    // Held-out lights through the whole run-time path, at 32 vectors.
    o.transferCoeffs = 32;
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    double worst = 0;
    for (const Vec3f& light : kHeldOut) {
        const Volume vol = relightVolume(prt, {test::pointLight(light)});
        ASSERT_EQ(vol.levels[0].data.size(), nodes * sh::kCoeffs * 3);
        direct = exactDirectUnit(prt.samples, box().scene, box().tracer, light);
        const std::vector<Rgb> ref = referenceVolume(prt.samples, prt.volumeGrid, box().tracer, direct);
        std::vector<Rgb> got(ref.size());
        for (std::size_t i = 0; i < got.size(); ++i)
            got[i] = Rgb{vol.levels[0].data[i * 3], vol.levels[0].data[i * 3 + 1], vol.levels[0].data[i * 3 + 2]};
        const double e = rmsRelativeError(got, ref);
        std::printf("volume, light (%.2f %.2f %.2f): SH RMS relative error %.4f\n", light.x, light.y, light.z, e);
        worst = std::max(worst, e);
    }
    EXPECT_LT(worst, 0.55);  // measured 0.447 (near-field sub-disks in the reference)
    // Through a PRT file and back, and written as a volume that the volume reader accepts.
    test::TempDir dir;
    writePrt(prt, dir.file("v.vdb"));
    const PrtData back = readPrt(dir.file("v.vdb"));
    ASSERT_TRUE(back.hasVolume());
    EXPECT_EQ(back.volumeGrid.nx, prt.volumeGrid.nx);
    const Volume a = relightVolume(prt, {test::pointLight(kHeldOut[0])});
    const Volume b = relightVolume(back, {test::pointLight(kHeldOut[0])});
    std::vector<Rgb> va(nodes * 9), vb(nodes * 9);
    for (std::size_t i = 0; i < va.size(); ++i) {
        va[i] = Rgb{a.levels[0].data[i * 3], a.levels[0].data[i * 3 + 1], a.levels[0].data[i * 3 + 2]};
        vb[i] = Rgb{b.levels[0].data[i * 3], b.levels[0].data[i * 3 + 1], b.levels[0].data[i * 3 + 2]};
    }
    EXPECT_LT(rmsRelativeError(vb, va), 5e-3);
    writeVolume(b, dir.file("relit.vdb"));
    EXPECT_EQ(readVolume(dir.file("relit.vdb")).levels[0].grid.nodeCount(), nodes);
    EXPECT_THROW(relightVolume(bakePrt(box().scene, box().tracer, smallOptions()), {test::pointLight(kHeldOut[0])}), ValueError);
}

TEST(Prt, OfficeRelightEndToEndAgainstReference) {
    // The second scene of the issue: the generated office (room [0,6] x [0,3] x [0,5] m with
    // desks, shelves, a divider; detail 1, ~53 k triangles; detail only refines the wall
    // tessellation, which the samples do not depend on). Small counts keep it quick; five
    // held-out light positions (not among the Halton training lights) at desk and ceiling
    // height, relit through the whole run-time path (compressed visibility -> direct ->
    // projection -> transfer) at the samples and at the nodes of a 6-node-long volume,
    // against the uncompressed one-bounce references with exact shadow rays.
    const Scene office = makeOfficeScene(1);
    const Tracer tracer(office);
    PrtOptions o = smallOptions();
    o.samples = 1200;
    o.clusterSize = 300;
    o.trainLights = 100;
    o.volumeResolution = 6;
    const PrtData prt = bakePrt(office, tracer, o);
    ASSERT_TRUE(prt.hasVolume());
    const Vec3f lights[5] = {{1.3f, 2.4f, 1.2f}, {4.6f, 2.1f, 3.7f}, {3.1f, 1.6f, 2.6f},
                             {0.8f, 1.3f, 4.1f}, {5.2f, 2.7f, 0.9f}};
    const Rgb colour{1, 0.5f, 0.25f};
    double worstSamples = 0, worstVolume = 0, meanSamples = 0, meanVolume = 0;
    for (const Vec3f& light : lights) {
        ASSERT_FALSE(insideSolid(tracer, light));
        const std::vector<float> direct = exactDirectUnit(prt.samples, office, tracer, light);
        std::vector<Rgb> ref = referenceIndirect(prt.samples, tracer, direct);
        for (Rgb& v : ref) v = v * colour;
        const PrtLighting lit = relightPrt(prt, {test::pointLight(light, colour)});
        const double es = rmsRelativeError(lit.indirect, ref);
        const Volume vol = relightVolume(prt, {test::pointLight(light, colour)});
        std::vector<Rgb> refVol = referenceVolume(prt.samples, prt.volumeGrid, tracer, direct);
        for (Rgb& v : refVol) v = v * colour;
        std::vector<Rgb> got(refVol.size());
        ASSERT_EQ(vol.levels[0].data.size(), got.size() * 3);
        for (std::size_t i = 0; i < got.size(); ++i)
            got[i] = Rgb{vol.levels[0].data[i * 3], vol.levels[0].data[i * 3 + 1], vol.levels[0].data[i * 3 + 2]};
        const double ev = rmsRelativeError(got, refVol);
        std::printf("office, light (%.1f %.1f %.1f): indirect RMS rel. error at samples %.4f, SH at %zu volume nodes %.4f\n",
                    light.x, light.y, light.z, es, prt.volumeGrid.nodeCount(), ev);
        worstSamples = std::max(worstSamples, es);
        worstVolume = std::max(worstVolume, ev);
        meanSamples += es / 5;
        meanVolume += ev / 5;
    }
    std::printf("office (%zu samples, %zu clusters, 32 vectors): mean / worst indirect error %.4f / %.4f at samples, "
                "%.4f / %.4f at volume nodes\n",
                prt.samples.size(), prt.samples.clusters(), meanSamples, worstSamples, meanVolume, worstVolume);
    // Bounds: measured (Release, this seed; the bake is deterministic) mean / worst 0.115 /
    // 0.282 at samples and 0.249 / 0.517 at the 90 volume nodes, the worst being the light
    // 0.3 m under the ceiling in a corner (the 1/d^2 peak is not in a 32-vector basis of 100
    // example lights). The bounds add about 40 % margin for float differences between
    // platforms; an all-zero or unrelated answer scores 1 or more.
    EXPECT_LT(meanSamples, 0.16);
    EXPECT_LT(worstSamples, 0.40);
    EXPECT_LT(meanVolume, 0.35);
    EXPECT_LT(worstVolume, 0.72);
}

TEST(Prt, DeterministicForAnyThreadCount) {
    PrtOptions o = smallOptions();
    o.samples = 200;
    o.threads = 1;
    const PrtData a = bakePrt(box().scene, box().tracer, o);
    o.threads = 2;
    const PrtData b = bakePrt(box().scene, box().tracer, o);
    ASSERT_EQ(a.transfer.size(), b.transfer.size());
    for (std::size_t c = 0; c < a.transfer.size(); ++c) EXPECT_TRUE(a.transfer[c] == b.transfer[c]);
    EXPECT_EQ(a.visCoeffs, b.visCoeffs);
}

TEST(Prt, FileRoundTripAndQuantisation) {
    test::TempDir dir;
    const PrtData prt = bakePrt(box().scene, box().tracer, smallOptions());
    const Vec3f light = kHeldOut[0];
    const PrtLighting ref = relightPrt(prt, {test::pointLight(light)});
    PrtWriteOptions exact;
    exact.quantize = false;
    writePrt(prt, dir.file("f32.vdb"), exact);
    writePrt(prt, dir.file("q16.vdb"));
    EXPECT_TRUE(isPrtFile(dir.file("q16.vdb")));
    const PrtData f32 = readPrt(dir.file("f32.vdb"));
    ASSERT_EQ(f32.samples.size(), prt.samples.size());
    EXPECT_EQ(f32.visCoeffs, prt.visCoeffs);
    for (std::size_t c = 0; c < prt.transfer.size(); ++c) EXPECT_TRUE(f32.transfer[c] == prt.transfer[c]);
    const PrtLighting a = relightPrt(f32, {test::pointLight(light)});
    EXPECT_LT(rmsRelativeError(a.indirect, ref.indirect), 1e-4);
    const PrtLighting q = relightPrt(readPrt(dir.file("q16.vdb")), {test::pointLight(light)});
    const double eq = rmsRelativeError(q.indirect, ref.indirect);
    std::printf("16-bit storage: indirect RMS relative change %.2e\n", eq);
    EXPECT_LT(eq, 5e-3);
    const PrtFileInfo i32 = inspectPrt(dir.file("f32.vdb")), i16 = inspectPrt(dir.file("q16.vdb"));
    std::printf("bytes: dense float32 %llu, stored %llu (float) / %llu (16-bit); files %llu / %llu\n",
                (unsigned long long)i32.bytesFloat32, (unsigned long long)i32.bytesStored,
                (unsigned long long)i16.bytesStored, (unsigned long long)i32.fileBytes,
                (unsigned long long)i16.fileBytes);
    EXPECT_LT(i16.bytesStored, i32.bytesStored * 0.55);
    EXPECT_LT(i16.fileBytes, i32.fileBytes);
    // Not a PRT file.
    test::writeTextFile(dir.file("junk.vdb"), "not a vdb");
    EXPECT_THROW(readPrt(dir.file("junk.vdb")), FormatError);
    EXPECT_THROW(readPrt(dir.file("missing.vdb")), IoError);
    // A folder is named as one (it was "no such file"), as the volume reader names it.
    std::filesystem::create_directories(dir.file("folder.vdb"));
    try {
        readPrt(dir.file("folder.vdb"));
        ADD_FAILURE() << "a folder was read as a PRT file";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot read '" + dir.file("folder.vdb") + "': is a directory");
    }
}

TEST(Prt, RefusesAbsurdOptions) {
    PrtOptions o = smallOptions();
    o.visCoeffs = 0;
    EXPECT_THROW(bakePrt(box().scene, box().tracer, o), ValueError);
    o = smallOptions();
    o.samples = 1500000;
    o.clusterSize = 100000;
    EXPECT_THROW(bakePrt(box().scene, box().tracer, o), ValueError);  // 1.5M^2 rays
}

}  // namespace
}  // namespace vdblight
