// SHA-256 for the content hash of .vdb files (vdb_io.h: fileContentHash) and the tile
// parameters' hash, computed by OpenSSL's libcrypto (EVP_sha256) rather than code of our own.
// A cryptographic hash rather than the scene's FNV-1a: a farm compares tiles and merged
// worlds by this hash, so two different files must not collide by accident. Internal: the
// header names no OpenSSL type, so only the volume module links libcrypto.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace vdblight {
namespace vdb_detail {

/// An incremental SHA-256: update() with the bytes in order, then finish() once.
class Sha256 {
public:
    Sha256();  ///< throws std::runtime_error if libcrypto cannot start a digest
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;

    void update(const void* data, std::size_t bytes);
    /// The 32-byte digest; the object must not be updated afterwards.
    std::array<uint8_t, 32> finish();
    static std::string hex(const std::array<uint8_t, 32>& digest);

private:
    struct Context;  // OpenSSL's EVP_MD_CTX, kept out of this header
    std::unique_ptr<Context> ctx_;
};

}  // namespace vdb_detail
}  // namespace vdblight
