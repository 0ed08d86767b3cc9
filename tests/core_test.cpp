// The core every module shares: the atomic file writer (vdblight/atomic_file.h), parallelFor
// with progress and cancelling, and the linear-index helper (libvdblight/src/core/).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "../libvdblight/src/core/grid_index.h"    // internal
#include "../libvdblight/src/core/parallel_for.h"  // internal
#include "test_util.h"
#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace fs = std::filesystem;
using namespace vdblight;

namespace {
std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Writes half of `text` into `temp`, then fails the way a writer does half way.
template <typename Error>
void writeHalfThenThrow(const std::string& temp, const std::string& text, const std::string& message) {
    std::ofstream out(temp, std::ios::binary);
    out << text.substr(0, text.size() / 2);
    out.flush();
    ASSERT_TRUE(fs::exists(temp)) << "the writer writes into the temporary file";
    ASSERT_GT(fs::file_size(temp), 0u);
    throw Error(message);
}
}  // namespace

TEST(AtomicFile, WritesTheWholeContentAndNoTemporaryFile) {
    test::TempDir dir;
    writeFileAtomically(dir.file("a.txt"), std::string("hello\n"));
    EXPECT_EQ(readFile(dir.file("a.txt")), "hello\n");
    writeFileAtomically(dir.file("a.txt"), [](const std::string& temp) { std::ofstream(temp, std::ios::binary) << "second"; });
    EXPECT_EQ(readFile(dir.file("a.txt")), "second");
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"a.txt"});
}

TEST(AtomicFile, TheTemporaryFileIsBesideTheDestination) {
    test::TempDir dir;
    std::string seen;
    writeFileAtomically(dir.file("b.bin"), [&](const std::string& temp) {
        seen = temp;
        std::ofstream(temp, std::ios::binary) << "x";
    });
    EXPECT_EQ(fs::path(seen).parent_path(), dir.path());
    EXPECT_NE(seen, dir.file("b.bin"));
    EXPECT_FALSE(fs::exists(seen));
}

// A writer that throws half way leaves no output file and no temporary file; an existing file
// of that name keeps its old content.
TEST(AtomicFile, AWriterThatThrowsHalfWayLeavesNothing) {
    test::TempDir dir;
    const std::string path = dir.file("out.csv");
    std::string temp;
    try {
        writeFileAtomically(path, [&](const std::string& t) {
            temp = t;
            writeHalfThenThrow<std::runtime_error>(t, "a,b,c\n1,2,3\n", "disk on fire");
        });
        FAIL() << "expected IoError";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write '" + path + "': disk on fire");
    }
    EXPECT_FALSE(temp.empty());
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_TRUE(listDir(dir.path()).empty());

    writeFileAtomically(path, std::string("old"));
    EXPECT_THROW(writeFileAtomically(path, [&](const std::string& t) { writeHalfThenThrow<IoError>(t, "new content", "x"); }),
                 IoError);
    EXPECT_EQ(readFile(path), "old");
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out.csv"});
}

// Errors about the content keep their type; an I/O error that names the temporary file is
// reported against the destination, with "cannot write" once.
TEST(AtomicFile, ErrorsKeepTheirTypeAndNameTheDestination) {
    test::TempDir dir;
    const std::string path = dir.file("v.dat");
    EXPECT_THROW(writeFileAtomically(path, [&](const std::string& t) { writeHalfThenThrow<ValueError>(t, "abc", "bad value"); }),
                 ValueError);
    EXPECT_THROW(writeFileAtomically(path, [&](const std::string& t) { writeHalfThenThrow<Cancelled>(t, "abc", "stop"); }),
                 Cancelled);
    try {
        writeFileAtomically(path, [](const std::string& t) { throw IoError("cannot write '" + t + "': disk full"); });
        FAIL() << "expected IoError";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write '" + path + "': disk full");
    }
    EXPECT_TRUE(listDir(dir.path()).empty());
}

TEST(AtomicFile, AMissingDirectoryOrAnUncommittedFileLeavesNothing) {
    test::TempDir dir;
    EXPECT_THROW(writeFileAtomically(dir.file("no/such/dir/x"), std::string("x")), IoError);
    EXPECT_THROW(AtomicFile(""), IoError);
    {
        AtomicFile f(dir.file("never.txt"));
        std::ofstream(f.tempPath()) << "never committed";
        EXPECT_TRUE(fs::exists(f.tempPath()));
    }
    EXPECT_TRUE(listDir(dir.path()).empty());
    // A destination that is a directory is refused up front by name; nothing is left.
    fs::create_directory(dir.path() / "taken");
    try {
        writeFileAtomically(dir.file("taken"), std::string("x"));
        FAIL() << "expected IoError";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot write '" + dir.file("taken") + "': it is a directory");
    }
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"taken"});
    EXPECT_TRUE(fs::is_empty(dir.path() / "taken"));
}

namespace {
bool isFifo(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}
bool isCharDevice(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}
}  // namespace

// A destination that is no regular file (here a FIFO; `-o /dev/null` is the same code path,
// below) receives the content: it is not renamed over (which would leave a regular file in
// its place), and no temporary file is left beside it or in the temporary directory.
TEST(AtomicFile, AFifoReceivesTheContentAndStaysAFifo) {
    test::TempDir dir;
    const std::string fifo = dir.file("pipe");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);

    // A writer that fails never opens the FIFO (no reader needed) and leaves nothing.
    std::string temp;
    EXPECT_THROW(writeFileAtomically(fifo, [&](const std::string& t) {
                     temp = t;
                     writeHalfThenThrow<std::runtime_error>(t, "half of it", "x");
                 }),
                 IoError);
    EXPECT_TRUE(isFifo(fifo));
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_EQ(fs::path(temp).parent_path(), fs::temp_directory_path()) << "not beside the FIFO";

    std::string received;
    std::thread reader([&] { received = readFile(fifo); });
    const std::string content(300000, 'v');  // more than a pipe buffer: the copy loops
    writeFileAtomically(fifo, [&](const std::string& t) {
        temp = t;
        std::ofstream(t, std::ios::binary) << content;
    });
    reader.join();
    EXPECT_EQ(received.size(), content.size());
    EXPECT_TRUE(received == content);
    EXPECT_TRUE(isFifo(fifo)) << "the FIFO was replaced by a regular file";
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"pipe"});
}

// /dev/null (a character device) takes the FIFO's code path: copied into, never renamed over.
// Only the decision is checked here, without a commit, so that a bug cannot replace the
// machine's /dev/null (root may rename over it).
TEST(AtomicFile, DevNullIsWrittenIntoNotRenamedOver) {
    if (!isCharDevice("/dev/null")) GTEST_SKIP() << "/dev/null is not a character device on this machine";
    std::string temp;
    {
        AtomicFile f("/dev/null");
        EXPECT_TRUE(f.copiesIntoDestination());
        temp = f.tempPath();
        EXPECT_EQ(fs::path(temp).parent_path(), fs::temp_directory_path());
        EXPECT_TRUE(fs::is_regular_file(temp));
    }
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_TRUE(isCharDevice("/dev/null"));

    test::TempDir dir;
    EXPECT_FALSE(AtomicFile(dir.file("new.txt")).copiesIntoDestination());
    writeFileAtomically(dir.file("old.txt"), std::string("x"));
    EXPECT_FALSE(AtomicFile(dir.file("old.txt")).copiesIntoDestination());
}

namespace {
/// Records what the library reports, and cancels after `cancelAfter` steps (0 = never).
struct RecordingInterrupter : Interrupter {
    explicit RecordingInterrupter(uint64_t cancelAfter = 0) : cancelAfter(cancelAfter) {}
    void start(const char* task, uint64_t total) override {
        std::lock_guard<std::mutex> lock(mutex);
        starts.push_back(std::string(task) + ":" + std::to_string(total));
    }
    void progress(uint64_t done) override {
        uint64_t seen = highest.load();
        while (done > seen && !highest.compare_exchange_weak(seen, done)) {
        }
        ++calls;
    }
    bool wasInterrupted() override { return cancelAfter > 0 && highest.load() >= cancelAfter; }
    void end() override { ++ends; }

    uint64_t cancelAfter;
    std::mutex mutex;
    std::vector<std::string> starts;
    std::atomic<uint64_t> highest{0}, calls{0};
    std::atomic<int> ends{0};
};
}  // namespace

TEST(ParallelFor, VisitsEveryIndexOnceForAnyThreadCount) {
    for (int threads : {1, 2, 3, 0}) {
        std::vector<std::atomic<int>> visits(1000);
        core::parallelFor(visits.size(), threads, [&](std::size_t i) { ++visits[i]; });
        for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << ", " << threads << " threads";
    }
    core::parallelFor(0, 2, [](std::size_t) { FAIL() << "no index in an empty range"; });
}

TEST(ParallelFor, ReportsEveryStepBetweenStartAndEnd) {
    RecordingInterrupter in;
    {
        core::TaskProgress progress(&in, "task", 500, "task cancelled");
        core::parallelFor(500, 2, [](std::size_t) {}, &progress);
        EXPECT_EQ(in.ends.load(), 0);
    }
    EXPECT_EQ(in.starts, std::vector<std::string>{"task:500"});
    EXPECT_EQ(in.highest.load(), 500u);
    EXPECT_EQ(in.calls.load(), 500u);
    EXPECT_EQ(in.ends.load(), 1);
}

// A cancel skips the items not yet begun and throws Cancelled with the task's message; end()
// is still called once.
TEST(ParallelFor, ACancelStopsTheLoopAndThrows) {
    for (int threads : {1, 2}) {
        RecordingInterrupter in(10);
        std::atomic<uint64_t> ran{0};
        try {
            core::TaskProgress progress(&in, "task", 100000, "task cancelled");
            core::parallelFor(100000, threads, [&](std::size_t) { ++ran; }, &progress);
            FAIL() << "expected Cancelled";
        } catch (const Cancelled& e) {
            EXPECT_EQ(std::string(e.what()), "task cancelled");
        }
        EXPECT_GE(ran.load(), 10u);
        EXPECT_LT(ran.load(), 1000u) << threads << " threads";
        EXPECT_EQ(in.ends.load(), 1);
    }
}

TEST(ParallelFor, ProgressWithoutAnInterrupterOnlyCounts) {
    core::TaskProgress progress(nullptr, "quiet", 10, "never");
    core::parallelFor(10, 2, [](std::size_t) {}, &progress);
    EXPECT_FALSE(progress.cancelled());
    progress.reportDone(10);
    EXPECT_NO_THROW(progress.throwIfCancelled());
}

TEST(GridIndex, UnflattenInvertsGridSpecIndex) {
    GridSpec g;
    g.nx = 5, g.ny = 3, g.nz = 4;
    std::size_t seen = 0;
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i, ++seen) {
                const core::Index3 c = core::unflatten(g.index(i, j, k), uint64_t(g.nx), uint64_t(g.ny));
                ASSERT_EQ(g.index(i, j, k), seen);
                EXPECT_EQ(c.i, i);
                EXPECT_EQ(c.j, j);
                EXPECT_EQ(c.k, k);
            }
    // Indices past 2^32 (a large grid) stay exact.
    const uint64_t big = uint64_t(3000) + 4000 * (uint64_t(2999) + 3000 * uint64_t(2500));
    const core::Index3 c = core::unflatten(big, 4000, 3000);
    EXPECT_EQ(c.i, 3000);
    EXPECT_EQ(c.j, 2999);
    EXPECT_EQ(c.k, 2500);
}
