// Numerical stress (issue 8): scene scale and position, dynamic range, degenerate geometry.
// Every bake must stay finite; where an answer is known (scale invariance of irradiance from
// emitters given as radiance, darkness outside a sealed box) it is checked.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "grids.h"
#include "one_point_light.h"
#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/export.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "scene/scene_origin.h"
#include "vdblight/query/query.h"
#include "bake/sh_window.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"

#include "support/scene_generators.h"

using namespace vdblight;
using vdblight::test::gridIn;

namespace {
Scene transformed(const Scene& in, double scale, const Vec3d& offset) {
    Scene s = in;
    for (Vec3f& p : s.positions) p = Vec3f(Vec3d(p) * scale + offset);
    return s;
}

bool allFinite(const Volume& v) {
    for (float x : v.levels[0].data)
        if (!std::isfinite(x)) return false;
    return true;
}

Volume bakeSmall(const Scene& s, const GridSpec& g, uint32_t rays = 64) {
    const Tracer tracer(s);
    GatherOptions o;
    o.raysPerNode = rays;
    o.transport.maxBounces = 3;
    return bakeShGather(s, tracer, g, o);
}

/// Expects every point's irradiance (luminance) in `got` to agree with `expected` within 4
/// combined standard errors + 1 % (a fatal failure if one is not finite); `worstZ` is the
/// largest |difference| / combined standard error. Failures name `what`.
void expectSameIrradiance(const std::vector<ReferenceResult>& expected, const std::vector<ReferenceResult>& got,
                          const std::string& what, double& worstZ) {
    worstZ = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const double e = luminance(Rgb(expected[i].irradiance)), g = luminance(Rgb(got[i].irradiance));
        const double se = std::hypot(luminance(Rgb(expected[i].standardError)), luminance(Rgb(got[i].standardError)));
        ASSERT_TRUE(std::isfinite(g)) << what;
        worstZ = std::max(worstZ, std::abs(g - e) / (se + 1e-12));
        EXPECT_NEAR(g, e, 4 * se + 0.01 * e) << what << " point " << i;
    }
}
}  // namespace

// Irradiance from emitters given as radiance does not depend on the scene's scale or position:
// the default scene scaled by 1e-4 .. 1e6 and moved far from the origin, against scale 1, at
// corresponding points (reference, independent noise), within 4 combined standard errors +1 %.
TEST(Stress, ScaleAndPositionInvariance) {
    const Scene base = loadScene(defaultScenePath());
    const Bounds b = base.bounds();
    Rng rng(3);
    std::vector<ReferencePoint> pts;
    for (int i = 0; i < 12; ++i) {
        const Vec3d t(0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform());
        pts.push_back({Vec3f(b.lo + b.size() * t), uniformSphere(rng.uniform(), rng.uniform())});
    }
    ReferenceOptions o;
    o.samples = 4096;
    o.transport.maxBounces = 3;
    const Tracer baseTracer(base);
    const auto expected = referenceIrradiance(base, baseTracer, pts, o);

    // Position is limited by float vertices: a scene of size S at distance D from the origin
    // has its vertices rounded by ~D * 6e-8: measured fine at D / S = 1.8e3 (the last two
    // cases), not at 1.8e4 (a 55-unit box 1e6 away: |z| = 12). The 0.55-unit box 1e5 away
    // (D / S = 2e5: vertices rounded by 1.4 % of the box) is only required to stay finite.
    struct Case { double scale; Vec3d offset; };
    for (const Case c : {Case{1e-4, {0, 0, 0}}, Case{1e4, {0, 0, 0}}, Case{1e6, {0, 0, 0}}, Case{1, {1e3, 0, 0}},
                         Case{1e3, {1e5, -1e5, 1e5}}}) {
        const Scene s = transformed(base, c.scale, c.offset);
        const Tracer tracer(s);
        std::vector<ReferencePoint> moved = pts;
        for (ReferencePoint& p : moved) p.position = Vec3f(Vec3d(p.position) * c.scale + c.offset);
        o.seed = 7;  // independent noise
        const auto got = referenceIrradiance(s, tracer, moved, o);
        const std::string what = "scale " + std::to_string(c.scale) + " offset " + std::to_string(c.offset.x);
        double worstZ = 0;
        ASSERT_NO_FATAL_FAILURE(expectSameIrradiance(expected, got, what, worstZ));
        // The bake at that scale stays finite and close to the bake at scale 1.
        const Volume v = bakeSmall(s, gridIn(s.bounds(), 3));
        EXPECT_TRUE(allFinite(v)) << "scale " << c.scale;
        std::printf("  scale %g, offset (%g, %g, %g): worst |z| %.2f over %zu points; bake finite\n", c.scale,
                    c.offset.x, c.offset.y, c.offset.z, worstZ, pts.size());
    }
}

// The default scene translated 1e5 units from the origin (docs/scene.md, "Large coordinates"):
// the scene keeps a double origin and float geometry relative to it, so irradiance at
// corresponding world points agrees with the untranslated scene within the Monte Carlo error
// (reference, independent noise: 4 combined standard errors + 1 %), and the baked volume,
// written to .vdb and read back, maps index space to world space and is queried at world
// points in double. (With the vertices themselves moved to 1e5 in float, the 0.55-unit box is
// rounded by 1.4 % of its size and this test fails: issue 8 notes.)
TEST(Stress, TranslatedFarFromTheOrigin) {
    const Scene base = loadScene(defaultScenePath());
    const Vec3d offset(1e5, 1e5, -1e5);
    Scene s = base;
    translateScene(s, offset);
    EXPECT_NEAR(s.worldBounds().lo.x, base.bounds().lo.x + offset.x, 1e-9);

    const Bounds b = base.bounds();
    Rng rng(5);
    std::vector<ReferencePoint> pts;
    std::vector<Vec3d> world;
    for (int i = 0; i < 12; ++i) {
        const Vec3d t(0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform(), 0.1 + 0.8 * rng.uniform());
        const Vec3d x = b.lo + b.size() * t;
        pts.push_back({Vec3f(x), uniformSphere(rng.uniform(), rng.uniform())});
        world.push_back(x + offset);
    }
    ReferenceOptions o;
    o.samples = 4096;
    o.transport.maxBounces = 3;
    const Tracer baseTracer(base);
    const auto expected = referenceIrradiance(base, baseTracer, pts, o);
    const Tracer tracer(s);
    std::vector<ReferencePoint> moved = pts;
    for (std::size_t i = 0; i < pts.size(); ++i) moved[i].position = s.toLocal(world[i]);  // world -> local frame
    o.seed = 7;  // independent noise
    const auto got = referenceIrradiance(s, tracer, moved, o);
    double worstZ = 0;
    ASSERT_NO_FATAL_FAILURE(expectSameIrradiance(expected, got, "translated", worstZ));
    std::printf("  offset (1e5, 1e5, -1e5): worst |z| %.2f over %zu points\n", worstZ, pts.size());

    // Bake in the local frame, place in the world, write and read back: the .vdb's grid sits at
    // the world position and a world query equals the untranslated volume's at local points.
    const GridSpec g = gridIn(s.bounds(), 4);
    Volume v = bakeSmall(s, g);
    ASSERT_TRUE(allFinite(v));
    const Volume vBase = bakeSmall(base, g);
    placeVolumeInWorld(v, s.origin);
    const test::TempDir dir;
    writeVolume(v, dir.file("far.vdb"));
    const Volume back = readVolume(dir.file("far.vdb"));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(back.levels[0].grid.origin[a], g.origin[a] + offset[a], 1e-9);
    const IrradianceQuery q(back), qBase(vBase);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const Vec3f n = normalize(pts[i].normal);
        const Rgb e = qBase.irradiance(pts[i].position, n), w = q.irradianceWorld(world[i], n);
        EXPECT_EQ(q.inside(world[i]), qBase.inside(pts[i].position));
        EXPECT_NEAR(luminance(w), luminance(e), 1e-4 * (std::abs(luminance(e)) + 1e-3)) << "point " << i;
    }
    // The outside policy works in world coordinates and names the world point.
    const IrradianceQuery strict(back, OutsidePolicy::Throw);
    EXPECT_NO_THROW(strict.irradianceWorld(back.levels[0].grid.nodeBounds().center(), Vec3f(0, 1, 0)));
    try {
        strict.irradianceWorld(offset - Vec3d(5, 5, 5), Vec3f(0, 1, 0));
        ADD_FAILURE() << "no exception outside the volume";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("99995"), std::string::npos) << e.what();
    }
    // Exported textures sample the far volume at its world lattice: the same texels as the
    // untranslated volume's, the lattice moved by the offset.
    ExportOptions eo;
    eo.format = TextureFormat::Raw;
    eo.halfFloat = false;
    const ExportSummary far = exportTextures(back, dir.file("far_tex"), eo);
    const ExportSummary nearS = exportTextures(vBase, dir.file("near_tex"), eo);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(far.lattice.lo[a], nearS.lattice.lo[a] + offset[a], 1e-9);
    ASSERT_EQ(far.files.size(), nearS.files.size());
    std::ifstream f0(far.files[0], std::ios::binary), f1(nearS.files[0], std::ios::binary);
    const std::string t0((std::istreambuf_iterator<char>(f0)), {}), t1((std::istreambuf_iterator<char>(f1)), {});
    ASSERT_EQ(t0.size(), t1.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i + 4 <= t0.size(); i += 4) {
        float x0, x1;
        std::memcpy(&x0, t0.data() + i, 4);
        std::memcpy(&x1, t1.data() + i, 4);
        if (std::abs(x0 - x1) > 1e-4f * (std::abs(x1) + 1e-3f)) ++differ;
    }
    EXPECT_EQ(differ, 0u) << "of " << t0.size() / 4 << " floats in " << far.files[0];
}

// Loading recentres a scene far from the origin: the geometry is rewritten relative to a
// rounded anchor (exactly, in double), the origin carries the rest, and nothing moves near the
// origin.
TEST(Stress, RecenteringKeepsWorldPositions) {
    Scene s = loadScene(defaultScenePath());
    EXPECT_EQ(recenterScene(s), Vec3d(0, 0, 0));  // near the origin: untouched
    Scene far = transformed(s, 1e3, Vec3d(1e5, -1e5, 1e5));
    const Scene before = far;
    const Vec3d shift = recenterScene(far);
    EXPECT_NE(shift, Vec3d(0, 0, 0));
    EXPECT_EQ(far.origin, shift);
    for (std::size_t i = 0; i < far.positions.size(); ++i)
        for (int a = 0; a < 3; ++a)
            EXPECT_EQ(far.toWorld(far.positions[i])[a], double(before.positions[i][a])) << i;  // exact: small integers of ulps
    const Vec3d c = far.bounds().center(), size = far.bounds().size();
    EXPECT_LT(length(c), length(size));
}

// Nodes exactly on surfaces, on shared edges and at corners of the box: finite, non-negative
// mean irradiance (the SH DC term).
TEST(Stress, NodesExactlyOnSurfacesEdgesAndCorners) {
    const Scene s = loadScene(defaultScenePath());
    const Bounds b = s.bounds();
    GridSpec g;
    g.origin = b.lo;  // node (0,0,0) is a corner of the box; nodes on faces and edges
    g.spacing = b.size().x / 4;
    g.nx = 5, g.ny = 5, g.nz = 5;
    const Volume v = bakeSmall(s, g);
    ASSERT_TRUE(allFinite(v));
    for (std::size_t n = 0; n < g.nodeCount(); ++n) EXPECT_GE(v.levels[0].data[n * 27 + 1], -1e-3f) << "node " << n;
}

// Zero-area and duplicate (coincident) triangles and grazing rays along shared edges.
TEST(Stress, DegenerateAndCoincidentTriangles) {
    Scene s = loadScene(defaultScenePath());
    const std::size_t before = s.triangleCount();
    const Vec3f a = s.vertex(0, 0), b = s.vertex(0, 1), c = s.vertex(0, 2);
    addTriangle(s, a, a, b, 0);                // zero area: two equal vertices
    addTriangle(s, a, (a + b) * 0.5f, b, 0);   // zero area: collinear
    addTriangle(s, a, b, c, 1);                // coincident with triangle 0, other material
    EXPECT_EQ(s.triangleCount(), before + 1);
    EXPECT_EQ(s.stats.degenerateTrianglesSkipped, 2u);
    const Volume v = bakeSmall(s, gridIn(s.bounds(), 4));
    EXPECT_TRUE(allFinite(v));
}

// A light sealed inside a closed box: everything outside is exactly dark, inside is lit.
TEST(Stress, LightSealedInsideAClosedBox) {
    Scene s;
    s.name = "sealed";
    s.materials.resize(2);
    s.materials[0].albedo = Rgb(0.5f, 0.5f, 0.5f);
    s.materials[1].emission = Rgb(10, 10, 10);
    s.materials[1].twoSidedEmission = true;
    appendBox(s, Vec3f(0, 0, 0), Vec3f(1, 1, 1), true, 0);
    appendIcosphere(s, Vec3f(0.5f, 0.5f, 0.5f), 0.05f, 1, 1);
    appendBox(s, Vec3f(-2, -2, -2), Vec3f(-1.5f, -1.5f, -1.5f), false, 0);  // something outside
    const Tracer tracer(s);
    GatherOptions o;
    o.raysPerNode = 128;
    GridSpec g;
    g.origin = Vec3d(-1, 0.25, 0.25);
    g.spacing = 0.5;
    g.nx = 6, g.ny = 2, g.nz = 2;  // x = -1, -0.5, 0, 0.5, 1, 1.5: outside, outside, wall, inside, wall, outside
    const Volume v = bakeShGather(s, tracer, g, o);
    ASSERT_TRUE(allFinite(v));
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j) {
            for (int i : {0, 1, 5}) {
                const float* c = v.levels[0].data.data() + g.index(i, j, k) * 27;
                for (int q = 0; q < 27; ++q) EXPECT_EQ(c[q], 0.0f) << "outside node " << i << "," << j << "," << k;
            }
            EXPECT_GT(v.levels[0].data[g.index(3, j, k) * 27], 0.0f) << "inside node";
        }
}

// Dynamic range: a tiny light 1e6 times brighter than a dim sky over a ground plane stays
// finite; a radiance that overflows float storage is refused by the writer and leaves no file.
TEST(Stress, DynamicRangeAndOverflow) {
    Scene s;
    s.name = "range";
    s.materials.resize(2);
    s.materials[1].emission = Rgb(1e3f, 1e3f, 1e3f);
    appendDisk(s, Vec3f(0, 0, 0), 10.0f, 8, 0);
    appendIcosphere(s, Vec3f(0, 0, 1), 0.01f, 1, 1);
    s.sky.constant = Rgb(1e-3f, 1e-3f, 1e-3f);
    const GridSpec g = gridIn(s.bounds(), 4);
    const Volume v = bakeSmall(s, g, 256);
    EXPECT_TRUE(allFinite(v));

    // Every surface emitting 3e38 (near FLT_MAX): a node above the ground sees it over a whole
    // hemisphere, and its SH DC coefficient (radiance x 2 pi Y00, about 5e38) leaves float range.
    // The bake must overflow, so that the writer's refusal below is always exercised. (The
    // tiny light alone at 3e38 does not overflow: the test's old branch never ran.)
    s.materials[0].emission = Rgb(3e38f, 3e38f, 3e38f);
    s.materials[1].emission = Rgb(3e38f, 3e38f, 3e38f);
    const Volume hot = bakeSmall(s, g, 16);
    ASSERT_FALSE(allFinite(hot)) << "an emission of 3e38 on every surface no longer overflows float storage; the "
                                    "overflow check needs a brighter input";
    test::TempDir dir;
    const std::string path = dir.file("hot.vdb");
    EXPECT_THROW(writeVolume(hot, path, WriteOptions{}), ValueError);
    EXPECT_FALSE(std::filesystem::exists(path));
    // The same refusal for one infinite and one NaN coefficient in an otherwise good volume.
    for (float bad : {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
        Volume one = v;
        one.levels[0].data[one.levels[0].data.size() / 2] = bad;
        EXPECT_THROW(writeVolume(one, path, WriteOptions{}), ValueError) << bad;
        EXPECT_FALSE(std::filesystem::exists(path)) << bad;
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "no temporary file is left either";
    EXPECT_NO_THROW(writeVolume(v, path, WriteOptions{}));  // the finite volume is written
    std::printf("  emission 3e38: the bake overflows float; the writer refuses it and leaves no file\n");
}

// Half precision: the error the 16-bit storage adds, measured on a baked volume, bounded by
// half a unit in the last place (2^-11 relative) for normal halves plus an absolute 2^-25 for
// subnormal ones; irradiance through the query changes by less than 0.1 % of the mean.
TEST(Stress, HalfPrecisionErrorIsBounded) {
    const Scene s = loadScene(defaultScenePath());
    const GridSpec g = gridIn(s.bounds(), 4);
    const Volume v = bakeSmall(s, g, 128);
    test::TempDir dir;
    WriteOptions half;
    half.halfFloat = true;
    writeVolume(v, dir.file("h.vdb"), half);
    const Volume h = readVolume(dir.file("h.vdb"));
    ASSERT_EQ(h.levels[0].data.size(), v.levels[0].data.size());
    double worstRel = 0;
    for (std::size_t i = 0; i < v.levels[0].data.size(); ++i) {
        const double a = v.levels[0].data[i], b = h.levels[0].data[i];
        EXPECT_LE(std::abs(a - b), std::abs(a) * std::ldexp(1.0, -11) + std::ldexp(1.0, -25)) << "value " << i;
        if (std::abs(a) > 6.2e-5) worstRel = std::max(worstRel, std::abs(a - b) / std::abs(a));
    }
    std::printf("  half storage: worst relative error of a coefficient %.2e (bound %.2e)\n", worstRel, std::ldexp(1.0, -11));
    EXPECT_GT(worstRel, 0.0);  // half storage did round something: the comparison is real
}

// SH ringing: one point light, direct light only. The order-2 irradiance goes negative
// behind the light (-0.040 of the peak in theory); the window removes that, at an error cost
// against the exact clamped cosine that is printed.
TEST(Stress, ShRingingAndTheWindow) {
    const Volume raw = test::bakeOnePointLight();
    Volume windowed = raw;
    applyShWindow(windowed);
    EXPECT_THROW(applyShWindow(windowed), ValueError);
    const IrradianceQuery qr(raw), qw(windowed);
    const Vec3f x(0.5f, 0.5f, 0.5f);  // a node
    const Vec3f toLight = normalize(Vec3f(0, 0, 2) - x);
    const double peak = 4.0 / double(dot(Vec3f(0, 0, 2) - x, Vec3f(0, 0, 2) - x));
    double minRaw = 1e30, minWin = 1e30, errRaw = 0, errWin = 0;
    Rng rng(1);
    const int normals = 4000;
    for (int i = 0; i < normals; ++i) {
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const double exact = peak * std::max(0.0f, dot(n, toLight));
        const double r = qr.irradiance(x, n).x, w = qw.irradiance(x, n).x;
        minRaw = std::min(minRaw, r);
        minWin = std::min(minWin, w);
        errRaw += (r - exact) * (r - exact);
        errWin += (w - exact) * (w - exact);
    }
    errRaw = std::sqrt(errRaw / normals) / peak;
    errWin = std::sqrt(errWin / normals) / peak;
    std::printf("  one point light: most negative irradiance %.4f of the peak raw, %.2e windowed; RMS error over "
                "normals %.4f raw, %.4f windowed (of the peak)\n", minRaw / peak, minWin / peak, errRaw, errWin);
    EXPECT_LT(minRaw / peak, -0.03);  // the ringing is there (theory: -0.0396)
    EXPECT_GE(minWin / peak, -1e-5);  // and the window removes it
}
