// What the per-format scans of declared_sizes.cpp share (internal): the running memory
// budget that refuses a file, and little-endian reads. One file per family of formats:
// declared_sizes_gltf.cpp, declared_sizes_fbx.cpp, declared_sizes_counts.cpp (COLLADA, OFF,
// STL, .x, OBJ).
#pragma once

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "declared_sizes.h"
#include "vdblight/core/errors.h"

namespace vdblight::declared_sizes {

constexpr std::uint64_t kMiB = 1024ull * 1024ull;
/// Assimp's ear-clipping triangulation is quadratic in the corners of a polygon.
constexpr std::size_t kMaxPolygonCorners = 4096;

inline std::string humanBytes(double bytes) {
    char text[64];
    if (bytes >= 1024.0 * kMiB) std::snprintf(text, sizeof text, "%.1f GB", bytes / (1024.0 * kMiB));
    else std::snprintf(text, sizeof text, "%.0f MB", bytes / double(kMiB));
    return text;
}

/// What the importer will allocate, summed as the scan goes; refuses past the bound.
class Budget {
public:
    Budget(const std::string& path, std::uint64_t fileBytes)
        : path_(path), fileBytes_(fileBytes), bound_(double(sceneMemoryBound(fileBytes))) {}

    [[noreturn]] void refuse(const std::string& reason) const {
        throw SceneError("scene file '" + path_ + "': " + reason);
    }
    /// Charges `bytes` for `what`; refuses once the total exceeds the bound.
    void charge(double bytes, const std::string& what) {
        used_ += bytes;
        if (!(used_ <= bound_))  // also catches NaN
            refuse(what + " would need about " + humanBytes(used_) + " of memory, over the loader's bound of " +
                   humanBytes(bound_) + " for a file of " + std::to_string(fileBytes_) + " bytes (docs/scene.md)");
    }
    double bound() const { return bound_; }
    std::uint64_t fileBytes() const { return fileBytes_; }

private:
    std::string path_;
    std::uint64_t fileBytes_;
    double bound_;
    double used_ = 0;
};

inline std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline uint32_t u32le(const std::string& d, std::size_t at) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= uint32_t(uint8_t(d[at + k])) << (8 * k);
    return v;
}
inline uint64_t u64le(const std::string& d, std::size_t at) {
    return uint64_t(u32le(d, at)) | (uint64_t(u32le(d, at + 4)) << 32);
}

// The scans. Each charges what the importer would allocate and refuses a declared size that
// points past the data (Budget::refuse throws SceneError).

/// glTF 2.0, text (.gltf, external and data: buffers) or binary (.glb).
void checkGltf(const std::string& path, bool binary, Budget& budget);
/// Binary FBX: every record and array property.
void checkFbxBinary(const std::string& d, Budget& budget);
/// ASCII FBX: every `*N` array count.
void checkFbxAscii(const std::string& d, Budget& budget);
void checkCollada(const std::string& d, Budget& budget);
void checkOff(const std::string& d, Budget& budget);
void checkStl(const std::string& d, Budget& budget);
void checkX(const std::string& d, Budget& budget);
void checkObj(const std::string& path, Budget& budget);

}  // namespace vdblight::declared_sizes
