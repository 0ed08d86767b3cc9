// Sha256 (sha256.h) over OpenSSL's EVP digest interface. EVP_sha256 is FIPS 180-4 SHA-256, so
// content hashes are the same bytes the hand-written implementation gave before issue 30
// (reproducible_test pins one).
#include <openssl/evp.h>

#include <stdexcept>

#include "sha256.h"

namespace vdblight {
namespace vdb_detail {

struct Sha256::Context {
    EVP_MD_CTX* md = EVP_MD_CTX_new();
    ~Context() { EVP_MD_CTX_free(md); }
};

namespace {
[[noreturn]] void fail(const char* what) { throw std::runtime_error(std::string("SHA-256 (libcrypto): ") + what + " failed"); }
}  // namespace

Sha256::Sha256() : ctx_(std::make_unique<Context>()) {
    if (ctx_->md == nullptr || EVP_DigestInit_ex(ctx_->md, EVP_sha256(), nullptr) != 1) fail("EVP_DigestInit_ex");
}

Sha256::~Sha256() = default;

void Sha256::update(const void* data, std::size_t bytes) {
    if (bytes > 0 && EVP_DigestUpdate(ctx_->md, data, bytes) != 1) fail("EVP_DigestUpdate");
}

std::array<uint8_t, 32> Sha256::finish() {
    std::array<uint8_t, 32> digest{};
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(ctx_->md, digest.data(), &length) != 1 || length != digest.size()) fail("EVP_DigestFinal_ex");
    return digest;
}

std::string Sha256::hex(const std::array<uint8_t, 32>& digest) {
    static const char* kHex = "0123456789abcdef";
    std::string s;
    s.reserve(64);
    for (uint8_t b : digest) s += kHex[b >> 4], s += kHex[b & 15];
    return s;
}

}  // namespace vdb_detail
}  // namespace vdblight
