// LightReach (light/light_reach.h): the plane test it answers most points with gives the exact
// predicate's answer, maxComponent(meanIrradiance) > 0, everywhere: at random points, on and
// next to the light's plane, far away, and for the lights it leaves to the exact formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "../libvdblight/src/bake/light_reach.h"
#include "vdblight/light/direct_light.h"

using namespace vdblight;
using vdblight::bake_detail::LightReach;

namespace {

/// `loop` is listed clockwise around `normal` (as seen from its front); the light's loop is
/// counter-clockwise (direct_light.h), so it is reversed here.
DirectLight polygon(std::vector<Vec3d> loop, const Vec3d& normal, const Rgb& radiance, bool twoSided = false) {
    std::reverse(loop.begin(), loop.end());
    DirectLight l;
    l.kind = DirectLight::Kind::Polygon;
    l.value = radiance;
    l.twoSided = twoSided;
    l.normal = normal;
    l.loops = {std::move(loop)};
    return l;
}

bool exact(const DirectLight& l, const Vec3d& x) { return maxComponent(meanIrradiance(l, x)) > 0.0f; }

/// Points of every kind around a light whose plane is y = planeY: uniform in a box, within
/// 1e-12..1e-2 of the plane on either side, exactly on it, and up to 1e6 away.
std::vector<Vec3d> hardPoints(double planeY, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-3.0, 3.0), e(-12.0, -2.0);
    std::vector<Vec3d> points;
    for (int i = 0; i < 20000; ++i) {
        const Vec3d box(u(rng), u(rng), u(rng));
        points.push_back(box);
        const double near = std::pow(10.0, e(rng)) * (i % 2 ? 1.0 : -1.0);
        points.push_back(Vec3d(box.x, planeY + near, box.z));
        points.push_back(Vec3d(box.x, planeY, box.z));
        points.push_back(box * std::pow(10.0, 6.0 * (i % 7) / 6.0));
    }
    return points;
}

void expectSameAnswers(const DirectLight& l, uint32_t seed, const char* what) {
    const LightReach reach(l);
    const double planeY = l.loops.empty() || l.loops[0].empty() ? 0.0 : l.loops[0][0].y;
    int reached = 0, differ = 0;
    for (const Vec3d& x : hardPoints(planeY, seed)) {
        const bool want = exact(l, x);
        reached += want;
        if (reach.reaches(x) != want && ++differ <= 5) ADD_FAILURE() << what << ": differs at " << x.x << " " << x.y << " " << x.z;
    }
    EXPECT_EQ(differ, 0) << what;
    EXPECT_GT(reached, 1000) << what << ": the points should reach the light often";
}

}  // namespace

TEST(LightReach, AnswersAsTheExactSolidAngleForAOneSidedPanel) {
    // A panel at y = 2 facing down, as the office's luminaires: counter-clockwise around -y.
    expectSameAnswers(polygon({{0, 2, 0}, {0, 2, 0.6}, {0.6, 2, 0.6}, {0.6, 2, 0}}, {0, -1, 0}, {5, 5, 5}), 1,
                      "one-sided square");
}

TEST(LightReach, AnswersAsTheExactSolidAngleForATwoSidedTriangle) {
    expectSameAnswers(polygon({{-1, 0.5, -1}, {1, 0.5, -1}, {0, 0.5, 1}}, {0, 1, 0}, {0.2f, 0.0f, 0.1f}, true), 2,
                      "two-sided triangle");
}

TEST(LightReach, LeavesWhatItCannotDecideToTheExactFormula) {
    // Concave (an L), a tiny panel, a panel of almost no radiance, a point light and a spot:
    // answered by the exact formula, which must give the same answers (trivially) and not throw.
    expectSameAnswers(polygon({{0, 1, 0}, {2, 1, 0}, {2, 1, 1}, {1, 1, 1}, {1, 1, 2}, {0, 1, 2}}, {0, 1, 0}, {1, 1, 1}), 3,
                      "L-shaped (concave)");
    expectSameAnswers(polygon({{0, 1, 0}, {1e-7, 1, 0}, {1e-7, 1, 1e-7}, {0, 1, 1e-7}}, {0, 1, 0}, {1, 1, 1}), 4,
                      "tiny square");
    DirectLight dim = polygon({{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}, {0, 1, 0}, {1e-9f, 0.0f, 0.0f});
    const LightReach dimReach(dim);
    EXPECT_EQ(dimReach.reaches(Vec3d(0.5, 2.0, 0.5)), exact(dim, Vec3d(0.5, 2.0, 0.5)));
    DirectLight spot;
    spot.kind = DirectLight::Kind::Spot;
    spot.value = Rgb(1, 1, 1);
    spot.position = Vec3d(0, 3, 0);
    spot.direction = Vec3d(0, -1, 0);
    const LightReach spotReach(spot);
    for (const Vec3d& x : {Vec3d(0, 0, 0), Vec3d(5, 3, 0), Vec3d(0, 3, 0)})
        EXPECT_EQ(spotReach.reaches(x), exact(spot, x));
}

TEST(LightReach, ReachesNothingBehindAOneSidedPanelOrOnItsPlane) {
    const DirectLight l = polygon({{0, 2, 0}, {0, 2, 1}, {1, 2, 1}, {1, 2, 0}}, {0, -1, 0}, {1, 1, 1});
    const LightReach reach(l);
    EXPECT_TRUE(reach.reaches(Vec3d(0.5, 1.0, 0.5)));
    EXPECT_FALSE(reach.reaches(Vec3d(0.5, 3.0, 0.5)));  // behind
    EXPECT_FALSE(reach.reaches(Vec3d(5.0, 2.0, 5.0)));  // on its plane
}
