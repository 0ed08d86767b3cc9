// `vdblight bake --direct baked|runtime|occlusion` end to end: query, slice, export, the
// independent readers (pyopenvdb, Blender), and clean refusals.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_util.h"
#include "manifest_util.h"
#include "vdblight/scene/scene.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
using test::runCli;
namespace fs = std::filesystem;

namespace {
const std::string kSource = VDBLIGHT_SOURCE_DIR;
}  // namespace

TEST(CliDirect, ModesBakeQuerySliceExportAndOpenInOtherReaders) {
    test::TempDir dir;
    const std::string bake = " --resolution 5 --rays 64 --bounces 2 -q";
    for (const std::string mode : {"baked", "runtime", "occlusion"}) {
        const std::string vol = dir.file(mode + ".vdb");
        const auto r = runCli("bake -o " + vol + bake + " --direct " + mode);
        ASSERT_EQ(r.status, 0) << r.output;
        const Volume v = readVolume(vol);
        EXPECT_EQ(std::string(directModeName(v.direct.mode)), mode);
        EXPECT_EQ(v.direct.lights.empty(), mode == "baked");
        EXPECT_EQ(v.levels[0].lightVisibility.empty(), mode != "occlusion");

        // pyopenvdb reads every mode's file (the SH grids are where they always were).
        std::string out;
        EXPECT_EQ(test::runCommand("/usr/bin/python3 " + kSource + "/scripts/check_pyopenvdb.py " + vol, &out), 0) << out;
        // slice and export handle every mode.
        const auto s = runCli("slice " + vol + " --axis y --at 0.3 -o " + dir.file(mode + ".png") + " -q");
        EXPECT_EQ(s.status, 0) << s.output;
        const auto e = runCli("export " + vol + " -o " + dir.file(mode + "_tex") + " --format raw");
        ASSERT_EQ(e.status, 0) << e.output;
        const nlohmann::json manifest = test::readManifest(dir.file(mode + "_tex"));
        EXPECT_EQ(manifest["direct"]["mode"], mode) << manifest;
        EXPECT_EQ(fs::exists(dir.file(mode + "_tex/light_visibility_0_0.raw")), mode == "occlusion");
        if (mode == "occlusion") {
            EXPECT_EQ(manifest["direct"]["lights"][0]["visibility"]["texture"], "light_visibility_0_0") << manifest;
        }
        // Blender opens the occlusion file, which holds every grid the other two modes write
        // and its lights' visibility too (three Blender runs were 10 s of CI's ASan suite).
        if (mode != "occlusion" || std::getenv("VDBLIGHT_SKIP_BLENDER")) continue;
        EXPECT_EQ(test::runCommand("blender -b --factory-startup --python " + kSource + "/scripts/check_blender.py -- " + vol, &out),
                  0)
            << out;
    }
    // Under the Cornell box's luminaire, facing it, the three modes agree (same scene, same
    // light): runtime with --scene and occlusion add the direct light the SH left out.
    const std::string at = " --at 0.278,0.45,0.28 --normal 0,1,0";
    const Rgbd baked = test::firstIrradianceRgb(runCli("query " + dir.file("baked.vdb") + at).output);
    const Rgbd occl = test::firstIrradianceRgb(runCli("query " + dir.file("occlusion.vdb") + at).output);
    const auto rt = runCli("query " + dir.file("runtime.vdb") + at + " --scene " + std::string(VDBLIGHT_SOURCE_DIR) + "/data/cornell_box.obj");  // the shell-safe path (tests/CMakeLists.txt)
    ASSERT_EQ(rt.status, 0) << rt.output;
    const Rgbd runtime = test::firstIrradianceRgb(rt.output);
    const Rgbd indirect = test::firstIrradianceRgb(runCli("query " + dir.file("runtime.vdb") + at + " --indirect-only").output);
    EXPECT_GT(baked.x, 1.0);
    EXPECT_NEAR(occl.x / baked.x, 1.0, 0.25);
    EXPECT_NEAR(runtime.x / baked.x, 1.0, 0.25);
    EXPECT_LT(indirect.x, 0.5 * runtime.x);  // most light there is direct
}

TEST(CliDirect, BadInputGetsOneLineAndNoFile) {
    test::TempDir dir;
    // A scene with no lights, lit by the sky only.
    const std::string obj = dir.file("sky_only.obj");
    test::writeTextFile(obj, "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\n");
    test::expectCleanFailuresWithOutput(dir, {
        {"bake " + obj + " --sky 1,1,1 --direct occlusion --resolution 3 --rays 8", "no lights"},
        {"bake --direct-lights 0 --direct occlusion --resolution 3 --rays 8", "--direct-lights"},
        {"bake --direct-lights 17 --direct occlusion --resolution 3 --rays 8", "--direct-lights"},
        {"bake --split-lights 0 --direct occlusion --resolution 3 --rays 8", "--split-lights"},
        {"bake --split-lights 5 --direct occlusion --resolution 3 --rays 8", "--split-lights"},
        {"bake --direct sometimes --resolution 3 --rays 8", "--direct"},
        {"bake --direct runtime --method photons --resolution 3", "--direct runtime"},
        {"bake --direct occlusion --sampling antialiased --resolution 3 --rays 8", "--direct occlusion"},
    });
    // A runtime volume queried without --scene: one line, no output file.
    const std::string vol = dir.file("rt.vdb");
    ASSERT_EQ(runCli("bake -q -o " + vol + " --resolution 3 --rays 8 --direct runtime").status, 0);
    test::expectRefusal("query " + vol + " --at 0.2,0.3,0.2 -o " + dir.file("q.csv"), "--scene", dir.file("q.csv"),
                        "runtime without --scene");
    test::expectRefusal("query " + vol + " --at 0.2,0.3,0.2 --scene " + obj + " -o " + dir.file("q.csv"), "lights",
                        dir.file("q.csv"), "runtime with another scene");
}
