// The .vdb reader against hostile lengths found by tests/fuzz/fuzz_vdb: a metadata length
// beyond the end of the file (file-level or in a grid's own metadata) is refused with
// FormatError before OpenVDB allocates it (it would allocate the length it reads).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "test_util.h"
#include "tiny_volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

/// Sets the value length of the metadata entry named `key` (the `occurrence`-th time the name
/// appears) to `length`: the entry is [u32 len]name [u32 len]type [u32 len]value.
std::string withValueLength(std::string bytes, const std::string& key, int occurrence, uint32_t length) {
    std::string name(4, '\0');  // the length-prefixed name, so that a longer key never matches
    const auto keyLength = uint32_t(key.size());
    std::memcpy(name.data(), &keyLength, 4);
    name += key;
    std::size_t at = std::string::npos;
    for (int k = 0; k <= occurrence; ++k) at = bytes.find(name, at == std::string::npos ? 0 : at + 1);
    EXPECT_NE(at, std::string::npos) << key;
    if (at == std::string::npos) return bytes;
    std::size_t p = at + name.size();
    uint32_t typeLength = 0;
    std::memcpy(&typeLength, bytes.data() + p, 4);
    p += 4 + typeLength;
    std::memcpy(bytes.data() + p, &length, 4);
    return bytes;
}

void expectRefused(const test::TempDir& dir, const std::string& bytes) {
    const std::string path = dir.file("hostile.vdb");
    test::writeTextFile(path, bytes);
    try {
        readVolume(path);
        ADD_FAILURE() << "readVolume accepted a hostile metadata length";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("metadata is corrupt"), std::string::npos) << e.what();
    }
    EXPECT_THROW(inspectVolumeFile(path), FormatError);
}

TEST(VdbReadHostile, MetadataLengthsBeyondTheFileAreRefusedBeforeAllocation) {
    test::TempDir dir;
    const std::string good = dir.file("good.vdb");
    writeVolume(test::tinySh2Volume(), good);
    const std::string bytes = test::readTextFile(good);
    ASSERT_NO_THROW(readVolume(good));
    // The lengths themselves were the only problem: one byte past the end is refused,
    // the real length is accepted.
    expectRefused(dir, withValueLength(bytes, "vdblight:format_version", 0, 0x7ffffff0u));
    expectRefused(dir, withValueLength(bytes, "vdblight:format_version", 0, uint32_t(bytes.size())));
    // A grid's own metadata (each channel grid carries vdblight:channel).
    expectRefused(dir, withValueLength(bytes, "vdblight:channel", 0, 0xfffffff0u));
    expectRefused(dir, withValueLength(bytes, "vdblight:channel", 3, 0x40000000u));
    // A length that fits in the file but disagrees with a fixed-size type (format_version is
    // an int64: OpenVDB reads 8 bytes whatever the length says) would put OpenVDB's parse out
    // of step with the check, and its next length would come from inside a value (fuzz_vdb).
    expectRefused(dir, withValueLength(bytes, "vdblight:format_version", 0, 4));
    expectRefused(dir, withValueLength(bytes, "vdblight:format_version", 0, 12));
}

TEST(VdbReadHostile, FilesWithoutGridOffsetsAreRefusedBeforeOpenVdbParsesThem) {
    // Without grid offsets OpenVDB reads grid descriptors with unchecked lengths (fuzz_vdb
    // found a name length of gigabytes), so such files are refused up front. Byte 20 of the
    // header (after magic, file version and library version) is the grid-offsets flag.
    test::TempDir dir;
    const std::string good = dir.file("good.vdb");
    writeVolume(test::tinySh2Volume(), good);
    std::string bytes = test::readTextFile(good);
    ASSERT_EQ(bytes[20], 1);
    EXPECT_NO_THROW(readVolume(good));
    bytes[20] = 0;
    const std::string path = dir.file("stream.vdb");
    test::writeTextFile(path, bytes);
    for (int call = 0; call < 2; ++call) {
        try {
            if (call == 0) readVolume(path);
            else inspectVolumeFile(path);
            ADD_FAILURE() << "a file without grid offsets was accepted";
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find("no grid offsets"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace vdblight
