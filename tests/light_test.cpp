// `reference` against closed forms: an emissive disk and sphere seen from their axis
// (E = pi L sin^2 alpha), the white furnace (E = pi Le / (1 - rho)), punctual lights
// (E = I cos / d^2). Required accuracy: 0.5 %.
#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

using namespace vdblight;

namespace {
std::vector<ReferenceResult> reference(const Scene& s, const std::vector<ReferencePoint>& points,
                                       uint32_t samples = 1 << 16, int bounces = 8) {
    const Tracer tracer(s);
    ReferenceOptions o;
    o.samples = samples;
    o.transport.maxBounces = bounces;
    return referenceIrradiance(s, tracer, points, o);
}

void expectRelative(const Rgbd& got, const Rgbd& expected, double tolerance, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], expected[c], tolerance * std::abs(expected[c]) + 1e-12)
            << what << " channel " << c << ": got " << got[c] << ", expected " << expected[c];
}
}  // namespace

TEST(Reference, EmissiveDiskOnItsAxis) {
    float reff;
    const Rgb L{2.0f, 1.0f, 0.5f};
    const Scene disk = test::makeEmissiveDisk(1.0f, L, 512, &reff);
    std::vector<ReferencePoint> points;
    for (float h : {0.25f, 1.0f, 3.0f}) points.push_back({{0, 0, h}, {0, 0, -1}});
    const auto r = reference(disk, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double h = points[i].position.z;
        const double sin2 = double(reff) * reff / (double(reff) * reff + h * h);
        expectRelative(r[i].irradiance, Rgbd(L) * (kPi * sin2), 0.005, "disk h=" + std::to_string(h));
        // The reported standard error is non-zero and small. (It is the i.i.d. estimate, an
        // upper bound for stratified samples; near the disk area sampling has more variance.)
        EXPECT_GT(r[i].standardError.x, 0.0);
        EXPECT_LT(r[i].standardError.x, 0.01 * r[i].irradiance.x);
    }
    // Behind the disk (it emits towards +z only): nothing.
    const auto behind = reference(disk, {{{0, 0, -1}, {0, 0, 1}}}, 4096);
    EXPECT_EQ(behind[0].irradiance.x, 0.0);
}

TEST(Reference, EmissiveSphereFromOutside) {
    float reff;
    const Rgb L{1.0f, 3.0f, 0.25f};
    const Scene sphere = test::makeEmissiveSphere(1.0f, L, 5, &reff);
    std::vector<ReferencePoint> points = {{{0, 0, 3}, {0, 0, -1}}, {{2, 0, 0}, {-1, 0, 0}}, {{0, -1.5f, 0}, {0, 1, 0}}};
    const auto r = reference(sphere, points);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double d = length(Vec3d(points[i].position));
        expectRelative(r[i].irradiance, Rgbd(L) * (kPi * reff * reff / (d * d)), 0.005, "sphere d=" + std::to_string(d));
    }
}

TEST(Reference, WhiteFurnace) {
    const Rgb Le{1.0f, 0.5f, 2.0f};
    const float rho = 0.5f;
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, Le, {rho, rho, rho});
    std::vector<ReferencePoint> points = {
        {{0, 0, 0}, {0, 0, 1}}, {{0.5f, -0.3f, 0.8f}, {1, 1, 0}}, {{-0.9f, 0.9f, 0.1f}, {-0.2f, 0.3f, -1}}};
    const auto r = reference(box, points, 1 << 16, 200);
    for (std::size_t i = 0; i < points.size(); ++i)
        expectRelative(r[i].irradiance, Rgbd(Le) * (kPi / (1.0 - rho)), 0.005, "furnace point " + std::to_string(i));
}

TEST(Reference, FurnaceWithLimitedBouncesSumsTheGeometricSeries) {
    // maxBounces = B keeps B reflections: E = pi Le (1 - rho^(B+1)) / (1 - rho).
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {0.6f, 0.6f, 0.6f});
    for (int b : {0, 1, 3}) {
        const auto r = reference(box, {{{0.1f, 0.2f, 0.3f}, {0, 1, 0}}}, 1 << 15, b);
        const double expected = kPi * (1 - std::pow(0.6, b + 1)) / (1 - 0.6);
        EXPECT_NEAR(r[0].irradiance.x, expected, 0.005 * expected) << "bounces " << b;
    }
}

TEST(Reference, PunctualLightsAreExact) {
    // A floor far below so the scene has a triangle; it does not block the lights.
    Scene s = test::makeEmissiveDisk(0.1f, {0, 0, 0}, 8);
    s.materials[0].albedo = {0, 0, 0};
    s.pointLights.push_back({{0, 0, 2}, {4, 4, 4}});
    s.spotLights.push_back({{3, 0, 1}, {-1, 0, 0}, {8, 8, 8}, 0.2f, 0.4f});
    s.directionalLights.push_back({normalize(Vec3f(0, 1, -1)), {0.5f, 0.5f, 0.5f}});
    const Vec3f x{0, 0, 1};
    const Vec3f n = normalize(Vec3f(1, -1, 1));
    const auto r = reference(s, {{x, n}}, 16);
    const double point = 4.0 / 1.0 * dot(n, Vec3f(0, 0, 1));                      // d = 1, towards +z
    const double spot = 8.0 / 9.0 * dot(n, Vec3f(1, 0, 0));                       // on axis, d = 3
    const double sun = 0.5 * std::max(0.0f, dot(n, normalize(Vec3f(0, -1, 1))));  // towards the light
    EXPECT_NEAR(r[0].irradiance.x, point + spot + sun, 1e-5);
    EXPECT_EQ(r[0].standardError.x, 0.0);
}

TEST(Reference, RejectsAZeroNormal) {
    const Scene s = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {0.5f, 0.5f, 0.5f});
    EXPECT_THROW(reference(s, {{{0, 0, 0}, {0, 0, 0}}}, 16), ValueError);
}

TEST(Reference, SameResultForAnyThreadCount) {
    const Scene box = test::makeFurnaceBox({-1, -1, -1}, {1, 1, 1}, {1, 1, 1}, {0.5f, 0.5f, 0.5f});
    const Tracer tracer(box);
    ReferenceOptions o;
    o.samples = 20000;
    std::vector<ReferencePoint> pts = {{{0, 0, 0}, {0, 0, 1}}, {{0.5f, 0.5f, 0.5f}, {1, 0, 0}}};
    o.threads = 1;
    const auto a = referenceIrradiance(box, tracer, pts, o);
    o.threads = 2;
    const auto b = referenceIrradiance(box, tracer, pts, o);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        EXPECT_EQ(a[i].irradiance, b[i].irradiance);
        EXPECT_EQ(a[i].standardError, b[i].standardError);
    }
}
