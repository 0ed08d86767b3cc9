// `vdblight query` on a volume larger than its memory limit (issue 17, "Worlds larger than
// memory"): a synthetic uniform SH file of about 400 MB is queried in a child process whose
// data segment (RLIMIT_DATA, set with prlimit) is a quarter of the file. Streamed, it answers
// the values known from construction; read whole (--stream off), it must fail under the same
// limit, so the test can fail. On a small file both modes print the same bytes.
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
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cli_util.h"
#include "test_util.h"
#include "random_volumes.h"
#include "vdblight/bins.h"
#include "vdblight/sampling.h"
#include "vdblight/sh.h"
#include "vdblight/vdb_io.h"

using namespace vdblight;
namespace fs = std::filesystem;

namespace {
const std::string kCli = VDBLIGHT_CLI_PATH;
constexpr int kN = 170;  // nodes per axis: 4.9 M nodes, 530 MB of floats, ~410 MB on disk (Blosc)
const Vec3d kOrigin(-3.0, 0.5, 2.0);
constexpr double kSpacing = 0.25;

// The synthetic coefficient of node (i, j, k), SH channel c, colour r: a hash of the indices
// mapped to [0.2, 1.2) with 24 random mantissa bits, so that the file does not compress.
float coefficient(int i, int j, int k, int c, int r) {
    const uint64_t h = hashCombine(hashCombine(hashCombine(uint64_t(i), uint64_t(j)), uint64_t(k)), uint64_t(c * 3 + r));
    return 0.2f + float(h >> 40) * (1.0f / 16777216.0f);
}

Volume syntheticVolume(int n) {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.origin = kOrigin;
    level.grid.spacing = kSpacing;
    level.grid.nx = level.grid.ny = level.grid.nz = n;
    level.data.resize(level.grid.nodeCount() * 27);
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                float* p = level.data.data() + level.grid.index(i, j, k) * 27;
                for (int c = 0; c < 9; ++c)
                    for (int r = 0; r < 3; ++r) p[3 * c + r] = coefficient(i, j, k, c, r);
            }
    v.levels.push_back(std::move(level));
    return v;
}

// E(x, n) from the closed form: trilinear weights in double, the generic SH code, the
// cosine-lobe constants (the definition in docs/format.md), and the scale of its terms.
Rgbd expected(int n, const Vec3d& x, const Vec3d& normal, double& scale) {
    double y[9];
    sh::evalGeneric(2, normalize(normal), y);
    int lo[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
        const double g = std::min(std::max((x[a] - kOrigin[a]) / kSpacing, 0.0), double(n - 1));
        lo[a] = std::min(int(g), n - 2);
        f[a] = g - lo[a];
    }
    Rgbd e(0, 0, 0);
    scale = 0;
    for (int corner = 0; corner < 8; ++corner) {
        int idx[3];
        double w = 1;
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            idx[a] = lo[a] + bit;
            w *= bit ? f[a] : 1 - f[a];
        }
        for (int c = 0; c < 9; ++c) {
            const double s = w * sh::kCosineLobe[sh::bandOf(c)] * y[c];
            e += Rgbd(coefficient(idx[0], idx[1], idx[2], c, 0), coefficient(idx[0], idx[1], idx[2], c, 1),
                      coefficient(idx[0], idx[1], idx[2], c, 2)) * s;
            scale += std::abs(s) * 1.2;
        }
    }
    return e;
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
}  // namespace

TEST(CliQueryStream, LargerThanItsMemoryLimit) {
#ifdef VDBLIGHT_SANITIZED
    GTEST_SKIP() << "under AddressSanitizer: its shadow memory counts against RLIMIT_DATA, so no memory limit applies";
#endif
    if (!havePrlimit()) GTEST_SKIP() << "prlimit or taskset (util-linux) is not available";
    test::TempDir dir;
    const std::string vdb = dir.file("world.vdb"), csv = dir.file("points.csv");
    auto t0 = std::chrono::steady_clock::now();
    {
        const Volume v = syntheticVolume(kN);
        std::printf("synthetic volume made in %.1f s\n", seconds(t0));
        writeVolume(v, vdb);
    }
    const uint64_t fileBytes = fs::file_size(vdb);
    const uint64_t limit = fileBytes / 4;
    std::printf("synthetic volume: %d^3 nodes, %.1f MB on disk, written in %.1f s; RLIMIT_DATA %.1f MB\n", kN,
                fileBytes / 1e6, seconds(t0), limit / 1e6);
    ASSERT_GE(fileBytes, 400'000'000u);
    const std::vector<Point> pts = points(kN, 64);
    writePoints(csv, pts);
    // One CPU for the child (taskset): RLIMIT_DATA counts thread stacks (8 MB each), and TBB
    // starts a worker per core, so on a many-core machine the limit would measure the core count.
    const std::string limited = "taskset -c 0 prlimit --data=" + std::to_string(limit) + ":" + std::to_string(limit) + " ";

    // Streamed (chosen automatically above 256 MiB): the values of the construction.
    t0 = std::chrono::steady_clock::now();
    std::string log;
    const int status = test::runCommand(limited + kCli + " query " + vdb + " --points " + csv + " --raw --stream-report -o " +
                                            dir.file("streamed.csv") + " 2>&1", &log);
    std::printf("streamed query of %zu points under the limit: %.2f s, %s", pts.size(), seconds(t0), log.c_str());
    ASSERT_EQ(status, 0) << log;
    std::istringstream rows(test::readTextFile(dir.file("streamed.csv")));
    std::string line;
    std::getline(rows, line);
    std::size_t checked = 0;
    while (std::getline(rows, line)) {
        double v[9];
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", v, v + 1, v + 2, v + 3, v + 4, v + 5, v + 6,
                              v + 7, v + 8), 9) << line;
        ASSERT_LT(checked, pts.size());
        double scale = 0;
        const Rgbd e = expected(kN, pts[checked].x, pts[checked].n, scale);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[6 + c], e[c], 2e-6 * scale) << "point " << checked << ": " << line;
        ++checked;
    }
    EXPECT_EQ(checked, pts.size());
    // Only the leaves around the points were read: at most 8 per grid and point.
    unsigned long long read = 0, total = 0;
    const std::size_t at = log.find("read ");
    ASSERT_NE(at, std::string::npos) << log;
    ASSERT_EQ(std::sscanf(log.c_str() + at, "read %llu of %llu leaves", &read, &total), 2) << log;
    EXPECT_LE(read, 9ull * 8ull * pts.size());
    EXPECT_LT(read * 10, total);

    // Read whole, the same query cannot run under this limit.
    t0 = std::chrono::steady_clock::now();
    const int whole = test::runCommand(limited + kCli + " query " + vdb + " --points " + csv + " --raw --stream off -o " +
                                           dir.file("whole.csv") + " 2>&1", &log);
    std::printf("the same query read whole under the limit: exit %d after %.2f s: %s", whole, seconds(t0), log.c_str());
    EXPECT_NE(whole, 0) << log;
    EXPECT_NE(log.find("out of memory"), std::string::npos) << log;  // fails for memory, not for another reason
    EXPECT_FALSE(fs::exists(dir.file("whole.csv")));
}

TEST(CliQueryStream, SameOutputStreamedOrWhole) {
    test::TempDir dir;
    const std::string vdb = dir.file("small.vdb"), csv = dir.file("points.csv");
    writeVolume(syntheticVolume(20), vdb);
    writePoints(csv, points(20, 200));
    std::string a, b, c;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --raw --stream on 2>&1", &a), 0) << a;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --raw 2>&1", &b), 0) << b;  // auto: small, whole
    EXPECT_EQ(a, b);
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream on --outside error 2>&1", &c), 0) << c;
    ASSERT_EQ(test::runCommand(kCli + " query " + vdb + " --points " + csv + " --stream off --outside error 2>&1", &b), 0) << b;
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
