// vdblight::Query (volume_query.h) answers what `vdblight query` prints, to the bit, for each
// kind of volume whose answer involves more than the lookup: the default bake (sh:4 with depth
// moments, negative values clamped or raw), a `--direct runtime` volume with its scene's
// shadowed direct light, a moment volume looked up along the mirrored view, a photon volume
// with tricubic interpolation and another blend, negative (ringing) components clamped unless
// raw; and it refuses options that do not apply.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "cli_util.h"
#include "one_point_light.h"
#include "test_util.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"
#include "volume/sh_truncate.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/query/volume_query.h"

using namespace vdblight;
using test::runCli;

namespace {

/// Points inside and outside the Cornell box's volume, with normals of any length; the last
/// two see part of the luminaire past the blocks (their shadow rays' seeds matter).
const char* const kPoints =
    "x,y,z,nx,ny,nz\n"
    "0.278,0.45,0.28,0,1,0\n"
    "0.1,0.1,0.5,0.3,-2,0.1\n"
    "0.5,0.3,0.05,-1,0.2,0.4\n"
    "0.2,0.5,0.3,0,0,-3\n"
    "-0.2,0.3,0.3,1,0,0\n"
    "0.3,0.7,0.1,0.5,0.5,-0.5\n"
    "0.3,0.02,0.05,0.1,1,0.1\n"
    "0.3,0.2,0.5,0.1,1,0.1\n";

struct Row {
    Vec3d x;
    Vec3f n;
    Rgb e;
};

/// The rows `vdblight query VOLUME --points POINTS ARGS -o CSV` writes (printed with 9
/// significant digits, so each float reads back as the same float).
std::vector<Row> cliRows(const test::TempDir& dir, const std::string& volume, const std::string& args) {
    const std::string points = dir.file("points.csv"), csv = dir.file("answers.csv");
    std::ofstream(points) << kPoints;
    const test::CliRun r = runCli("query " + volume + " --points " + points + " -o " + csv + args);
    EXPECT_EQ(r.status, 0) << r.output;
    std::istringstream in(test::readTextFile(csv));
    std::string line;
    std::getline(in, line);  // header
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        std::vector<double> v;
        std::istringstream fields(line);
        for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
        EXPECT_EQ(v.size(), 9u) << line;
        if (v.size() != 9) break;
        rows.push_back({Vec3d(v[0], v[1], v[2]), Vec3f(float(v[3]), float(v[4]), float(v[5])),
                        Rgb(float(v[6]), float(v[7]), float(v[8]))});
    }
    return rows;
}

/// What a point's answer must be, from the lookups themselves: (index, x, unit normal) -> E.
using Expected = std::function<Rgb(std::size_t, const Vec3d&, const Vec3f&)>;

/// Each component clamped to 0 (what the command prints unless --raw).
Rgb clampNegative(const Rgb& e) { return Rgb(std::max(e.x, 0.0f), std::max(e.y, 0.0f), std::max(e.z, 0.0f)); }

/// Query's answers at the points of kPoints are the command's rows and `expected`'s values.
void expectSameAnswers(const Query& query, const std::vector<Row>& cli, const std::string& label, const Expected& expected) {
    std::istringstream in(kPoints);
    std::string line;
    std::getline(in, line);
    std::size_t i = 0;
    for (; std::getline(in, line); ++i) {
        double v[6];
        char comma;
        std::istringstream(line) >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> v[3] >> comma >> v[4] >> comma >> v[5];
        ASSERT_LT(i, cli.size()) << label;
        const QueryAnswer a = query.at(Vec3d(v[0], v[1], v[2]), Vec3f(float(v[3]), float(v[4]), float(v[5])), i);
        EXPECT_EQ(a.irradiance.x, cli[i].e.x) << label << ", point " << i;
        EXPECT_EQ(a.irradiance.y, cli[i].e.y) << label << ", point " << i;
        EXPECT_EQ(a.irradiance.z, cli[i].e.z) << label << ", point " << i;
        EXPECT_EQ(a.normal.x, cli[i].n.x) << label << ", point " << i;
        EXPECT_EQ(a.normal.z, cli[i].n.z) << label << ", point " << i;
        const Rgb e = expected(i, Vec3d(v[0], v[1], v[2]), a.normal);
        EXPECT_EQ(a.irradiance.x, e.x) << label << ", point " << i << " against the lookup";
        EXPECT_EQ(a.irradiance.y, e.y) << label << ", point " << i << " against the lookup";
        EXPECT_EQ(a.irradiance.z, e.z) << label << ", point " << i << " against the lookup";
    }
    EXPECT_EQ(i, cli.size()) << label;
}

}  // namespace

TEST(VolumeQuery, DefaultBakeAnswersAsTheCommandWholeStreamedAndInMemory) {
    test::TempDir dir;
    const std::string vol = dir.file("default.vdb");
    const test::CliRun bake = runCli("bake -q -o " + vol + " --resolution 3 --rays 16 --bounces 1");
    ASSERT_EQ(bake.status, 0) << bake.output;
    const Volume volume = readVolume(vol);
    const IrradianceQuery lookup(volume);
    const auto clamped = [&](std::size_t, const Vec3d& x, const Vec3f& n) { return clampNegative(lookup.irradianceWorld(x, n)); };
    const auto raw = [&](std::size_t, const Vec3d& x, const Vec3f& n) { return lookup.irradianceWorld(x, n); };

    expectSameAnswers(Query(vol), cliRows(dir, vol, ""), "default", clamped);
    QueryOptions rawOptions;
    rawOptions.raw = true;
    expectSameAnswers(Query(vol, rawOptions), cliRows(dir, vol, " --raw"), "--raw", raw);
    QueryOptions streamed;
    streamed.streaming = QueryStreaming::On;
    const Query s(vol, streamed);
    EXPECT_NE(s.streamed(), nullptr);
    expectSameAnswers(s, cliRows(dir, vol, " --stream on"), "--stream on", clamped);

    QueryOptions plain;  // no depth weights, bands 0..2 of the volume in memory
    plain.depthWeights = false;
    plain.shOrder = 2;
    const IrradianceQuery l2(truncateSh(volume, 2), OutsidePolicy::Clamp, false);
    expectSameAnswers(Query(Volume(volume), plain), cliRows(dir, vol, " --no-depth-weights --sh-order 2"),
                      "in memory, --no-depth-weights --sh-order 2",
                      [&](std::size_t, const Vec3d& x, const Vec3f& n) { return clampNegative(l2.irradianceWorld(x, n)); });

    // Options that do not apply are refused, as the command refuses them.
    QueryOptions view;
    view.view = Vec3f(0, 1, 0);
    EXPECT_THROW(Query(vol, view), ValueError);
    QueryOptions scene;
    scene.scenePath = defaultScenePath();
    EXPECT_THROW(Query(vol, scene), ValueError);
    QueryOptions tricubic;
    tricubic.interpolation = Interpolation::Tricubic;
    EXPECT_THROW(Query(vol, tricubic), ValueError);
}

TEST(VolumeQuery, RuntimeDirectLightIsAddedWithTheScenesShadowRays) {
    test::TempDir dir;
    const std::string vol = dir.file("runtime.vdb");
    const test::CliRun bake = runCli("bake -q -o " + vol + " --resolution 3 --rays 16 --bounces 1 --direct runtime");
    ASSERT_EQ(bake.status, 0) << bake.output;
    const IrradianceQuery lookup(readVolume(vol));

    QueryOptions indirect;
    indirect.indirectOnly = true;
    const Query stored(vol, indirect);
    expectSameAnswers(stored, cliRows(dir, vol, " --indirect-only"), "--indirect-only",
                      [&](std::size_t, const Vec3d& x, const Vec3f& n) { return clampNegative(lookup.irradianceWorld(x, n)); });

    // The stored light plus the scene's direct light with shadow rays at the point (clamped to
    // the node box like the lookup), seeded by the point's index.
    const Scene scene = loadScene(defaultScenePath());
    const Tracer tracer(scene);
    const std::vector<SceneLight> lights = sceneLights(scene);
    QueryOptions o;
    o.scenePath = defaultScenePath();
    o.shadowRays = 16;
    const Query withScene(vol, o);
    expectSameAnswers(withScene, cliRows(dir, vol, " --scene " + std::string(VDBLIGHT_SOURCE_DIR) + "/data/cornell_box.obj --shadow-rays 16"), "--scene",
                      [&](std::size_t i, const Vec3d& x, const Vec3f& n) {
                          RayCount rays;
                          const Vec3d inBox = vmin(vmax(x, lookup.bounds().lo), lookup.bounds().hi);
                          return clampNegative(lookup.irradianceWorld(x, n) +
                                               runtimeDirectIrradiance(scene, tracer, lights, scene.toLocal(inBox), n, 16,
                                                                       hashCombine(0x9ee7, i), rays));
                      });
    // Under the luminaire, facing it, the direct light is most of the answer.
    const Vec3d x(0.278, 0.45, 0.28);
    EXPECT_GT(withScene.irradiance(x, Vec3f(0, 1, 0)).x, 2 * stored.irradiance(x, Vec3f(0, 1, 0)).x);
    EXPECT_THROW(Query(vol, QueryOptions{}), ValueError);  // neither a scene nor indirectOnly
}

TEST(VolumeQuery, MomentVolumeIsLookedUpAlongTheMirroredView) {
    test::TempDir dir;
    const std::string vol = dir.file("moment.vdb");
    const test::CliRun bake = runCli("bake -q -o " + vol + " --resolution 3 --rays 16 --bounces 1 --basis moment:4:4");
    ASSERT_EQ(bake.status, 0) << bake.output;
    const IrradianceQuery lookup(readVolume(vol));

    QueryOptions o;
    o.view = normalize(Vec3f(0.3f, 1, 0.2f));
    const Vec3f v = *o.view;
    expectSameAnswers(Query(vol, o), cliRows(dir, vol, " --view 0.3,1,0.2"), "--view",
                      [&](std::size_t, const Vec3d& x, const Vec3f& n) {
                          const Vec3f mirrored = normalize(n * (2.0f * dot(n, v)) - v);
                          return clampNegative(lookup.irradianceWorld(x, mirrored));
                      });
    EXPECT_THROW(Query(vol, QueryOptions{}), ValueError);  // a moment volume needs a view
}

TEST(VolumeQuery, PhotonVolumeWithTricubicInterpolationAndAnotherBlend) {
    test::TempDir dir;
    const std::string vol = dir.file("photons.vdb");
    const test::CliRun bake = runCli("bake -q -o " + vol + " --method photons --photons 20000 --resolution 4");
    ASSERT_EQ(bake.status, 0) << bake.output;
    const Volume volume = readVolume(vol);
    const IrradianceQuery lookup(volume);
    expectSameAnswers(Query(vol), cliRows(dir, vol, ""), "photons",
                      [&](std::size_t, const Vec3d& x, const Vec3f& n) { return clampNegative(lookup.irradianceWorld(x, n)); });

    QueryOptions o;
    o.interpolation = Interpolation::Tricubic;
    o.ivBlend = iv::Blend::Paper;
    const VectorGridLookup cubic(volume, OutsidePolicy::Clamp, Interpolation::Tricubic, iv::Blend::Paper);
    expectSameAnswers(Query(vol, o), cliRows(dir, vol, " --interp tricubic --iv-blend paper"), "tricubic, paper",
                      [&](std::size_t, const Vec3d& x, const Vec3f& n) { return clampNegative(cubic.irradiance(Vec3f(x), n)); });
}

// The case of CliQueryRaw (one_point_light.h): order-2 SH of one point light rings negative at
// cos = -8/15 to the light. Query clamps each component to 0 and says so, or with `raw`
// answers the lookup's negative value.
TEST(VolumeQuery, NegativeIrradianceIsClampedUnlessRaw) {
    const Volume volume = test::bakeOnePointLight();
    const Vec3f x(0.5f, 0.5f, 0.5f);
    const Vec3f toLight = normalize(Vec3f(0, 0, 2) - x);
    const Vec3f side = normalize(cross(toLight, Vec3f(1, 0, 0)));
    const float c = -8.0f / 15.0f;
    const Vec3f ringing = normalize(toLight * c + side * std::sqrt(1 - c * c));
    const Rgb lookup = IrradianceQuery(volume).irradiance(x, ringing);
    ASSERT_LT(lookup.x, 0.0f);

    const QueryAnswer clamped = Query(Volume(volume), QueryOptions{}).at(Vec3d(x), ringing);
    EXPECT_TRUE(clamped.negative);
    EXPECT_EQ(clamped.irradiance.x, 0.0f);
    EXPECT_EQ(clamped.irradiance.z, 0.0f);
    QueryOptions rawOptions;
    rawOptions.raw = true;
    const QueryAnswer raw = Query(Volume(volume), rawOptions).at(Vec3d(x), ringing);
    EXPECT_FALSE(raw.negative);
    EXPECT_EQ(raw.irradiance.x, lookup.x);
    EXPECT_EQ(raw.irradiance.z, lookup.z);
}
