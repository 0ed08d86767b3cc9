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
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/scene/scene.h"
#include "basis/sh.h"
#include "vdblight/trace/trace.h"

#include "support/scene_generators.h"

namespace vdblight {
namespace {

float relativeDifference(const Rgb& a, const Rgb& b) {
    const Rgb d = a - b;
    return (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) / (std::abs(b.x) + std::abs(b.y) + std::abs(b.z) + 1e-6f);
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
    const std::vector<float> d = exactDirectUnit(prt.samples, box().scene, box().tracer, light);
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

TEST(PrtBounces, RelitVolumeIsAnOcclusionVolume) {
    // With the scene, the relit volume is a `--direct occlusion` volume: the SH is the
    // reflected light alone (the same bits as without the scene), the lights are listed, and
    // IrradianceQuery adds exactIrradiance times the visibility channel. At a node the channel
    // is the node's own: 1 where a shadow ray to a point light is free, 0 where it is blocked
    // (checked here with an independent ray), so the lookup there is the SH part plus the
    // exact irradiance, or the SH part alone.
    const PrtData prt = bakePrt(box().scene, box().tracer, options(2));
    const DirectLight light = test::pointLight(Vec3f{0.2f, 0.45f, 0.2f}, Rgb{1, 2, 3});
    const Volume indirect = relightVolume(prt, {light});
    const Volume complete = relightVolume(prt, {light}, &box().scene, &box().tracer);
    EXPECT_EQ(complete.levels[0].data, indirect.levels[0].data);
    EXPECT_EQ(indirect.direct.mode, DirectMode::Baked);
    ASSERT_EQ(complete.direct.mode, DirectMode::Occlusion);
    ASSERT_EQ(complete.direct.lights.size(), 1u);
    EXPECT_EQ(complete.direct.lights[0].position, light.position);  // origin 0: local is world
    const GridSpec& grid = complete.levels[0].grid;
    ASSERT_EQ(complete.levels[0].lightVisibility.size(), grid.nodeCount());
    const IrradianceQuery withDirect(complete), without(indirect);
    int seen = 0, blocked = 0;
    for (std::size_t node = 0; node < grid.nodeCount(); ++node) {
        const Vec3f x(grid.node(node));
        const Vec3f toLight = Vec3f(light.position) - x;
        const Vec3f n = normalize(toLight);  // facing the light: exact irradiance I / d^2
        const bool free = !box().tracer.occluded(Ray{x, toLight, 0.0f, 1.0f - 1e-4f});
        EXPECT_EQ(complete.levels[0].lightVisibility[node], free ? 1.0f : 0.0f) << node;
        const Rgb e = exactIrradiance(light, Vec3d(x), Vec3d(n));
        ASSERT_GT(e.x, 0.0f);
        const Rgb want = without.irradiance(x, n) + (free ? e : Rgb{0, 0, 0});
        const Rgb got = withDirect.irradiance(x, n);
        EXPECT_LT(relativeDifference(got, want), 1e-4f) << "node " << node << (free ? " lit" : " shadowed");
        (free ? seen : blocked) += 1;
    }
    std::printf("occlusion volume: %d nodes see the light, %d are shadowed\n", seen, blocked);
    EXPECT_GT(seen, 10);
    EXPECT_GT(blocked, 3);
    EXPECT_THROW(relightVolume(prt, {light}, &box().scene, nullptr), ValueError);
    EXPECT_THROW(bakePrt(box().scene, box().tracer, options(0)), ValueError);
}

TEST(PrtBounces, PolygonLightIsItsPointsAndMatchesTheExactLight) {
    // A downward square panel under the ceiling (DirectLight polygon, squareLight): through the
    // compressed visibility it is exactly its 4 x 4 cell-centre points, each a cosine emitter
    // of a sixteenth of the area (built here from prtDirectUnit of isotropic points); against
    // the shared exact direct light (Lambert's formula times visibility by shadow rays) it is
    // within the compressed visibility's error; given as a five-vertex loop (the general
    // triangle path instead of the parallelogram grid) it is the same light within the
    // discretisation's difference. Its indirect light goes through the basis as before
    // (prt_oriented_test compares the bases with and without one-sided examples).
    PrtOptions o = options(1);
    o.transferCoeffs = 32;
    o.volumeResolution = 0;
    o.orientedTraining = PrtOptions{}.orientedTraining;  // the default basis
    const PrtData prt = bakePrt(box().scene, box().tracer, o);
    const Vec3d centre(0.28, 0.40, 0.28);
    const DirectLight panel = squareLight(centre, {0, -1, 0}, 0.1, Rgb{2, 2, 2});
    EXPECT_NEAR(panel.value.x, 200.0f, 1e-3f);  // radiance = intensity / area
    const std::vector<float> got = prtDirectLight(prt, panel, 4);
    std::vector<float> points(got.size(), 0.0f);
    const Vec3f corner = Vec3f(panel.loops[0][0]), e1 = Vec3f(panel.loops[0][1] - panel.loops[0][0]),
                e3 = Vec3f(panel.loops[0][3] - panel.loops[0][0]);
    for (int a = 0; a < 16; ++a) {
        const Vec3f c = corner + e1 * ((float(a % 4) + 0.5f) / 4) + e3 * ((float(a / 4) + 0.5f) / 4);
        const std::vector<float> unit = prtDirectUnit(prt, c);
        for (std::size_t i = 0; i < got.size(); ++i) {
            const float cosine = -normalize(prt.samples.position[i] - c).y;  // emitting downwards
            if (cosine > 0) points[i] += unit[i] * cosine * 0.01f / 16;
        }
    }
    const auto grey = [](const std::vector<float>& d) {
        std::vector<Rgb> out(d.size());
        for (std::size_t i = 0; i < d.size(); ++i) out[i] = Rgb{d[i], d[i], d[i]};
        return out;
    };
    const double pointsErr = rmsRelativeError(grey(got), grey(points));
    const std::vector<float> exact = exactDirectLight(prt.samples, box().scene, box().tracer, panel);
    const double directErr = rmsRelativeError(grey(got), grey(exact));
    DirectLight five = panel;  // the same square with a vertex in the middle of one edge
    five.loops[0].insert(five.loops[0].begin() + 1, 0.5 * (panel.loops[0][0] + panel.loops[0][1]));
    const std::vector<float> fiveGot = prtDirectLight(prt, five, 4);
    const double shapeErr = rmsRelativeError(grey(fiveGot), grey(got));
    const double fiveExactErr = rmsRelativeError(grey(exactDirectLight(prt.samples, box().scene, box().tracer, five)),
                                                 grey(exact));
    const double indErr = rmsRelativeError(prtTransfer(prt, got), referenceIndirect(prt.samples, box().tracer, exact));
    std::printf("polygon light: its points %.2e, direct error vs exact %.4f, five-vertex loop vs square %.4f "
                "(exact %.2e), indirect error %.4f\n", pointsErr, directErr, shapeErr, fiveExactErr, indErr);
    EXPECT_LT(pointsErr, 1e-5);
    EXPECT_LT(directErr, 0.1);
    EXPECT_LT(shapeErr, 0.05);
    EXPECT_LT(fiveExactErr, 1e-3);  // the exact reference does not depend on how the loop is drawn
    EXPECT_LT(indErr, 0.4);
    // Samples behind the emitting side get nothing: above the panel nothing is lit.
    double up = 0, lit = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        if (prt.samples.position[i].y > 0.4f) up += got[i] + fiveGot[i] + exact[i];
        lit += got[i];
    }
    EXPECT_EQ(up, 0.0);
    EXPECT_GT(lit, 0.0);
    // relightPrt is the same light times its radiance; a directional light is refused.
    const PrtLighting relit = relightPrt(prt, {panel}, PrtRelightOptions{4});
    for (std::size_t i = 0; i < got.size(); i += 17) EXPECT_FLOAT_EQ(relit.direct[i].x, got[i] * 200.0f) << i;
    DirectLight sun;
    sun.kind = DirectLight::Kind::Directional;
    sun.value = Rgb{1, 1, 1};
    EXPECT_THROW(relightPrt(prt, {sun}), ValueError);
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
