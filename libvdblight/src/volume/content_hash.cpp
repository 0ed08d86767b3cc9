#include "content_hash.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <openvdb/version.h>

#include "sha256.h"

namespace vdblight {
namespace vdb_detail {
namespace {

/// Checks the fixed part of the header: the magic number and a UUID-shaped field.
void checkHeader(const char* head, const std::string& path) {
    int64_t magic = 0;
    std::memcpy(&magic, head, sizeof magic);
    if (magic != int64_t(openvdb::OPENVDB_MAGIC)) throw std::runtime_error("'" + path + "' is not an OpenVDB file");
    const char* uuid = head + kUuidOffset;
    for (int i = 0; i < kUuidChars; ++i) {
        const bool hyphen = i == 8 || i == 13 || i == 18 || i == 23;
        const char c = uuid[i];
        const bool hex = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
        if (hyphen ? c != '-' : !hex) throw std::runtime_error("'" + path + "' has no UUID where OpenVDB 10 writes it");
    }
}

/// RFC 9562 layout with version 8 ("custom"): the first 16 bytes of the digest with the
/// version and variant bits set, so that tools that parse UUIDs accept it.
std::string uuidFromDigest(const std::array<uint8_t, 32>& d) {
    uint8_t b[16];
    std::memcpy(b, d.data(), 16);
    b[6] = uint8_t((b[6] & 0x0f) | 0x80);
    b[8] = uint8_t((b[8] & 0x3f) | 0x80);
    static const char* kHex = "0123456789abcdef";
    std::string s;
    for (int i = 0; i < 16; ++i) {
        if (i == 4 || i == 6 || i == 8 || i == 10) s += '-';
        s += kHex[b[i] >> 4], s += kHex[b[i] & 15];
    }
    return s;
}

}  // namespace

FileDigest digestVdbFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read '" + path + "'");
    char head[kUuidOffset + kUuidChars];
    if (!in.read(head, sizeof head)) throw std::runtime_error("'" + path + "' is too short for an OpenVDB header");
    checkHeader(head, path);
    Sha256 sha;
    sha.update(head, kUuidOffset);  // everything but the UUID
    std::vector<char> chunk(1 << 20);
    while (in) {
        in.read(chunk.data(), std::streamsize(chunk.size()));
        sha.update(chunk.data(), std::size_t(in.gcount()));
    }
    if (!in.eof()) throw std::runtime_error("cannot read '" + path + "'");
    const std::array<uint8_t, 32> digest = sha.finish();
    FileDigest out;
    out.sha256 = Sha256::hex(digest);
    out.contentUuid = uuidFromDigest(digest);
    out.headerUuid.assign(head + kUuidOffset, std::size_t(kUuidChars));
    return out;
}

bool looksContentDerived(const std::string& uuid) {
    if (uuid.size() != std::size_t(kUuidChars)) return false;
    const char variant = uuid[19];
    return uuid[14] == '8' && (variant == '8' || variant == '9' || variant == 'a' || variant == 'b');
}

void stampContentUuid(const std::string& path) {
    const FileDigest digest = digestVdbFile(path);
    std::fstream out(path, std::ios::binary | std::ios::in | std::ios::out);
    out.seekp(kUuidOffset);
    out.write(digest.contentUuid.data(), kUuidChars);
    out.flush();
    if (!out) throw std::runtime_error("cannot rewrite the header of '" + path + "'");
}

}  // namespace vdb_detail
}  // namespace vdblight
