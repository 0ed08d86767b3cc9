// The memory bound of scene loading (docs/scene.md, "Memory bound"): no scene file makes
// vdblight allocate more than max(256 MB, 64 x its size) before it refuses the file. Each
// memory regression input of the fuzz corpus (tests/fuzz/corpus/*/regression-mem-*, written
// by tests/fuzz/make_memory_corpus.py: declared counts and lengths that made Assimp ask for
// gigabytes) is loaded by the real program in a child process; the test checks the clean
// one-line refusal and the child's peak resident memory (getrusage's ru_maxrss via wait4).
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

namespace fs = std::filesystem;

namespace vdblight::test {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

struct ChildRun {
    int status = -1;
    std::string output;
    double peakBytes = 0;  ///< ru_maxrss of the child
};

/// Runs `vdblight ARGS...` without a shell (so that the rusage is the program's own).
ChildRun runMeasured(const std::vector<std::string>& args) {
    int pipeFds[2];
    if (pipe(pipeFds) != 0) throw std::runtime_error("pipe failed");
    const pid_t pid = fork();
    if (pid == 0) {
        dup2(pipeFds[1], STDOUT_FILENO);
        dup2(pipeFds[1], STDERR_FILENO);
        close(pipeFds[0]);
        close(pipeFds[1]);
        std::vector<char*> argv{const_cast<char*>(cliPath().c_str())};
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(cliPath().c_str(), argv.data());
        _exit(127);
    }
    close(pipeFds[1]);
    ChildRun run;
    char buffer[4096];
    for (ssize_t n; (n = read(pipeFds[0], buffer, sizeof buffer)) > 0;) run.output.append(buffer, std::size_t(n));
    close(pipeFds[0]);
    int status = 0;
    rusage usage{};
    wait4(pid, &status, 0, &usage);
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    run.peakBytes = double(usage.ru_maxrss) * 1024.0;  // kilobytes on Linux
    return run;
}

std::vector<fs::path> memoryRegressionInputs() {
    std::vector<fs::path> files;
    for (const auto& dir : fs::directory_iterator(fs::path(VDBLIGHT_SOURCE_DIR) / "tests" / "fuzz" / "corpus"))
        for (const auto& f : fs::directory_iterator(dir.path()))
            if (f.path().filename().string().rfind("regression-mem-", 0) == 0) files.push_back(f.path());
    std::sort(files.begin(), files.end());
    return files;
}

double boundFor(const fs::path& file) {
    return std::max(256.0 * kMiB, 64.0 * double(fs::file_size(file)));
}

TEST(SceneMemoryBound, EveryMemoryRegressionInputIsRefusedCleanlyWithinTheBound) {
    const std::vector<fs::path> inputs = memoryRegressionInputs();
    ASSERT_GE(inputs.size(), 9u) << "tests/fuzz/make_memory_corpus.py writes the inputs";
    // What the program needs anyway (libraries, Embree, a small scene), measured the same way.
    const ChildRun baseline = runMeasured({"check-scene", defaultScenePath()});
    ASSERT_EQ(baseline.status, 0) << baseline.output;
#ifdef VDBLIGHT_SANITIZED
    const double slack = 1.5;  // ASan's shadow memory and quarantine
#else
    const double slack = 1.0;
#endif
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        const ChildRun run = runMeasured({"check-scene", input.string()});
        EXPECT_EQ(run.status, 1) << run.output;
        EXPECT_EQ(countLines(run.output), 1) << run.output;
        EXPECT_NE(run.output.find(input.string()), std::string::npos) << "the message names the file: " << run.output;
        EXPECT_LE(run.peakBytes, baseline.peakBytes + slack * boundFor(input))
            << "peak " << run.peakBytes / kMiB << " MB, baseline " << baseline.peakBytes / kMiB << " MB";
    }
}

TEST(SceneMemoryBound, TheGuardNamesTheDeclaredSizeThatIsTooLarge) {
    const fs::path corpus = fs::path(VDBLIGHT_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
    const struct { const char* file; const char* reason; } cases[] = {
        {"fuzz_scene_glb/regression-mem-accessor-without-view.glb", "over the loader's bound"},
        {"fuzz_scene_glb/regression-mem-accessor-count-past-view.glb", "more than its buffer view holds"},
        {"fuzz_scene_glb/regression-mem-buffer-length.glb", "declares 2147483648 bytes but only"},
        {"fuzz_scene_glb/regression-mem-chunk-length.glb", "past the end of the file"},
        {"fuzz_scene_glb/regression-mem-node-instancing.glb", "node 6 instanced 1000000 times"},
        {"fuzz_scene_glb/regression-mem-node-cycle.glb", "cycle in the node hierarchy"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.file);
        try {
            (void)loadScene((corpus / c.file).string());
            ADD_FAILURE() << "loaded";
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
        }
    }
}

/// OBJ has no declared sizes, but Assimp's cost grows with statements the guard counts.
TEST(SceneMemoryBound, ObjMaterialSwitchesAndHugePolygonsAreRefusedBeforeAssimp) {
    TempDir dir;
    {
        // Unguarded, Assimp 5.2.5 went past 1.9 GB on this 4.5 MB file.
        std::ofstream obj(dir.file("switches.obj"));
        obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        for (int i = 0; i < 200000; ++i) obj << "usemtl m" << i << "\nf 1 2 3\n";
        // Unguarded, Assimp's triangulation of this one face did not finish in 10 minutes.
        std::ofstream big(dir.file("polygon.obj"));
        big << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
        for (int i = 0; i < 300000; ++i) big << " 1 2 3";
        big << "\n";
    }
    const ChildRun switches = runMeasured({"check-scene", dir.file("switches.obj")});
    EXPECT_EQ(switches.status, 1) << switches.output;
    EXPECT_NE(switches.output.find("200000 material switches"), std::string::npos) << switches.output;
    EXPECT_LE(switches.peakBytes, 512.0 * kMiB) << switches.peakBytes / kMiB << " MB";
    const ChildRun polygon = runMeasured({"check-scene", dir.file("polygon.obj")});
    EXPECT_EQ(polygon.status, 1) << polygon.output;
    EXPECT_NE(polygon.output.find("an OBJ face has 900000 corners"), std::string::npos) << polygon.output;
}

/// Large and instanced scenes that are legitimate still load: the bound is not a size limit.
TEST(SceneMemoryBound, LegitimateLargeAndInstancedScenesLoad) {
    TempDir dir;
    // 200 000 triangles in an OBJ of about 7 MB.
    {
        std::ofstream obj(dir.file("grid.obj"));
        const int n = 317;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) obj << "v " << i << " 0 " << j << "\n";
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
                obj << "f " << a << " " << c << " " << b << "\nf " << b << " " << c << " " << d << "\n";
            }
    }
    EXPECT_EQ(loadScene(dir.file("grid.obj")).triangleCount(), 2u * 317u * 317u);
    // One mesh instanced 1000 times through a glTF node list (each node its own transform).
    {
        std::string nodes, roots;
        for (int i = 0; i < 1000; ++i) {
            nodes += std::string(i ? "," : "") + "{\"mesh\":0,\"translation\":[" + std::to_string(2 * i) + ",0,0]}";
            roots += std::string(i ? "," : "") + std::to_string(i);
        }
        std::ofstream gltf(dir.file("instances.gltf"));
        gltf << "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[" << roots << "]}],\"nodes\":[" << nodes
             << "],\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,"
                "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA\"}],"
                "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
                "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
                "\"min\":[0,0,0],\"max\":[1,1,0]}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}]}";
    }
    EXPECT_EQ(loadScene(dir.file("instances.gltf")).triangleCount(), 1000u);
}

}  // namespace
}  // namespace vdblight::test
