// The smallest complete use of vdblight as a library: load a scene, bake an SH irradiance
// volume into a .vdb (bakeToFile, bake/bake.h), read it back and query it, as an engine tool
// would.
//
//   bake_and_query SCENE OUT.vdb
//
// Built against the installed package (find_package(vdblight), examples/CMakeLists.txt);
// the test command builds and runs it (tests/install_example_test.sh).
#include <cstdio>
#include <exception>

#include <vdblight/vdblight.h>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: bake_and_query SCENE OUT.vdb\n");
        return 2;
    }
    try {
        using namespace vdblight;
        const Scene scene = loadScene(argv[1], SceneLoadOptions{});

        // The same entry point as `vdblight bake` (the same file for the same options):
        // a BakeRequest starts at the command line's defaults. Here 8 nodes along the longest
        // axis and 64 rays per node; the grid is refused before anything is allocated if it
        // would not fit in memory, and the file is written atomically.
        BakeRequest request;
        request.quality = "preview";
        request.resolution = 8;
        request.params.set("rays", 64);
        request.seed = 1;
        BakeReport report;
        bakeToFile(scene, request, argv[2], nullptr, &report);
        const BakeStats& stats = report.stats;

        const Volume volume = readVolume(argv[2]);
        const IrradianceQuery query(volume);
        const Bounds box = query.bounds();
        const Vec3f centre((box.lo.x + box.hi.x) / 2, (box.lo.y + box.hi.y) / 2, (box.lo.z + box.hi.z) / 2);
        const Rgb e = query.irradiance(centre, Vec3f(0, 1, 0));
        std::printf("baked %llu nodes in %.2f s; irradiance at the centre, normal +y: %.6g %.6g %.6g W/m^2\n",
                    static_cast<unsigned long long>(stats.nodes), stats.seconds, e.x, e.y, e.z);
        return 0;
    } catch (const vdblight::Error& e) {
        std::fprintf(stderr, "bake_and_query: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bake_and_query: %s\n", e.what());
        return 1;
    }
}
