// Reproducible files (issue 17): the header UUID derived from the content, the content hash,
// and run-specific metadata left out (docs/format.md, "Reproducible files").
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "../libvdblight/src/volume/sha256.h"  // internal, tested against FIPS 180-4 vectors
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

std::string sha256Hex(const std::string& text) {
    vdb_detail::Sha256 h;
    h.update(text.data(), text.size());
    return vdb_detail::Sha256::hex(h.finish());
}

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

Volume smallVolume(float scale = 1.0f) {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.origin = Vec3d(0.5, -1, 2);
    level.grid.spacing = 0.25;
    level.grid.nx = 9, level.grid.ny = 5, level.grid.nz = 3;  // two leaves along x
    level.data.resize(level.grid.nodeCount() * 27);
    for (std::size_t i = 0; i < level.data.size(); ++i) level.data[i] = scale * float(i % 97) * 0.125f;
    v.levels.push_back(level);
    v.meta["seed"] = int64_t(3);
    v.meta["bake_seconds"] = 1.25;
    v.meta["threads"] = int64_t(2);
    return v;
}

TEST(Sha256, KnownVectors) {
    EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    // One million 'a', fed in uneven pieces (the buffering path).
    vdb_detail::Sha256 h;
    const std::string piece(997, 'a');
    std::size_t left = 1000000;
    while (left > 0) {
        const std::size_t n = std::min(left, piece.size());
        h.update(piece.data(), n);
        left -= n;
    }
    EXPECT_EQ(vdb_detail::Sha256::hex(h.finish()), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Reproducible, SameVolumeSameBytesAndUuidFromContent) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb"), b = dir.file("b.vdb"), c = dir.file("c.vdb");
    writeVolume(smallVolume(), a);
    writeVolume(smallVolume(), b);
    writeVolume(smallVolume(2.0f), c);
    EXPECT_EQ(fileBytes(a), fileBytes(b));  // OpenVDB alone would differ in the header UUID
    const ContentHash ha = fileContentHash(a), hc = fileContentHash(c);
    EXPECT_TRUE(ha.uuidFromContent);
    EXPECT_EQ(ha.sha256.size(), 64u);
    EXPECT_EQ(ha.headerUuid.size(), 36u);
    EXPECT_EQ(ha.headerUuid[14], '8');  // RFC 9562 version 8
    EXPECT_NE(ha.sha256, hc.sha256);
    EXPECT_NE(ha.headerUuid, hc.headerUuid);
    EXPECT_NE(fileBytes(a).find(ha.headerUuid), std::string::npos);
    EXPECT_EQ(inspectVolumeFile(a).hash.sha256, ha.sha256);
    // The file still reads back, values intact; the hash its damage check computed comes out
    // with it (what `info` reuses instead of hashing the file twice) and is the file's own.
    ContentHash read;
    EXPECT_EQ(readVolume(a, &read).levels[0].data, smallVolume().levels[0].data);
    EXPECT_EQ(read.sha256, ha.sha256);
    EXPECT_EQ(read.headerUuid, ha.headerUuid);
    EXPECT_TRUE(read.uuidFromContent);
    EXPECT_EQ(inspectVolumeFile(a, &read).hash.sha256, ha.sha256);
}

// The content hash is what farms and merges compare across versions of vdblight, so it must
// not move when the code computing it does (issue 30: SHA-256 from libcrypto instead of our
// own). The hex string was computed by the hand-written SHA-256 before the change; OpenVDB 10
// writes these bytes for smallVolume().
TEST(Reproducible, ContentHashOfASmallVolumeIsPinned) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb");
    writeVolume(smallVolume(), a);
    const ContentHash h = fileContentHash(a);
    EXPECT_EQ(h.sha256, "e5d5ac5e66001b623072dd06fe80532b66b40b8d304810d4091caaf5e6ad2bb5");
    EXPECT_EQ(h.headerUuid, "e5d5ac5e-6600-8b62-b072-dd06fe80532b");
}

TEST(Reproducible, RunSpecificMetadataOnlyOnRequest) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb"), b = dir.file("b.vdb");
    writeVolume(smallVolume(), a);
    const Volume ra = readVolume(a);
    EXPECT_EQ(ra.meta.count("bake_seconds"), 0u);
    EXPECT_EQ(ra.meta.count("threads"), 0u);
    EXPECT_EQ(ra.meta.count("seed"), 1u);
    WriteOptions keep;
    keep.reproducible = false;
    writeVolume(smallVolume(), b, keep);
    const Volume rb = readVolume(b);
    EXPECT_EQ(metaNumber(rb.meta, "bake_seconds", 0), 1.25);
    EXPECT_EQ(metaNumber(rb.meta, "threads", 0), 2);
    EXPECT_TRUE(fileContentHash(b).uuidFromContent);
}

TEST(Reproducible, TamperedFileNoLongerMatchesItsUuid) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb");
    writeVolume(smallVolume(), a);
    std::string bytes = fileBytes(a);
    bytes[bytes.size() - 1] ^= 1;  // the last byte of grid data
    std::ofstream(a, std::ios::binary | std::ios::trunc) << bytes;
    EXPECT_FALSE(fileContentHash(a).uuidFromContent);
    EXPECT_TRUE(fileContentHash(a).damaged);
    test::writeTextFile(dir.file("x.vdb"), "not a vdb file at all, but long enough for a header........");
    EXPECT_THROW(fileContentHash(dir.file("x.vdb")), FormatError);
    EXPECT_THROW(fileContentHash(dir.file("missing.vdb")), IoError);
}

/// Writes `bytes` with the header UUID replaced by `uuid` (36 characters at byte 21).
void writeWithUuid(std::string bytes, const std::string& uuid, const std::string& path) {
    bytes.replace(21, 36, uuid);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(Reproducible, ADamagedFileIsRefusedBeforeOpenVdbReadsItsData) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb");
    writeVolume(smallVolume(), a);
    std::string bytes = fileBytes(a);
    bytes[bytes.size() / 2] ^= 0x40;  // a bad copy: one bit in the grid data
    std::ofstream(a, std::ios::binary | std::ios::trunc) << bytes;
    try {
        (void)readVolume(a);
        ADD_FAILURE() << "a damaged file was read";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("is damaged"), std::string::npos) << e.what();
    }
    // info still lists it (it reads no node data) and says so.
    EXPECT_TRUE(inspectVolumeFile(a).hash.damaged);
    // A file whose UUID another writer chose at random (version 4) cannot be checked: it is
    // read as before, and not called damaged.
    writeWithUuid(fileBytes(a), "0f5d2a4e-1c3b-4a9e-8d7c-6b5a4f3e2d1c", a);
    EXPECT_FALSE(fileContentHash(a).damaged);
    writeVolume(smallVolume(), a);
    writeWithUuid(fileBytes(a), "0f5d2a4e-1c3b-4a9e-8d7c-6b5a4f3e2d1c", a);
    EXPECT_EQ(readVolume(a).levels.at(0).data, smallVolume().levels.at(0).data);
}

// The input on which OpenVDB 10 reads a leaf's blosc block past its buffer
// (tests/fuzz/known_crashes.txt) carries a random UUID, so nothing can check it. Had this
// writer written it (a content-derived UUID) and the file been damaged since, the check
// refuses it before OpenVDB parses a leaf: under ASan, a missing check is a
// heap-buffer-overflow report here.
TEST(Reproducible, TheBloscOverflowInputIsRefusedWhenItsUuidIsContentDerived) {
    test::TempDir dir;
    const std::string input = std::string(VDBLIGHT_SOURCE_DIR) +
                              "/tests/fuzz/known_inputs/fuzz_vdb/openvdb-blosc-heap-overflow.vdb";
    const std::string a = dir.file("damaged.vdb");
    writeWithUuid(fileBytes(input), "cbde310f-f8ee-8329-936a-b873e6704ff3", a);  // version 8
    ASSERT_TRUE(fileContentHash(a).damaged);
    EXPECT_THROW((void)readVolume(a), FormatError);
}

}  // namespace
}  // namespace vdblight
