// The content hash of a .vdb file and the header UUID derived from it (docs/format.md,
// "Reproducible files"). Internal to the volume module.
//
// OpenVDB writes a fresh random UUID into every file header (io::Archive::writeHeader), so
// two bakes of the same volume would differ in 36 bytes. The writer replaces those bytes in
// its temporary file, before the rename, by a UUID made from the SHA-256 of every other byte
// of the file: equal content, equal file.
#pragma once

#include <string>

namespace vdblight {
namespace vdb_detail {

/// Where OpenVDB (file format 222 and later) keeps the UUID: after the magic number (8 bytes),
/// the file format version (4), the library version (4 + 4) and the grid-offsets flag (1),
/// as 36 ASCII characters 8-4-4-4-12 (Archive.cc, readHeader / writeHeader).
constexpr long kUuidOffset = 21;
constexpr long kUuidChars = 36;

struct FileDigest {
    std::string sha256;       ///< hex SHA-256 of the file without the UUID field
    std::string contentUuid;  ///< the UUID this hash gives
    std::string headerUuid;   ///< the UUID the header holds
};

/// Hashes `path`. Throws std::runtime_error if it is not an OpenVDB file with the header above.
FileDigest digestVdbFile(const std::string& path);

/// True if `uuid` has the shape of one this writer derives from content (RFC 9562 version 8,
/// variant 10). OpenVDB's own UUIDs are random (version 4), so a file with a version-8 UUID
/// that its content does not give was changed after it was written: damaged or truncated.
bool looksContentDerived(const std::string& uuid);

/// Overwrites the header UUID of `path` with the one its content gives.
void stampContentUuid(const std::string& path);

}  // namespace vdb_detail
}  // namespace vdblight
