// PRT beyond one bounce and beyond indirect light: the multi-bounce transfer against the white
// furnace's geometric series and against the uncompressed multi-bounce reference, the lights'
// direct radiance at volume nodes against the foundation's gather, and area lights.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdio>

#include "default_scene.h"
#include "prt_fixtures.h"
#include "test_util.h"
#include "vdblight/bake.h"
#include "vdblight/errors.h"
#include "vdblight/prt.h"
#include "vdblight/prt_io.h"
#include "vdblight/vdb_io.h"
#include "vdblight/scene.h"
#include "vdblight/sh.h"
#include "vdblight/trace.h"

#include "support/scene_generators.h"

namespace vdblight {
namespace {

std::vector<Rgb> volumeRgb(const Volume& v) {
    std::vector<Rgb> out(v.levels[0].data.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = Rgb{v.levels[0].data[i * 3], v.levels[0].data[i * 3 + 1], v.levels[0].data[i * 3 + 2]};
    return out;
}

TEST(PrtBounces, WhiteFurnaceGeometricSeries) {
    // Closed box, albedo 0.5, uniform direct irradiance 1: bounce b brings 0.5^b, so N bounces
    // sum to 1 - 0.5^N. With closure normalisation every row of F sums to pi (the box is
    // closed), so every sample must read the series; the raw disk form factors miss the near
    // field at edges, a deficit that compounds with bounces (printed, bounded loosely).
    const Scene scene = test::greyUnitBox();
    const Tracer tracer(scene);
    const SurfaceSamples s = generateSurfaceSamples(scene, 0, 1500, 2000, 3);
    const std::vector<float> raw = sampleFormFactors(s, tracer);
    const std::vector<float> F = sampleFormFactors(s, tracer, 0, nullptr, true);
    // Reciprocity of the raw matrix: area_r F_rj = area_j F_jr up to the disk formula's
    // near-field term.
    double asym = 0, sym = 0;
    for (std::size_t r = 0; r < s.size(); r += 7)
        for (std::size_t j = 0; j < s.size(); j += 5) {
            asym += std::abs(s.area[r] * raw[r * s.size() + j] - s.area[j] * raw[j * s.size() + r]);
            sym += s.area[r] * raw[r * s.size() + j];
        }
    std::printf("reciprocity of the raw form factors: %.4f\n", asym / sym);
    EXPECT_LT(asym / sym, 0.05);
    for (int bounces : {1, 2, 4, 8}) {
        const std::vector<Rgb> e = bounceIndirect(s, F, std::vector<Rgb>(s.size(), Rgb{1, 1, 1}), bounces);
        const std::vector<Rgb> er = bounceIndirect(s, raw, std::vector<Rgb>(s.size(), Rgb{1, 1, 1}), bounces);
        const double exact = 1.0 - std::pow(0.5, bounces);
        double worst = 0, interior = 0;
        std::size_t count = 0;
        for (std::size_t i = 0; i < e.size(); ++i) {
            worst = std::max(worst, std::abs(e[i].x - exact));
            if (test::distanceToUnitBoxEdge(s, i) < 0.25f) continue;
            interior += er[i].x;
            ++count;
        }
        interior /= double(count);
        std::printf("furnace: %d bounces (exact %.4f): normalised worst |error| %.2e over all %zu samples; raw disks "
                    "%.4f over %zu central samples\n", bounces, exact, worst, s.size(), interior, count);
        EXPECT_LT(worst, 1e-3);
        EXPECT_GT(count, 100u);
        EXPECT_NEAR(interior, exact, 0.05 * exact);
        EXPECT_LT(interior, exact);  // the disks' deficit
    }
}

PrtOptions options(int bounces) {
    PrtOptions o = test::smallPrtOptions();  // without closure normalisation, as referenceVolume
    o.transferCoeffs = 60;  // complete basis of the training lights: compression is exact for them
    o.orientedTraining = 0;  // (isotropic training lights only)
    o.bounces = bounces;
    o.volumeResolution = 4;
    return o;
}

const test::DefaultScene& box() { return test::defaultScene(); }

TEST(PrtBounces, CompressedTransferMatchesUncompressedReference) {
    // With the complete basis, a training light's multi-bounce indirect light at samples and
    // SH radiance at nodes must equal the uncompressed iteration (double sums, by rays).
    const PrtData prt = bakePrt(box().scene, box().tracer, options(4));
    EXPECT_EQ(prt.bounces, 4);
    const Vec3f light = trainingLightPositions(box().scene, box().tracer, 60)[11];
    const std::vector<float> d = exactDirectUnit(prt.samples, box().tracer, light);
    std::vector<Rgb> direct(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) direct[i] = Rgb{d[i], d[i], d[i]};
    const std::vector<float> F = sampleFormFactors(prt.samples, box().tracer);
    std::vector<Rgb> senders;
    const std::vector<Rgb> ref = bounceIndirect(prt.samples, F, direct, 4, &senders);
    const double err = rmsRelativeError(prtTransfer(prt, d), ref);
    const std::vector<Rgb> one = bounceIndirect(prt.samples, F, direct, 1);
    // The one-bounce F path agrees with the ray-by-ray reference.
    EXPECT_LT(rmsRelativeError(one, referenceIndirect(prt.samples, box().tracer, d)), 1e-5);
    const double gain = rmsRelativeError(ref, one);
    const std::vector<Rgb> vref = referenceVolume(prt.samples, prt.volumeGrid, box().tracer, senders);
    const double verr = rmsRelativeError(prtVolumeTransfer(prt, d), vref);
    std::printf("4 bounces, training light: samples error %.2e, volume error %.2e; bounces 2-4 add %.3f\n", err,
                verr, gain);
    EXPECT_LT(err, 1e-3);
    EXPECT_LT(verr, 1e-3);
    EXPECT_GT(gain, 0.1);  // more bounces do change the answer in a Cornell box
}

TEST(PrtBounces, LightsAtNodesMatchTheFoundationGather) {
    // The direct part of a relit volume equals a maxBounces = 0 gather of the scene with only
    // that point light (same shadow rays, delta projected on SH): exact up to float sums.
    const Vec3f light{0.28f, 0.40f, 0.28f};
    Scene lit = box().scene;
    for (Material& mat : lit.materials) mat.emission = Rgb{0, 0, 0};
    lit.pointLights = {PointLight{light, Rgb{2, 1, 0.5f}}};
    lit.spotLights.clear();
    lit.directionalLights.clear();
    lit.sky = Sky{};
    const Tracer tracer(lit);
    GridSpec grid;
    grid.origin = {0.05, 0.05, 0.05};
    grid.spacing = 0.1;
    grid.nx = grid.ny = grid.nz = 5;
    GatherOptions g;
    g.raysPerNode = 4;
    g.transport.maxBounces = 0;
    const std::vector<Rgb> want = volumeRgb(bakeShGather(lit, tracer, grid, g));
    PrtLight pl{light, Rgb{2, 1, 0.5f}};
    const std::vector<Rgb> got = lightsAtNodes(grid, box().tracer, {pl});
    const double err = rmsRelativeError(got, want);
    std::printf("direct at nodes vs gather: %.2e\n", err);
    EXPECT_LT(err, 1e-4);
    double norm = 0;
    for (const Rgb& v : got) norm += v.x;
    EXPECT_GT(norm, 0.0);
}

TEST(PrtBounces, CompleteVolumeIsDirectPlusIndirect) {
    const PrtData prt = bakePrt(box().scene, box().tracer, options(2));
    const PrtLight light{Vec3f{0.3f, 0.3f, 0.3f}, Rgb{1, 2, 3}};
    const std::vector<Rgb> indirect = volumeRgb(relightVolume(prt, {light}));
    const std::vector<Rgb> complete = volumeRgb(relightVolume(prt, {light}, &box().tracer));
    const std::vector<Rgb> direct = lightsAtNodes(prt.volumeGrid, box().tracer, {light});
    for (std::size_t i = 0; i < complete.size(); ++i) {
        const Rgb d = complete[i] - indirect[i] - direct[i];
        EXPECT_LT(std::abs(d.x) + std::abs(d.y) + std::abs(d.z), 1e-4f * (1.0f + std::abs(complete[i].x)));
    }
    EXPECT_THROW(bakePrt(box().scene, box().tracer, options(0)), ValueError);
}

TEST(PrtBounces, AreaLightAgainstShadowRays) {
    // A small downward-facing square light under the ceiling: its direct light through the
    // compressed visibility against shadow rays to the same points, and its indirect light
    // through the basis against the uncompressed reference (prt_oriented_test compares the
    // bases with and without one-sided examples).
    PrtOptions o = options(1);
    o.transferCoeffs = 32;
    o.volumeResolution = 0;
    o.orientedTraining = PrtOptions{}.orientedTraining;  // the default basis
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    PrtLight area{Vec3f{0.28f, 0.40f, 0.28f}, Rgb{1, 1, 1}, 0.1f, 4, Vec3f{0, -1, 0}};
    const std::vector<float> exact = exactDirectLight(prt.samples, box().tracer, area);
    const std::vector<float> got = prtDirectLight(prt, area);
    std::vector<Rgb> a(got.size()), b(got.size());
    for (std::size_t i = 0; i < got.size(); ++i) a[i] = Rgb{got[i], got[i], got[i]}, b[i] = Rgb{exact[i], exact[i], exact[i]};
    const double directErr = rmsRelativeError(a, b);
    const std::vector<Rgb> ind = prtTransfer(prt, got);
    const std::vector<Rgb> ref = referenceIndirect(prt.samples, box().tracer, exact);
    const double indErr = rmsRelativeError(ind, ref);
    // Samples behind the emitting side get nothing: the floor is unlit by a downward light.
    double up = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
        if (prt.samples.position[i].y > 0.4f) up += got[i];
    // The same square emitting isotropically and a point light at its centre, for scale.
    PrtLight iso = area;
    iso.normal = Vec3f{0, 0, 0};
    const std::vector<float> isoExact = exactDirectLight(prt.samples, box().tracer, iso);
    const double isoErr = rmsRelativeError(prtTransfer(prt, prtDirectLight(prt, iso)),
                                           referenceIndirect(prt.samples, box().tracer, isoExact));
    const std::vector<float> ptExact = exactDirectUnit(prt.samples, box().tracer, area.position);
    const double ptErr = rmsRelativeError(prtTransfer(prt, prtDirectUnit(prt, area.position)),
                                          referenceIndirect(prt.samples, box().tracer, ptExact));
    std::printf("area light: direct error %.4f, indirect error %.4f (isotropic square %.4f, point %.4f)\n", directErr,
                indErr, isoErr, ptErr);
    // Direct light is as exact as the compressed visibility. The indirect light of the
    // isotropic square is as good as a point light's; the one-sided square's was 0.53 with a
    // basis of point lights only, 0.31 with the default one-sided examples.
    EXPECT_LT(directErr, 0.1);
    EXPECT_LT(isoErr, ptErr * 1.2 + 0.02);
    EXPECT_LT(indErr, 0.4);
    EXPECT_EQ(up, 0.0);
    EXPECT_EQ(lightPoints(area).size(), 16u);
}

TEST(PrtBounces, FormatVersionWrittenAndUnknownVersionsRefused) {
    PrtOptions o = options(3);
    o.volumeResolution = 0;
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    test::TempDir dir;
    const std::string path = dir.file("p.vdb");
    writePrt(prt, path);
    const PrtData back = readPrt(path);
    EXPECT_EQ(back.bounces, 3);
    EXPECT_FALSE(back.closureNormalise);
    openvdb::io::File in(path);
    in.open();
    openvdb::GridPtrVecPtr grids = in.getGrids();
    openvdb::MetaMap::Ptr meta = in.getMetadata();
    in.close();
    ASSERT_TRUE(meta->getMetadata<openvdb::Int64Metadata>("vdblight:format_version"));
    EXPECT_EQ(meta->getMetadata<openvdb::Int64Metadata>("vdblight:format_version")->value(), 2);
    EXPECT_EQ(meta->getMetadata<openvdb::StringMetadata>("vdblight:kind")->value(), "prt");
    meta->removeMeta("vdblight:format_version");
    meta->insertMeta("vdblight:format_version", openvdb::Int64Metadata(99));
    const std::string future = dir.file("future.vdb");
    openvdb::io::File(future).write(*grids, *meta);
    try {
        readPrt(future);
        ADD_FAILURE() << "a PRT file of version 99 was accepted";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("PRT format version 99; this build reads PRT versions 1 to 2"),
                  std::string::npos) << e.what();
    }
    // A volume reader names a PRT file as such.
    try {
        readVolume(path);
        ADD_FAILURE() << "a PRT file was read as a volume";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("is a PRT file"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdblight
