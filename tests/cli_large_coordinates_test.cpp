// Large coordinates end to end (docs/scene.md, "Large coordinates"): a scene file far from the
// origin is recentred on load, baked in its local frame, written with a world transform, and
// queried at world points; it agrees with the same scene near the origin.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cli_util.h"
#include "test_util.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
using namespace vdblight::test;

TEST(CliLargeCoordinates, FarSceneBakesIntoAWorldPlacedVolume) {
    const TempDir dir;
    const double zero[3] = {0, 0, 0}, far[3] = {1e5, 1e5, -1e5};
    // Scale 1000 (a 550-unit box): float keeps 1e5 to 1/128, 1.4e-5 of the box.
    const std::string nearObj = writeMovedCornell(dir, "near", 1000, zero);
    const std::string farObj = writeMovedCornell(dir, "far", 1000, far);
    const std::string opts = " --resolution 4 --rays 64 --bounces 2 --seed 3 -q";
    ASSERT_EQ(runCli("bake " + nearObj + " -o " + dir.file("near.vdb") + opts).status, 0);
    const CliRun bake = runCli("bake " + farObj + " -o " + dir.file("far.vdb") + opts);
    ASSERT_EQ(bake.status, 0) << bake.output;

    const Volume nearV = readVolume(dir.file("near.vdb")), farV = readVolume(dir.file("far.vdb"));
    for (int a = 0; a < 3; ++a)  // the .vdb is placed in the world, 1e5 away
        EXPECT_NEAR(farV.levels[0].grid.origin[a], nearV.levels[0].grid.origin[a] + far[a], 0.05) << a;

    // The same physical points, given in world coordinates.
    const char* local[] = {"278,100,280", "150,300,200", "400,450,400"};
    for (const char* p : local) {
        double x, y, z;
        char c;
        std::istringstream(p) >> x >> c >> y >> c >> z;
        std::ostringstream w;
        w.precision(17);
        w << x + far[0] << ',' << y + far[1] << ',' << z + far[2];
        const double en = firstIrradiance(runCli("query " + dir.file("near.vdb") + " --at " + p + " --normal 0,1,0").output);
        const double ef = firstIrradiance(runCli("query " + dir.file("far.vdb") + " --at " + w.str() + " --normal 0,1,0").output);
        EXPECT_GT(en, 0) << p;
        EXPECT_NEAR(ef, en, 0.02 * en) << p;  // same seed, same local frame up to the parse rounding
    }
}
