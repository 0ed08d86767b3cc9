// End to end: vdblight prt bake / relight / info, and the refusals.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "test_util.h"
#include "vdblight/core/math.h"

namespace fs = std::filesystem;
using namespace vdblight;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;
const std::string kSource = VDBLIGHT_SOURCE_DIR;

struct CliRun {
    int status;
    std::string output;
};

CliRun runCli(const std::string& args) {
    CliRun r;
    r.status = test::runCommand(kCli + " " + args, &r.output);
    return r;
}

std::size_t filesIn(const fs::path& dir) {
    std::size_t n = 0;
    for (auto& e : fs::directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
    return n;
}

void expectCleanFailure(const test::TempDir& dir, const std::string& args, const std::string& text) {
    const std::size_t before = filesIn(dir.path());
    const CliRun r = runCli(args);
    EXPECT_NE(r.status, 0) << args << "\n" << r.output;
    EXPECT_LT(r.status, 128) << args;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(text), std::string::npos) << args << "\nexpected '" << text << "' in: " << r.output;
    EXPECT_EQ(filesIn(dir.path()), before) << "a file was left behind by: " << args;
}

const char* kSmall = " --samples 300 --cluster-size 100 --vis-dirs 256 --vis-coeffs 20 --train-lights 40 --transfer-coeffs 8";
}  // namespace

TEST(CliPrt, BakeRelightInfo) {
    test::TempDir dir;
    const std::string prt = dir.file("box_prt.vdb");
    const CliRun bake = runCli("prt bake -o " + prt + kSmall + " --volume-resolution 4");
    ASSERT_EQ(bake.status, 0) << bake.output;
    EXPECT_NE(bake.output.find("time: samples"), std::string::npos) << bake.output;

    const CliRun info = runCli("info " + prt);
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("PRT file"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("as dense 32-bit floats"), std::string::npos) << info.output;
    EXPECT_EQ(runCli("prt info " + prt).output, info.output);

    const CliRun csv = runCli("prt relight " + prt + " --light 0.28,0.4,0.28,1,1,1 --light 0.1,0.3,0.4 -o " +
                              dir.file("lit.csv") + " --reference " + kSource + "/data/cornell_box.obj");
    ASSERT_EQ(csv.status, 0) << csv.output;
    EXPECT_NE(csv.output.find("reference: RMS relative error"), std::string::npos) << csv.output;
    std::ifstream in(dir.file("lit.csv"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line.rfind("x,y,z,nx,ny,nz,cluster,direct_r", 0), 0u) << line;
    int rows = 0;
    bool lit = false;
    while (std::getline(in, line)) {
        ++rows;
        std::stringstream ss(line);
        std::string v;
        for (int k = 0; k < 8; ++k) std::getline(ss, v, ',');
        lit = lit || std::stod(v) > 0;
    }
    EXPECT_GT(rows, 200);
    EXPECT_TRUE(lit);

    const CliRun ply = runCli("prt relight " + prt + " --light 0.28,0.4,0.28 --area-size 0.1 -q -o " + dir.file("lit.ply"));
    ASSERT_EQ(ply.status, 0) << ply.output;
    std::ifstream p(dir.file("lit.ply"));
    std::getline(p, line);
    EXPECT_EQ(line, "ply");

    // The relit volume is an ordinary SH volume: info and query read it.
    const std::string vol = dir.file("relit.vdb");
    const std::string scene = std::string(kSource) + "/data/cornell_box.obj";
    const CliRun rv = runCli("prt relight " + prt + " --light 0.28,0.4,0.28 -q -o " + dir.file("v.csv") + " --volume-out " +
                             vol + " --scene " + scene);
    ASSERT_EQ(rv.status, 0) << rv.output;
    // Without the scene the lights' direct light cannot be added: refused unless asked for.
    expectCleanFailure(dir, "prt relight " + prt + " --light 0.28,0.4,0.28 -q -o " + dir.file("w.csv") +
                                " --volume-out " + dir.file("w.vdb"), "--indirect-only");
    const std::string ind = dir.file("indirect.vdb");
    ASSERT_EQ(runCli("prt relight " + prt + " --light 0.28,0.4,0.28 -q -o " + dir.file("w.csv") + " --volume-out " +
                     ind + " --indirect-only").status, 0);
    // The complete volume is brighter than its indirect part (the light shines on the point).
    auto irradiance = [&](const std::string& file) {
        const CliRun r = runCli("query " + file + " --at 0.28,0.2,0.28 --normal 0,1,0");
        EXPECT_EQ(r.status, 0) << r.output;
        const std::string last = r.output.substr(r.output.rfind(',', r.output.size() - 2) + 1);
        return std::stod(last);
    };
    EXPECT_GT(irradiance(vol), 2.0 * irradiance(ind));
    const CliRun vinfo = runCli("info " + vol);
    EXPECT_EQ(vinfo.status, 0) << vinfo.output;
    EXPECT_NE(vinfo.output.find("sh2"), std::string::npos) << vinfo.output;
    const CliRun q = runCli("query " + vol + " --at 0.1,0.3,0.3 --normal 1,0,0");
    ASSERT_EQ(q.status, 0) << q.output;
    EXPECT_NE(q.output.find("E_r"), std::string::npos) << q.output;
    EXPECT_NE(vinfo.output.find("direct light: occlusion, 1 listed light"), std::string::npos) << vinfo.output;

    // The scene's own lights (the Cornell box's ceiling panel, a polygon light): relit at the
    // samples, and listed with their visibility in the volume, whose direct light `query` adds.
    // Under the panel, facing it, the unshadowed exact irradiance is at most L A / d^2 = 0.446
    // in blue (L = 4, A = 0.0137, d = 0.35); the interpolated visibility of this 4^3 volume
    // (nodes inside the blocks are shadowed) lowers it, but some of it must be there.
    const std::string sl = dir.file("scene_lights.vdb"), slIndirect = dir.file("scene_lights_indirect.vdb");
    const CliRun slRun = runCli("prt relight " + prt + " --scene " + scene + " --scene-lights -o " + dir.file("sl.csv") +
                                " --volume-out " + sl);
    ASSERT_EQ(slRun.status, 0) << slRun.output;
    EXPECT_NE(slRun.output.find("1 light(s)"), std::string::npos) << slRun.output;
    ASSERT_EQ(runCli("prt relight " + prt + " --scene " + scene + " --scene-lights -q -o " + dir.file("sl.csv") +
                     " --indirect-only --volume-out " + slIndirect).status, 0);
    const CliRun slInfo = runCli("info " + sl);
    EXPECT_NE(slInfo.output.find("direct light: occlusion, 1 listed light"), std::string::npos) << slInfo.output;
    const double directBlue = irradiance(sl) - irradiance(slIndirect);
    std::printf("--scene-lights volume: direct E_b %.3f under the panel\n", directBlue);
    EXPECT_GT(directBlue, 0.1);
    EXPECT_LT(directBlue, 0.45);

    const CliRun outside = runCli("prt relight " + prt + " --light 5,5,5 -q -o " + dir.file("far.csv"));
    EXPECT_EQ(outside.status, 0);
    EXPECT_NE(outside.output.find("light 1 at 5,5,5 is outside the scene bounds"), std::string::npos) << outside.output;
    // Inside the short block, judged from the samples alone, and exactly with --scene.
    const CliRun inside = runCli("prt relight " + prt + " --light 0.45,0.48,0.1 --light 0.185,0.08,0.17 -q -o " +
                                 dir.file("in.csv"));
    EXPECT_EQ(inside.status, 0);
    EXPECT_NE(inside.output.find("light 2 at 0.185,0.08,0.17 is inside a solid"), std::string::npos) << inside.output;
    EXPECT_EQ(inside.output.find("light 1"), std::string::npos) << inside.output;
    const CliRun insideExact = runCli("prt relight " + prt + " --light 0.185,0.08,0.17 -q -o " + dir.file("in.csv") +
                                      " --scene " + scene);
    EXPECT_NE(insideExact.output.find("light 1 at 0.185,0.08,0.17 is inside a solid (lit as given)"), std::string::npos)
        << insideExact.output;
    const CliRun area = runCli("prt relight " + prt + " --area-light 0.28,0.5,0.28,0,-1,0,0.1,2,2,2 -q -o " +
                               dir.file("area.csv") + " --reference " + scene);
    EXPECT_EQ(area.status, 0) << area.output;
    EXPECT_NE(area.output.find("reference: RMS relative error"), std::string::npos) << area.output;
}

TEST(CliPrt, BadInput) {
    test::TempDir dir;
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --samples 0", "--samples");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --samples 1000000 --cluster-size 1000000",
                       "per-cluster PCA would take");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --samples 1000000 --cluster-size 100000 --form-factors dense",
                       "billion rays");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --form-factors sometimes", "--form-factors");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --form-factor-rays 0", "--form-factor-rays");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --vis-coeffs 0", "--vis-coeffs");
    expectCleanFailure(dir, "prt bake -o " + dir.file("nodir/a.vdb") + kSmall, "nodir");
    // An SH volume is not a PRT file, and a PRT file is not a volume.
    const std::string vol = dir.file("vol.vdb");
    ASSERT_EQ(runCli("bake -q --resolution 4 --rays 16 -o " + vol).status, 0);
    expectCleanFailure(dir, "prt relight " + vol + " --light 0.2,0.2,0.2", "not a PRT file");
    const std::string prt = dir.file("p.vdb");
    ASSERT_EQ(runCli("prt bake -q -o " + prt + kSmall).status, 0);
    expectCleanFailure(dir, "query " + prt + " --at 0.2,0.2,0.2", "not a vdblight volume");
    expectCleanFailure(dir, "prt relight " + prt + " --light 0.2,0.2", "--light");
    expectCleanFailure(dir, "prt relight " + prt + " --scene-lights", "--scene-lights needs --scene");
    expectCleanFailure(dir, "prt relight " + prt + " --light 0.2,0.2,0.2 -o " + dir.file("x.csv") + " --volume-out " +
                                dir.file("x.vdb"), "has no volume");
    expectCleanFailure(dir, "prt relight " + prt + " --light 0.2,0.2,0.2,-1,0,0", "negative");
    expectCleanFailure(dir, "prt relight " + prt + " --area-light 0.2,0.2,0.2,0,0,0,0.1", "normal");
    expectCleanFailure(dir, "prt relight " + prt + " --area-light 0.2,0.2,0.2,0,-1,0", "--area-light");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --bounces 0", "--bounces");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --oriented-training -1", "--oriented-training");
    expectCleanFailure(dir, "prt bake -o " + dir.file("a.vdb") + " --oriented-training 17", "--oriented-training");
}

namespace {

/// The first irradiance value (E_r) of the first data row of a `vdblight query` CSV.
double firstIrradianceOf(const std::string& csv) {
    std::istringstream lines(csv);
    std::string header, row;
    std::getline(lines, header);
    std::getline(lines, row);
    const std::size_t at = header.find("E_r");
    if (at == std::string::npos) return -1;
    const long column = std::count(header.begin(), header.begin() + std::ptrdiff_t(at), ',');
    std::istringstream cells(row);
    std::string cell;
    for (long c = 0; std::getline(cells, cell, ','); ++c)
        if (c == column) return std::stod(cell);
    return -1;
}

/// Mean x, y, z of the sample rows of a `prt relight` CSV.
Vec3d meanPosition(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);
    Vec3d sum(0, 0, 0);
    int n = 0;
    while (std::getline(in, line)) {
        std::istringstream row(line);
        double v[3];
        char comma;
        row >> v[0] >> comma >> v[1] >> comma >> v[2];
        sum += Vec3d(v[0], v[1], v[2]);
        ++n;
    }
    return n ? sum / double(n) : sum;
}
}  // namespace

TEST(CliPrt, FarSceneRelightsIntoTheWorld) {
    // The same box near the origin and 1e6 away (scale 1000: a 550-unit box; float keeps 1e6
    // to 1/16, 1e-4 of the box). The relit volume and samples are placed in the world, and the
    // light is given in world coordinates: the far scene reads what the near one reads.
    const test::TempDir dir;
    const double zero[3] = {0, 0, 0}, far[3] = {1e6, -1e6, 1e6};
    const std::string nearObj = test::writeMovedCornell(dir, "near", 1000, zero);
    const std::string farObj = test::writeMovedCornell(dir, "far", 1000, far);
    const std::string bake = " --samples 300 --cluster-size 150 --vis-dirs 64 --vis-coeffs 8 --train-lights 40 "
                             "--bounces 2 --volume-resolution 4 -q";
    ASSERT_EQ(runCli("prt bake " + nearObj + " -o " + dir.file("near_prt.vdb") + bake).status, 0);
    const CliRun farBake = runCli("prt bake " + farObj + " -o " + dir.file("far_prt.vdb") + bake);
    ASSERT_EQ(farBake.status, 0) << farBake.output;
    const CliRun info = runCli("prt info " + dir.file("far_prt.vdb"));
    EXPECT_NE(info.output.find("scene origin: 1000"), std::string::npos) << info.output;

    auto world = [&](double x, double y, double z, const double* o) {
        std::ostringstream w;
        w.precision(17);
        w << x + o[0] << ',' << y + o[1] << ',' << z + o[2];
        return w.str();
    };
    for (const double* o : {zero, far}) {
        const std::string name = o == zero ? "near" : "far";
        const CliRun r = runCli("prt relight " + dir.file(name + "_prt.vdb") + " --light " + world(278, 400, 280, o) +
                                ",1e5,1e5,1e5 --scene " + dir.file(name + ".obj") + " --volume-out " +
                                dir.file(name + "_lit.vdb") + " -o " + dir.file(name + ".csv") + " -q");
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_EQ(r.output.find("outside the scene bounds"), std::string::npos) << r.output;
    }
    const Vec3d mn = meanPosition(dir.file("near.csv")), mf = meanPosition(dir.file("far.csv"));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(mf[a] - mn[a], far[a], 1.0) << a;  // samples in world coordinates
    const double points[3][3] = {{278, 100, 280}, {150, 300, 200}, {400, 450, 400}};
    for (const auto& p : points) {
        const double en = firstIrradianceOf(
            runCli("query " + dir.file("near_lit.vdb") + " --at " + world(p[0], p[1], p[2], zero) + " --normal 0,1,0").output);
        const double ef = firstIrradianceOf(
            runCli("query " + dir.file("far_lit.vdb") + " --at " + world(p[0], p[1], p[2], far) + " --normal 0,1,0").output);
        EXPECT_GT(en, 0) << p[0];
        EXPECT_NEAR(ef, en, 0.03 * en) << p[0];
    }
}
