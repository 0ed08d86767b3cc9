// SHA-256 (FIPS 180-4), for the content hash of .vdb files (vdb_io.h: fileContentHash).
// A cryptographic hash rather than the scene's FNV-1a: a farm compares tiles and merged
// worlds by this hash, so two different files must not collide by accident. Internal.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace vdblight {
namespace vdb_detail {

class Sha256 {
public:
    Sha256();
    void update(const void* data, std::size_t bytes);
    /// The 32-byte digest; the object must not be updated afterwards.
    std::array<uint8_t, 32> finish();
    static std::string hex(const std::array<uint8_t, 32>& digest);

private:
    void block(const uint8_t* p);
    uint32_t h_[8];
    uint8_t buffer_[64];
    std::size_t buffered_ = 0;
    uint64_t total_ = 0;
};

}  // namespace vdb_detail
}  // namespace vdblight
