// query's exact direct light in float (query/fast_exact_lights.h), the lights a `--direct
// occlusion` lookup adds at every query, against the plain forms it replaces: its atan2 against
// std::atan2 in double, and four edges at once against one, bit for bit; the polygon and mesh
// lights' float contour against exactIrradiance in double, within float rounding; the quad
// lights' own path against the general contour, bit for bit. (Moved from
// query_fast_paths_test.cpp in session 25, when mesh lights joined the float path.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "test_util.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/sampling/sampling.h"
#include "../libvdblight/src/query/fast_exact_lights.h"  // internal: the float light terms

namespace vdblight {
namespace {

bool sameBits(const Rgb& a, const Rgb& b) { return std::memcmp(&a, &b, sizeof(Rgb)) == 0; }

TEST(FastExactLights, Atan2OfANonNegativeYIsTheLibrarys) {
    Rng rng(77);
    double worst = 0;
    auto check = [&](float y, float x) {
        const double ref = std::atan2(double(y), double(x));
        const double got = query_detail::atan2NonNegative(y, x);
        const double err = std::fabs(got - ref) / std::max(ref, 1e-30);
        worst = std::max(worst, err);
        ASSERT_LE(err, 3e-7) << "atan2(" << y << ", " << x << ") = " << ref << ", got " << got;
        // The four-lane version (the polygon's edges side by side) gives the scalar's bits in
        // every lane, whatever the other lanes hold.
        const query_detail::Float4 ys = {y, 2 * y, y, 0.5f * y}, xs = {x, x, -x, 4 * x};
        const query_detail::Float4 lanes = query_detail::atan2NonNegative4(ys, xs);
        for (int k = 0; k < 4; ++k) {
            const float one = query_detail::atan2NonNegative(ys[k], xs[k]);
            const float lane = lanes[k];  // a copy: clang refuses the address of a vector element
            ASSERT_EQ(std::memcmp(&lane, &one, sizeof one), 0)
                << "lane " << k << ": atan2(" << ys[k] << ", " << xs[k] << ") " << lanes[k] << " vs " << one;
        }
    };
    for (const float y : {0.0f, 1e-30f, 1e-7f, 0.5f, 1.0f, 3e7f})
        for (const float x : {-3e7f, -1.0f, -1e-7f, 0.0f, 1e-7f, 1.0f, 3e7f})
            if (y > 0 || x != 0) check(y, x);
    EXPECT_EQ(query_detail::atan2NonNegative(0.0f, 2.0f), 0.0f);
    for (int t = 0; t < 1000000; ++t) {
        const float y = float(rng.uniform() * std::pow(10.0, 6 * rng.uniform() - 3));
        const float x = float((rng.uniform() - 0.5) * std::pow(10.0, 6 * rng.uniform() - 3));
        check(y, x);
    }
    std::printf("[ info ] largest relative error %.3g (float epsilon 1.19e-7)\n", worst);
}

/// Receivers around each light (`centres[i]`, 0.01 .. 3 away, normals at random): the float path
/// against exactIrradiance in double, within a few float roundings of the largest edge term
/// (L pi / 2 bounds each edge's L theta / 2). A receiver (nearly) in the light's plane (a mesh:
/// one of its triangles') sees it edge-on: the contour's terms cancel to what is left, and float
/// keeps fewer of its digits (measured up to 2e-5 of L pi / 2 within 1 % of r of the plane).
/// Lights off the float path give exactIrradiance's bits; point lights are within float
/// rounding of I / d^2.
void expectFloatContoursWithinRounding(const std::vector<DirectLight>& lights, const std::vector<Vec3d>& centres, uint64_t seed,
                                       int trials) {
    const query_detail::FastExactLights fast(lights);
    Rng rng(seed);
    double worst = 0, edgeOn = 0;
    int clipped = 0, lit = 0;
    for (int t = 0; t < trials; ++t) {
        const std::size_t i = std::size_t(t) % lights.size();
        const double r = std::pow(10.0, 2.5 * rng.uniform() - 2);  // 0.01 .. 3 from the light
        const Vec3d x = centres[i] + Vec3d(uniformSphere(float(rng.uniform()), float(rng.uniform()))) * r;
        const Vec3d n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
        const Rgb exact = exactIrradiance(lights[i], x, n), got = fast.irradiance(i, x, n);
        if (fast.floatPunctual(i)) {
            const Vec3d d = lights[i].position - x;
            ASSERT_LE(std::fabs(double(got.x) - double(exact.x)), 1e-6 * double(lights[i].value.x) / dot(d, d)) << "light " << i;
            continue;
        }
        if (!fast.floatPath(i)) {
            ASSERT_TRUE(sameBits(exact, got)) << "light " << i;
            continue;
        }
        lit += exact.x > 0;
        for (const auto& loop : lights[i].loops)
            for (const Vec3d& p : loop) clipped += dot(n, p - x) < 0 && exact.x > 0;
        const double scale = double(lights[i].value.x) * kPi / 2;
        const double err = std::fabs(double(got.x) - double(exact.x)) / scale;
        double nearestPlane = std::fabs(dot(lights[i].normal, x - lights[i].loops[0][0]));
        if (lights[i].kind == DirectLight::Kind::Mesh) {
            nearestPlane = r;
            for (const auto& tri : lights[i].loops)
                nearestPlane = std::min(nearestPlane, std::fabs(dot(normalize(cross(tri[1] - tri[0], tri[2] - tri[0])), x - tri[0])));
        }
        if (nearestPlane < 0.01 * r) {
            edgeOn = std::max(edgeOn, err);
            ASSERT_LE(err, 1e-4) << "light " << i << " edge-on";
            continue;
        }
        worst = std::max(worst, err);
        ASSERT_LE(err, 1.5e-6) << "light " << i << " at " << x.x << " " << x.y << " " << x.z << " n " << n.x << " " << n.y << " "
                             << n.z << ": " << got.x << " vs " << exact.x;
    }
    EXPECT_GT(lit, trials / 7);
    EXPECT_GT(clipped, trials / 20);  // the hemisphere clipping ran
    std::printf("[ info ] %d lit receivers; largest error %.3g of L pi / 2 (%.3g for receivers within 1 %% of r of a "
                "light's plane)\n", lit, worst, edgeOn);
}

/// The polygon lights' float contour against exactIrradiance in double: a square, a two-sided
/// triangle, a square with a square hole; a polygon with more vertices than the float path
/// takes (exactIrradiance's bits) and a point light.
TEST(FastExactLights, PolygonContourIsTheDoubleOnesWithinFloatRounding) {
    std::vector<DirectLight> lights;
    lights.push_back(squareLight({0.0, 2.0, 0.0}, {0, -1, 0}, 0.6, Rgb(30, 20, 10)));
    DirectLight tri;
    tri.kind = DirectLight::Kind::Polygon;
    tri.value = Rgb(5, 6, 7);
    tri.normal = normalize(Vec3d(1, 1, 1));
    tri.twoSided = true;
    tri.loops = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    lights.push_back(tri);
    DirectLight holed = lights[0];  // a square with a square hole (a clockwise inner loop)
    holed.loops.push_back({{-0.1, 2.0, -0.1}, {-0.1, 2.0, 0.1}, {0.1, 2.0, 0.1}, {0.1, 2.0, -0.1}});
    lights.push_back(holed);
    DirectLight nine = lights[0];  // more vertices than the float path takes: exactIrradiance
    nine.loops[0].insert(nine.loops[0].begin() + 1, 5, nine.loops[0][0]);
    lights.push_back(nine);
    DirectLight point;
    point.position = {0.5, 1.0, 0.2};
    point.value = Rgb(1, 2, 3);
    lights.push_back(point);
    const query_detail::FastExactLights fast(lights);
    EXPECT_TRUE(fast.floatPath(0) && fast.floatPath(1) && fast.floatPath(2));
    EXPECT_FALSE(fast.floatPath(3) || fast.floatPath(4));
    const Vec3d square(0, 2, 0);
    expectFloatContoursWithinRounding(lights, {square, Vec3d(1, 1, 1) / 3.0, square, square, square}, 123, 200000);
}

/// Mesh lights take the float path too (since session 25): each triangle's contour in float,
/// on the side its own plane decides in double, as exactIrradiance's sum over the triangles. A
/// closed tetrahedron, and two of its faces as an open two-sided mesh (receivers that see one
/// face's front and the other's back).
TEST(FastExactLights, MeshContourIsTheDoubleOnesWithinFloatRounding) {
    DirectLight bulb;  // each face counter-clockwise seen from outside
    bulb.kind = DirectLight::Kind::Mesh;
    bulb.value = Rgb(3, 2, 1);
    const Vec3d c(0.0, -1.0, 0.5), a = c + Vec3d(0.3, 0.3, 0.3), b = c + Vec3d(0.3, -0.3, -0.3), d = c + Vec3d(-0.3, 0.3, -0.3),
                e = c + Vec3d(-0.3, -0.3, 0.3);
    bulb.loops = {{a, b, d}, {a, e, b}, {a, d, e}, {b, e, d}};
    DirectLight roof = bulb;
    roof.loops.resize(2);
    roof.twoSided = true;
    DirectLight big = bulb;  // a mesh with a loop of more vertices than the float path takes
    big.loops[0].insert(big.loops[0].begin() + 1, 7, big.loops[0][0]);
    const std::vector<DirectLight> lights = {bulb, roof, big};
    const query_detail::FastExactLights fast(lights);
    EXPECT_TRUE(fast.floatPath(0) && fast.floatPath(1));
    EXPECT_FALSE(fast.floatPath(2));
    expectFloatContoursWithinRounding(lights, {c, c, c}, 321, 150000);
}

/// A quad light (one loop of four vertices) takes its own path (fast_exact_lights.cpp:
/// quadContour, the edges in registers); the same quad with its last vertex repeated takes the
/// general one, whose extra edge has length 0 and adds +0: the two give the same bits, at
/// receivers that see the quad whole, clipped by their plane, or not at all.
TEST(FastExactLights, QuadLightsPathGivesTheGeneralContoursBits) {
    std::vector<DirectLight> lights = {squareLight({0.0, 2.0, 0.0}, {0.3, -1, 0.2}, 0.6, Rgb(30, 20, 10))};
    lights[0].twoSided = true;  // receivers on both sides
    DirectLight repeated = lights[0];
    repeated.loops[0].push_back(repeated.loops[0].back());
    lights.push_back(repeated);
    const query_detail::FastExactLights fast(lights);
    ASSERT_TRUE(fast.floatPath(0) && fast.floatPath(1));
    Rng rng(77);
    int whole = 0, clipped = 0, unlit = 0;
    for (int t = 0; t < 100000; ++t) {
        const double r = std::pow(10.0, 2.5 * rng.uniform() - 2);  // 0.01 .. 3 from the light
        const Vec3d x = Vec3d(0, 2, 0) + Vec3d(uniformSphere(float(rng.uniform()), float(rng.uniform()))) * r;
        const Vec3d n(uniformSphere(float(rng.uniform()), float(rng.uniform())));
        const Rgb quad = fast.irradiance(0, x, n), general = fast.irradiance(1, x, n);
        ASSERT_TRUE(sameBits(quad, general)) << "at " << x.x << " " << x.y << " " << x.z << " n " << n.x << " " << n.y << " " << n.z
                                             << ": " << quad.x << " vs " << general.x;
        int above = 0;
        for (const Vec3d& p : lights[0].loops[0]) above += dot(n, p - x) >= 0;
        whole += above == 4 && quad.x > 0;
        clipped += above > 0 && above < 4 && quad.x > 0;
        unlit += quad.x == 0;
    }
    EXPECT_GT(whole, 10000);
    EXPECT_GT(clipped, 10000);
    EXPECT_GT(unlit, 10000);
    std::printf("[ info ] %d receivers saw the quad whole, %d clipped, %d not at all\n", whole, clipped, unlit);
}

}  // namespace
}  // namespace vdblight
