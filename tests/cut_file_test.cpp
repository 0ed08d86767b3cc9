// A .vdb cut short at any byte is refused by every reader with the message of vdblight's own
// structure check (vdb_read_parts.h, checkNotTruncated), before OpenVDB parses the file.
//
// Why so many cuts: OpenVDB's io::File::open allocates the lengths it reads. A file cut inside a
// grid's metadata made `vdblight info` (which first asks the PRT reader whether the file is a
// PRT file) allocate 19 GB in Release; under ASan the process was killed (CI, session 20).
// Where a cut lands decides whether a length is garbage, so one cut proves little: the test cuts
// every 61st byte (a prime, so the cuts fall at every offset within the file's 4- and 8-byte
// fields; every byte of the 96 KB file took 3 minutes in Release). In a 389 KB default-scene
// bake, 54 cuts of that stride (from two starts) each kept `vdblight info` busy for 1-28 s,
// one of them at 19 GB resident, before the PRT reader had the check.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "test_util.h"
#include "tiny_volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {

/// True if `message` is one of the structure check's refusals, not OpenVDB's own error passed on.
bool refusedByTheStructureCheck(const std::string& message) {
    for (const char* checked : {"is truncated:", "(truncated or corrupt?)", "(corrupt file?)"})
        if (message.find(checked) != std::string::npos) return true;
    return false;
}

constexpr std::size_t kStride = 61;

template <typename Read>
void expectEveryCutRefused(const std::string& bytes, const test::TempDir& dir, const char* reader, Read read) {
    const std::string path = dir.file("cut.vdb");
    int cuts = 0, refused = 0;
    for (std::size_t length = 0; length < bytes.size(); length += kStride, ++cuts) {
        test::writeTextFile(path, bytes.substr(0, length));
        try {
            read(path);
            ADD_FAILURE() << reader << " accepted the file cut to " << length << " of " << bytes.size() << " bytes";
        } catch (const FormatError& e) {
            if (refusedByTheStructureCheck(e.what())) {
                ++refused;
            } else {
                ADD_FAILURE() << reader << ", cut to " << length << " bytes: OpenVDB parsed it: " << e.what();
            }
        }
        if (::testing::Test::HasFailure()) return;  // one cut's story is enough
    }
    EXPECT_EQ(refused, cuts) << reader;
}

TEST(CutFile, EveryReaderRefusesAFileCutAtAnyByteBeforeOpenVdbParsesIt) {
    test::TempDir dir;
    const std::string whole = dir.file("whole.vdb");
    writeVolume(test::tinySh2Volume(), whole);
    const std::string bytes = test::readTextFile(whole);
    // The whole file reads (so the refusals below are about the cut).
    ASSERT_NO_THROW(readVolume(whole));
    ASSERT_FALSE(isPrtFile(whole));
    std::printf("the whole file: %zu bytes, cut every %zu bytes\n", bytes.size(), kStride);

    expectEveryCutRefused(bytes, dir, "isPrtFile", [](const std::string& p) { isPrtFile(p); });
    expectEveryCutRefused(bytes, dir, "readPrt", [](const std::string& p) { readPrt(p); });
    expectEveryCutRefused(bytes, dir, "readVolume", [](const std::string& p) { readVolume(p); });
    expectEveryCutRefused(bytes, dir, "inspectVolumeFile", [](const std::string& p) { inspectVolumeFile(p); });
}

}  // namespace
}  // namespace vdblight
