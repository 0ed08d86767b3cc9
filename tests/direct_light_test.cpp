// Exact unshadowed irradiance of the lights a volume lists (direct_light.h) and the grouping
// of a scene's emissive triangles into polygon lights (scene_lights.h).
#include <gtest/gtest.h>

#include <cmath>

#include "vdblight/light/direct_light.h"
#include "vdblight/core/errors.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {

DirectLight quadLight(const Vec3d& corner, const Vec3d& e1, const Vec3d& e2, const Rgb& radiance, bool twoSided = false) {
    DirectLight l;
    l.kind = DirectLight::Kind::Polygon;
    l.value = radiance;
    l.twoSided = twoSided;
    l.normal = normalize(cross(e1, e2));
    l.loops = {{corner, corner + e1, corner + e1 + e2, corner + e2}};
    return l;
}

/// Irradiance of a one- or two-sided parallelogram light by the midpoint rule over its area:
/// L * max(0, cos at the receiver) * |cos at the light| / d^2, emitting side only.
double numericalQuad(const Vec3d& corner, const Vec3d& e1, const Vec3d& e2, double L, bool twoSided, const Vec3d& x,
                     const Vec3d& n, int steps) {
    const Vec3d nl = normalize(cross(e1, e2));
    const double dA = length(cross(e1, e2)) / (double(steps) * steps);
    double sum = 0;
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < steps; ++j) {
            const Vec3d q = corner + e1 * ((i + 0.5) / steps) + e2 * ((j + 0.5) / steps);
            const Vec3d d = q - x;
            const double d2 = dot(d, d), dist = std::sqrt(d2);
            const double cr = dot(n, d) / dist;
            double cl = -dot(nl, d) / dist;  // > 0 when x sees the front
            if (twoSided) cl = std::abs(cl);
            if (cr > 0 && cl > 0) sum += cr * cl / d2;
        }
    return L * sum * dA;
}

}  // namespace

TEST(ExactIrradiance, PolygonMatchesNumericalIntegrationPartlyBelowHorizon) {
    // A 1 x 0.8 panel facing -z at height 0.3; receivers whose tangent plane cuts it.
    const Vec3d corner(-0.5, -0.4, 0.3), e1(0, 0.8, 0), e2(1.0, 0, 0);  // e1 x e2 = -z: faces down
    const DirectLight light = quadLight(corner, e1, e2, Rgb(2.0f, 1.0f, 0.5f));
    ASSERT_NEAR(light.normal.z, -1.0, 1e-12);
    struct Case { Vec3d x, n; };
    const Case cases[] = {
        {{0, 0, 0}, normalize(Vec3d(1, 0, 0.3))},     // horizon cuts the panel near its middle
        {{0.2, -0.1, 0.05}, normalize(Vec3d(-1, 0.5, 0.2))},
        {{0.4, 0.3, 0.25}, normalize(Vec3d(0.3, -1, 0.1))},  // close below, steep cut
        {{0, 0, 0}, Vec3d(0, 0, 1)},                  // fully visible
        {{0.9, 0.1, -0.2}, normalize(Vec3d(-1, 0, -1.2))},  // off to the side, cut at x = 0.3
    };
    for (const Case& c : cases) {
        const double exact = exactIrradiance(light, c.x, c.n).x;
        const double numeric = numericalQuad(corner, e1, e2, 2.0, false, c.x, c.n, 2000);
        EXPECT_GT(numeric, 1e-3);
        EXPECT_NEAR(exact / numeric, 1.0, 1e-4) << "x " << c.x.x << " " << c.x.y << " " << c.x.z;
        EXPECT_NEAR(exactIrradiance(light, c.x, c.n).y / exact, 0.5, 1e-6);  // linear in radiance
    }
    // Entirely below the horizon, and behind a one-sided light: 0.
    EXPECT_EQ(exactIrradiance(light, {0, 0, 0}, {0, 0, -1}).x, 0.0f);
    EXPECT_EQ(exactIrradiance(light, {0, 0, 1}, {0, 0, -1}).x, 0.0f);
}

TEST(ExactIrradiance, TwoSidedPolygonFromBehind) {
    const Vec3d corner(-0.5, -0.4, 0.3), e1(0, 0.8, 0), e2(1.0, 0, 0);
    const DirectLight light = quadLight(corner, e1, e2, Rgb(1, 1, 1), true);
    const Vec3d x(0.1, 0.2, 0.9), n = normalize(Vec3d(0.4, 0, -1));
    const double numeric = numericalQuad(corner, e1, e2, 1.0, true, x, n, 2000);
    EXPECT_NEAR(exactIrradiance(light, x, n).x / numeric, 1.0, 1e-4);
}

TEST(ExactIrradiance, NonConvexLoopClipped) {
    // An L-shaped loop (counter-clockwise around -z) = two rectangles; clipping through both arms.
    DirectLight l;
    l.kind = DirectLight::Kind::Polygon;
    l.value = Rgb(1, 1, 1);
    l.normal = {0, 0, -1};
    const double z = 0.5;
    // Listed clockwise seen from +z, i.e. counter-clockwise around the normal -z.
    l.loops = {{{-0.5, 0, z}, {-0.5, 0.5, z}, {-1, 0.5, z}, {-1, 1, z}, {0, 1, z}, {0, 0, z}}};
    const Vec3d x(-0.3, 0.4, 0), n = normalize(Vec3d(-0.2, 1, 0.3));
    const double numeric = numericalQuad({-0.5, 0, z}, {0, 0.5, 0}, {0.5, 0, 0}, 1.0, false, x, n, 1500) +
                           numericalQuad({-1, 0.5, z}, {0, 0.5, 0}, {1, 0, 0}, 1.0, false, x, n, 1500);
    ASSERT_NEAR(l.area(), 0.75, 1e-12);
    EXPECT_NEAR(exactIrradiance(l, x, n).x / numeric, 1.0, 1e-4);
}

TEST(ExactIrradiance, PunctualClosedForms) {
    DirectLight p;
    p.kind = DirectLight::Kind::Point;
    p.position = {1, 2, 3};
    p.value = Rgb(4, 8, 2);
    const Vec3d x(0.5, 1.0, 1.0), n = normalize(Vec3d(0.2, 0.3, 1));
    const Vec3d d = p.position - x;
    const double cosine = dot(n, normalize(d));
    EXPECT_NEAR(exactIrradiance(p, x, n).y, 8.0 * cosine / dot(d, d), 1e-5);
    EXPECT_EQ(exactIrradiance(p, x, -n).y, 0.0f);
    EXPECT_NEAR(meanIrradiance(p, x).x, 4.0 / (4.0 * dot(d, d)), 1e-6);

    DirectLight s = p;
    s.kind = DirectLight::Kind::Spot;
    s.direction = {0, 0, -1};
    s.innerCone = 0.2;
    s.outerCone = 0.6;
    // On the axis: full intensity. Between the cones: ((c - cos outer) / (cos inner - cos outer))^2.
    const Vec3d below(1, 2, 1);
    EXPECT_NEAR(exactIrradiance(s, below, {0, 0, 1}).x, 4.0 / 4.0, 1e-6);
    const double angle = 0.4;
    const Vec3d off = s.position + Vec3d(std::sin(angle), 0, -std::cos(angle)) * 2.0;
    const double t = (std::cos(angle) - std::cos(0.6)) / (std::cos(0.2) - std::cos(0.6));
    const Vec3d toLight = normalize(s.position - off);
    EXPECT_NEAR(exactIrradiance(s, off, toLight).x, 4.0 * t * t / 4.0, 1e-6);
    const Vec3d outside = s.position + Vec3d(std::sin(0.7), 0, -std::cos(0.7));
    EXPECT_EQ(exactIrradiance(s, outside, normalize(s.position - outside)).x, 0.0f);

    DirectLight sun;
    sun.kind = DirectLight::Kind::Directional;
    sun.direction = normalize(Vec3d(1, -2, 0.5));
    sun.value = Rgb(3, 3, 3);
    EXPECT_NEAR(exactIrradiance(sun, x, n).x, 3.0 * std::max(0.0, -dot(n, sun.direction)), 1e-6);
    EXPECT_NEAR(exactIrradiance(sun, x, -sun.direction).x, 3.0, 1e-6);
}

TEST(ExactIrradiance, MeanIrradianceIsTheAverageOverNormals) {
    const DirectLight light = quadLight({-0.5, -0.4, 0.3}, {0, 0.8, 0}, {1.0, 0, 0}, Rgb(1, 1, 1));
    const Vec3d x(0.3, 0.1, -0.2);
    // Average of exactIrradiance over a fine grid of normals on the sphere (area-weighted).
    double sum = 0, weight = 0;
    const int m = 400;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < 2 * m; ++j) {
            const double theta = kPi * (i + 0.5) / m, phi = kPi * (j + 0.5) / m;
            const Vec3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            sum += exactIrradiance(light, x, n).x * std::sin(theta);
            weight += std::sin(theta);
        }
    EXPECT_NEAR(meanIrradiance(light, x).x / (sum / weight), 1.0, 1e-3);
}

TEST(ExactIrradiance, TextRoundTrip) {
    DirectLight l = quadLight({0.1, 0.2, 0.3}, {0, 0.8, 0}, {1.0, 0, 0}, Rgb(1.5f, 2.5f, 0.25f), true);
    const DirectLight back = parseDirectLight(formatDirectLight(l));
    EXPECT_EQ(back.kind, l.kind);
    EXPECT_EQ(back.value, l.value);
    EXPECT_EQ(back.twoSided, true);
    ASSERT_EQ(back.loops.size(), 1u);
    EXPECT_EQ(back.loops[0][2], l.loops[0][2]);
    DirectLight s;
    s.kind = DirectLight::Kind::Spot;
    s.position = {1, 2, 3};
    s.direction = {0, 0, -1};
    s.innerCone = 0.25;
    s.outerCone = 0.5;
    s.value = Rgb(7, 7, 7);
    const DirectLight sb = parseDirectLight(formatDirectLight(s));
    EXPECT_EQ(sb.position, s.position);
    EXPECT_EQ(sb.outerCone, 0.5);
    EXPECT_THROW(parseDirectLight("kind=lamp;value=1 1 1"), FormatError);
    EXPECT_THROW(parseDirectLight("kind=polygon;value=1 1 1"), FormatError);
    EXPECT_THROW(parseDirectLight("kind=point;value=1 nan 1"), FormatError);
}

TEST(SceneLights, QuadOfTwoTrianglesIsOnePolygonAndMatchesTheEstimator) {
    // A downward-facing quad luminaire (two triangles) and a separate small emissive
    // triangle of another material; a far dark floor so the scene has geometry to hit.
    Scene s;
    Material lamp;
    lamp.emission = Rgb(5, 5, 5);
    lamp.albedo = Rgb(0, 0, 0);
    const uint32_t m = addMaterial(s, lamp);
    Material other = lamp;
    other.emission = Rgb(1, 2, 3);
    const uint32_t m2 = addMaterial(s, other);
    const Vec3f a(-0.5f, 1, -0.4f), b(0.5f, 1, -0.4f), c(0.5f, 1, 0.4f), d(-0.5f, 1, 0.4f);
    // Facing -y: (b - a) x (c - a) = (1,0,0) x (1,0,0.8) = (0, -0.8, 0).
    addTriangle(s, a, b, c, m);
    addTriangle(s, a, c, d, m);
    addTriangle(s, Vec3f(3, 2, 0), Vec3f(3.5f, 2, 0), Vec3f(3, 2, 0.5f), m2);
    const std::vector<SceneLight> lights = sceneLights(s);
    ASSERT_EQ(lights.size(), 2u);
    ASSERT_EQ(lights[0].triangles.size(), 2u);
    ASSERT_EQ(lights[0].light.loops.size(), 1u);
    EXPECT_EQ(lights[0].light.loops[0].size(), 4u);  // the quad's outline, not two triangles
    EXPECT_NEAR(lights[0].light.area(), 0.8, 1e-6);
    EXPECT_NEAR(lights[0].light.normal.y, -1.0, 1e-9);

    // Exact irradiance of the grouped light against the estimator's direct light (bounces 0).
    // `reference` at one seed errs by up to 2 % here while reporting 0.15 %: its light point and
    // light choice share one stratified index, so a grazing light is not sampled evenly. The
    // mean over 16 seeds (16 scrambles) comes within about 0.5 %.
    const Tracer tracer(s);
    std::vector<ReferencePoint> pts = {{{0.2f, 0.3f, 0.1f}, {0.3f, 1, 0.2f}}, {{0.9f, 0.6f, 0}, {-1, 0.2f, 0}}};
    std::vector<double> ref(pts.size(), 0.0);
    for (uint64_t seed = 1; seed <= 16; ++seed) {
        ReferenceOptions ro;
        ro.samples = 1 << 14;
        ro.seed = seed;
        ro.transport.maxBounces = 0;
        const auto r = referenceIrradiance(s, tracer, pts, ro);
        for (std::size_t i = 0; i < pts.size(); ++i) ref[i] += r[i].irradiance.x / 16;
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const Vec3d xp(pts[i].position), np = normalize(Vec3d(pts[i].normal));
        EXPECT_NEAR(exactIrradiance(lights[0].light, xp, np).x /
                        numericalQuad(Vec3d(a), Vec3d(b - a), Vec3d(d - a), 5.0, false, xp, np, 1000), 1.0, 1e-4);
        const Rgb e = exactIrradiance(lights[0].light, Vec3d(pts[i].position), normalize(Vec3d(pts[i].normal))) +
                      exactIrradiance(lights[1].light, Vec3d(pts[i].position), normalize(Vec3d(pts[i].normal)));
        EXPECT_NEAR(e.x / ref[i], 1.0, 0.015) << i;
    }
}

