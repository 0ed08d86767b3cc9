// `vdblight query` and `export --cells` on a volume larger than their memory limit (issue 17,
// "Worlds larger than memory"; issue 33: on the default bake's kind): a synthetic volume of
// the kind the default bake writes (sh:4, depth moments, --direct occlusion with two lights'
// visibility) of about 400 MB is queried and exported in cells in a child process whose data
// segment (RLIMIT_DATA, set with prlimit) is a quarter of the file. Streamed, the query prints
// exactly the floats the in-memory query gives at the same points; read whole (--stream off),
// it must fail under the same limit, so the test can fail. On a small file both modes print
// the same bytes.
//
// Why RLIMIT_DATA and not RLIMIT_AS: delayed loading maps the whole file read-only (its pages
// are page cache the kernel can drop, not the process's memory) and TBB and glibc reserve
// address space they never touch; RLIMIT_AS counts both, RLIMIT_DATA (Linux >= 4.7) counts
// the heap and private writable mappings, which is what reading a volume whole allocates (and
// thread stacks: the child runs on one CPU so that TBB starts no worker per core).
#include <gtest/gtest.h>
#include <sys/utsname.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "test_util.h"
#include "random_volumes.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;
constexpr int kN = 105;  // nodes per axis: 1.16 M nodes of 25 + 4 Vec3f and 2 float channels, ~410 MB on disk (Blosc)
const Vec3d kOrigin(-3.0, 0.5, 2.0);
constexpr double kSpacing = 0.25;

// A hash of the node indices and a channel, 24 random bits in [0, 1), so that the file does
// not compress.
float hashed(int i, int j, int k, int channel) {
    const uint64_t h = hashCombine(hashCombine(hashCombine(uint64_t(i), uint64_t(j)), uint64_t(k)), uint64_t(channel));
    return float(h >> 40) * (1.0f / 16777216.0f);
}

// The default bake's kind: sh:4 coefficients in [0.2, 1.2) (band 0) and [-0.1, 0.1) (the
// others), depth moments as the bake stores them (k/255; sigmas below 0.3), a point light and
// a square light with visibility in [0, 1].
Volume syntheticVolume(int n) {
    Volume v;
    v.basis = makeBasis("sh:4")->desc();
    VolumeLevel level;
    level.grid.origin = kOrigin;
    level.grid.spacing = kSpacing;
    level.grid.nx = level.grid.ny = level.grid.nz = n;
    const std::size_t nodes = level.grid.nodeCount();
    level.data.resize(nodes * 75);
    level.depth.resize(nodes * depth::kFloatsPerNode);
    level.lightVisibility.resize(nodes * 2);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const std::size_t node = level.grid.index(i, j, k);
                float* p = level.data.data() + node * 75;
                for (int f = 0; f < 75; ++f) p[f] = f < 3 ? 0.2f + hashed(i, j, k, f) : 0.2f * hashed(i, j, k, f) - 0.1f;
                float* d = level.depth.data() + node * depth::kFloatsPerNode;
                for (int f = 0; f < depth::kFloatsPerNode; ++f)
                    d[f] = depth::quantize(f >= 6 ? 0.3 * hashed(i, j, k, 100 + f) : hashed(i, j, k, 100 + f));
                for (int l = 0; l < 2; ++l) level.lightVisibility[node * 2 + l] = hashed(i, j, k, 200 + l);
            }
    v.levels.push_back(std::move(level));
    v.direct.mode = DirectMode::Occlusion;
    DirectLight point;
    point.position = kOrigin + Vec3d(5.0, 30.0, 7.0);
    point.value = Rgb(400.0f, 380.0f, 350.0f);
    v.direct.lights = {point, squareLight(kOrigin + Vec3d(12.0, 27.0, 12.0), Vec3d(0, -1, 0), 2.0, Rgb(900.0f, 900.0f, 800.0f))};
    return v;
}

struct Point {
    Vec3d x, n;
};

std::vector<Point> points(int n, int count) {
    Rng rng(17);
    std::vector<Point> out;
    const double extent = (n - 1) * kSpacing;
    for (int p = 0; p < count; ++p) {
        Point q;
        for (int a = 0; a < 3; ++a) q.x[a] = kOrigin[a] + extent * rng.uniform();
        if (p < 4) q.x = kOrigin + Vec3d(p * 37 % n, p * 53 % n, n - 1 - p) * kSpacing;  // nodes, a box face
        q.n = normalize(Vec3d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5 + 1e-3));
        out.push_back(q);
    }
    return out;
}

void writePoints(const std::string& path, const std::vector<Point>& pts) {
    std::ofstream out(path);
    out.precision(17);
    out << "x,y,z,nx,ny,nz\n";
    for (const Point& p : pts) out << p.x.x << ',' << p.x.y << ',' << p.x.z << ',' << p.n.x << ',' << p.n.y << ',' << p.n.z << '\n';
}

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool havePrlimit() {
    return test::runCommand("prlimit --version > /dev/null 2>&1") == 0 && test::runCommand("taskset -c 0 true > /dev/null 2>&1") == 0;
}
// The in-memory query's answers at the points, as `vdblight query --raw` computes them (the
// normal read as floats and normalised, the point in double).
std::vector<Rgb> inMemoryAnswers(const Volume& v, const std::vector<Point>& pts) {
    const IrradianceQuery q(v);
    std::vector<Rgb> out;
    for (const Point& p : pts) out.push_back(q.irradianceWorld(p.x, normalize(Vec3f(float(p.n.x), float(p.n.y), float(p.n.z)))));
    return out;
}

// The E columns of `vdblight query`'s CSV, parsed back to the floats it printed (9 digits
// identify a float), compared bit for bit with `expected`.
void expectSameFloats(const std::string& csv, const std::vector<Rgb>& expected) {
    std::istringstream rows(csv);
    std::string line;
    std::getline(rows, line);
    std::size_t row = 0;
    while (std::getline(rows, line)) {
        ASSERT_LT(row, expected.size());
        std::vector<std::string> fields;
        std::stringstream fs(line);
        for (std::string f; std::getline(fs, f, ',');) fields.push_back(f);
        ASSERT_EQ(fields.size(), 9u) << line;
        const float e[3] = {expected[row].x, expected[row].y, expected[row].z};
        for (int c = 0; c < 3; ++c) {
            const float v = std::strtof(fields[std::size_t(6 + c)].c_str(), nullptr);
            EXPECT_EQ(std::memcmp(&v, &e[c], sizeof v), 0) << "point " << row << " channel " << c << ": " << line << " vs " << e[c];
        }
        ++row;
    }
    EXPECT_EQ(row, expected.size());
}
}  // namespace

TEST(CliQueryStream, LargerThanItsMemoryLimit) {
#ifdef VDBLIGHT_SANITIZED
    GTEST_SKIP() << "under AddressSanitizer: its shadow memory counts against RLIMIT_DATA, so no memory limit applies";
#endif
    if (!havePrlimit()) GTEST_SKIP() << "prlimit or taskset (util-linux) is not available";
    test::TempDir dir;
    const std::string vdb = dir.file("world.vdb"), csv = dir.file("points.csv");
    const std::vector<Point> pts = points(kN, 64);
    writePoints(csv, pts);
    auto t0 = std::chrono::steady_clock::now();
    std::vector<Rgb> expected;
    {
        const Volume v = syntheticVolume(kN);
        expected = inMemoryAnswers(v, pts);
        std::printf("synthetic volume made and queried in memory in %.1f s\n", seconds(t0));
        writeVolume(v, vdb);
    }
    const uint64_t fileBytes = fs::file_size(vdb);
    const uint64_t limit = fileBytes / 4;
    std::printf("synthetic default-kind volume: %d^3 nodes, %.1f MB on disk, written in %.1f s; RLIMIT_DATA %.1f MB\n", kN,
                fileBytes / 1e6, seconds(t0), limit / 1e6);
    ASSERT_GE(fileBytes, 400'000'000u);
    // One CPU for the child (taskset): RLIMIT_DATA counts thread stacks (8 MB each), and TBB
    // starts a worker per core, so on a many-core machine the limit would measure the core count.
    const std::string limited = "taskset -c 0 prlimit --data=" + std::to_string(limit) + ":" + std::to_string(limit) + " ";

    // Streamed (chosen automatically above 256 MiB): the in-memory query's floats.
    t0 = std::chrono::steady_clock::now();
    std::string log;
    const int status = test::runCommand(limited + kCli + " query " + vdb + " --points " + csv + " --raw --stream-report -o " +
                                            dir.file("streamed.csv") + " 2>&1", &log);
    std::printf("streamed query of %zu points under the limit: %.2f s, %s", pts.size(), seconds(t0), log.c_str());
    ASSERT_EQ(status, 0) << log;
    expectSameFloats(test::readTextFile(dir.file("streamed.csv")), expected);
    // Only the leaves around the points were read: at most 8 per grid (25 + 4 + 2) and point.
    unsigned long long read = 0, total = 0;
    const std::size_t at = log.find("read ");
    ASSERT_NE(at, std::string::npos) << log;
    ASSERT_EQ(std::sscanf(log.c_str() + at, "read %llu of %llu leaves", &read, &total), 2) << log;
    EXPECT_LE(read, 31ull * 8ull * pts.size());
    EXPECT_LT(read * 10, total);

    // Exported in cells under the same limit. Texels 4.3 nodes apart read every leaf (8 nodes
    // per edge) of the coefficients' first nine grids, the depth and the visibility grids,
    // about 380 MB in memory: the leaves are dropped between cells once they pass 4 MiB
    // (--cells-leaf-memory), so the export holds the topology (43.5 MiB), the leaves of a cell
    // and its textures. (Measured: 85 MB of data segment suffice, 1 000 MiB of leaves kept would not.)
    t0 = std::chrono::steady_clock::now();
    const int cells = test::runCommand(limited + kCli + " export " + vdb + " -o " + dir.file("cells") +
                                           " --cells 6 --resolution 25 --cells-leaf-memory 4 2>&1", &log);
    std::printf("export --cells under the limit: exit %d after %.2f s: %s", cells, seconds(t0), log.c_str());
    ASSERT_EQ(cells, 0) << log;
    EXPECT_EQ(nlohmann::json::parse(test::readTextFile(dir.file("cells") + "/cells.json"))["cells_per_axis"],
              nlohmann::json::array({4, 4, 4}));
    EXPECT_TRUE(fs::exists(dir.file("cells") + "/cell_3_3_3/light_visibility_0_1.ktx2"));

    // Read whole, the same query cannot run under this limit.
    t0 = std::chrono::steady_clock::now();
    const int whole = test::runCommand(limited + kCli + " query " + vdb + " --points " + csv + " --raw --stream off -o " +
                                           dir.file("whole.csv") + " 2>&1", &log);
    std::printf("the same query read whole under the limit: exit %d after %.2f s: %s", whole, seconds(t0), log.c_str());
    EXPECT_NE(whole, 0) << log;
    EXPECT_NE(log.find("out of memory"), std::string::npos) << log;  // fails for memory, not for another reason
    EXPECT_FALSE(fs::exists(dir.file("whole.csv")));
}

// One point in every leaf (8^3 nodes) of an n^3 volume, with normals as points() makes them.
std::vector<Point> oneInEveryLeaf(int n) {
    std::vector<Point> out;
    for (int k = 4; k < n; k += 8)
        for (int j = 4; j < n; j += 8)
            for (int i = 4; i < n; i += 8) out.push_back({kOrigin + Vec3d(i + 0.3, j + 0.2, k + 0.1) * kSpacing, Vec3d(0, 1, 0)});
    return out;
}

// At its memory limit a streamed query ends like any other error: exit status 1, one line that
// says it ran out of memory and names the limit, no output file; never a crash. (libblosc,
// which decompresses each leaf into buffers it mallocs, dereferences the null pointer of a
// failed malloc, so StreamedVolume checks before each leaf that the memory is there, vdb_stream.cpp.)
// In a child process, as a user meets it: a fresh process's heap only grows as leaves are
// read, so its limit binds where the reading is (within one process, the heap that earlier
// reads freed serves the next ones whatever the limit: the limit never bound). The smallest
// limit at which the query of every leaf completes is found by bisection to 2 MB (each run that
// completes prints the answers of no limit); the same query then runs under 2, 4 and 8 MB less,
// inside the 20 MB that the leaves take.
TEST(CliQueryStream, StopsWithOneLineAtItsMemoryLimit) {
#ifdef VDBLIGHT_SANITIZED
    GTEST_SKIP() << "under AddressSanitizer: its shadow memory counts against RLIMIT_DATA, so no memory limit applies";
#endif
    if (!havePrlimit()) GTEST_SKIP() << "prlimit or taskset (util-linux) is not available";
    test::TempDir dir;
    constexpr int kNodes = 40;  // 5^3 leaves in each of 31 grids: about 20 MB of leaves in memory
    const std::string vdb = dir.file("world.vdb"), csv = dir.file("points.csv"), out = dir.file("out.csv");
    writeVolume(syntheticVolume(kNodes), vdb);
    writePoints(csv, oneInEveryLeaf(kNodes));
    const auto query = [&](uint64_t limit, std::string& log) {
        return test::runCommand("taskset -c 0 prlimit --data=" + std::to_string(limit) + ":" + std::to_string(limit) + " " +
                                    kCli + " query " + vdb + " --points " + csv + " --raw --stream on -o " + out + " 2>&1",
                                &log);
    };
    std::string log;
    uint64_t fails = 0, completes = 512ull << 20;
    ASSERT_EQ(query(completes, log), 0) << log;
    const std::string expected = test::readTextFile(out);
    while (completes - fails > (2u << 20)) {
        const uint64_t mid = (fails + completes) / 2;
        fs::remove(out);
        const bool completed = query(mid, log) == 0;
        (completed ? completes : fails) = mid;
        if (completed) {
            EXPECT_EQ(test::readTextFile(out), expected) << "under " << mid << " B";  // the answers of no limit
        }
    }
    std::printf("the streamed query of %d^3 nodes completes with a data segment of %.1f MB\n", kNodes, completes / 1e6);
    int leafStops = 0;
    for (const uint64_t less : {2u << 20, 4u << 20, 8u << 20}) {
        fs::remove(out);
        const int status = query(completes - less, log);
        std::printf("%.1f MB: exit %d: %s", (completes - less) / 1e6, status, log.c_str());
        EXPECT_EQ(status, 1) << log;  // a signal gives 128 + its number
        EXPECT_EQ(test::countLines(log), 1) << log;
        EXPECT_EQ(log.rfind("vdblight: error: out of memory", 0), 0u) << log;
        EXPECT_NE(log.find("RLIMIT_DATA"), std::string::npos) << log;
        EXPECT_FALSE(fs::exists(out));
        leafStops += log.find("the next leaf of") != std::string::npos;
    }
    EXPECT_GT(leafStops, 0);  // stopped by the check before a leaf (OutOfMemory), not elsewhere

    // Under an address-space limit (prlimit --as: it also counts the mapped file, the libraries
    // and the threads' stacks), a one-point query. Every limit from 36 MB below the smallest
    // that completes, in 3 MB steps, gives the answer or the one line with exit 1: never an
    // abort (before issue 33's fix, std::terminate while the error unwound, an OpenVDB tree's
    // destructor failing to allocate or to start a TBB worker: 185-187 MB for a 5.2 MB default
    // bake), nor "internal error" (TBB's "pthread_create has failed": 188-195 MB there). Limits
    // so low that the program cannot start at all (log4cplus aborts before main) are skipped.
    // On every CPU, unlike the runs above: on one, TBB starts no worker thread whose stack could
    // fail to fit.
    writePoints(csv, {oneInEveryLeaf(kNodes)[0]});
    const auto queryAs = [&](uint64_t limit, std::string& text) {
        return test::runCommand("prlimit --as=" + std::to_string(limit) + " " + kCli + " query " + vdb +
                                    " --points " + csv + " --raw --stream on -o " + out + " 2>&1",
                                &text);
    };
    uint64_t asFails = 0, asCompletes = 1024ull << 20;
    ASSERT_EQ(queryAs(asCompletes, log), 0) << log;
    while (asCompletes - asFails > (1u << 20)) {
        const uint64_t mid = (asFails + asCompletes) / 2;
        (queryAs(mid, log) == 0 ? asCompletes : asFails) = mid;
    }
    int stopped = 0, notStarted = 0;
    for (uint64_t less = 1u << 20; less <= (36u << 20); less += 3u << 20) {
        fs::remove(out);
        const int status = queryAs(asCompletes - less, log);
        if (status == 0) continue;  // the limit's edge is not sharp: mappings come and go
        if (status != 1 && test::runCommand("prlimit --as=" + std::to_string(asCompletes - less) + " " + kCli +
                                            " --version > /dev/null 2>&1") != 0) {
            ++notStarted;
            continue;
        }
        EXPECT_EQ(status, 1) << (asCompletes - less) / 1e6 << " MB: " << log;
        EXPECT_EQ(test::countLines(log), 1) << log;
        EXPECT_EQ(log.rfind("vdblight: error: out of memory", 0), 0u) << log;
        EXPECT_FALSE(fs::exists(out));
        ++stopped;
    }
    std::printf("--as: a one-point query completes at %.1f MB; of the 12 limits below it, %d stopped the query (each must "
                "with the one line), %d the program before it started\n",
                asCompletes / 1e6, stopped, notStarted);
    EXPECT_GT(stopped, 6);
}

// Same points, byte-identical output, streamed or read whole, for the default bake's kind.
TEST(CliQueryStream, SameOutputStreamedOrWhole) {
    test::TempDir dir;
    const std::string vdb = dir.file("small.vdb"), csv = dir.file("points.csv");
    const Volume v = syntheticVolume(20);
    writeVolume(v, vdb);
    const std::vector<Point> pts = points(20, 200);
    writePoints(csv, pts);
    std::string a, b, c;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --raw --stream on 2>&1", &a), 0) << a;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --raw 2>&1", &b), 0) << b;  // auto: small, whole
    EXPECT_EQ(a, b);
    expectSameFloats(a, inMemoryAnswers(v, pts));
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream on --outside error 2>&1", &c), 0) << c;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream off --outside error 2>&1", &b), 0) << b;
    EXPECT_EQ(c, b);
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream on --no-depth-weights 2>&1", &c), 0) << c;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream off --no-depth-weights 2>&1", &b), 0) << b;
    EXPECT_EQ(c, b);
    EXPECT_EQ(test::countLines(a), 201);
}

TEST(CliQueryStream, KindsThatDoNotStreamAreRefusedOrReadWhole) {
    test::TempDir dir;
    const std::string vdb = dir.file("bins.vdb");
    writeVolume(test::randomLevelsVolume(LayoutKind::Adaptive, 2, bins::basis(bins::parseBasisSpec("bins:2")), 1, 0.0f, 1.0f), vdb);
    test::expectCleanFailure(dir, "query " + vdb + " --at 0.5,0.5,0.5 --stream on", "cannot be streamed: its basis is 'bins:2'");
    std::string log;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --at 0.5,0.5,0.5 --stream-report 2>&1", &log), 0) << log;
    EXPECT_NE(log.find("read all of"), std::string::npos) << log;  // auto: small, read whole
}
