// Loads a `vdblight export` directory the way an engine does (docs/engines.md): manifest.json
// for the lattice, the sampler and each texture's format and data offset, then one OpenGL
// 3-D texture per KTX2 or DDS file made from the file's own bytes. The container headers are
// parsed here (no KTX library in Debian 12) and must agree with the manifest.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gl_compute.h"

namespace vdblight::gpu {

struct ManifestTexture {
    std::string name, file, format;  ///< format: rgba16_sfloat | rgba32_sfloat | rgba8_unorm
    std::size_t dataOffset = 0;
};

struct Manifest {
    std::string layout, container;  ///< container: ktx2 | dds
    std::array<int, 3> dims{};
    std::array<float, 3> boundsMin{}, boundsMax{}, texelSpacing{}, uvwScale{}, uvwBias{};
    std::vector<ManifestTexture> textures;  ///< in the manifest's order
    nlohmann::json root;                    ///< everything else (direct lights, depth, bins)
};

/// Reads DIR/manifest.json (throws std::runtime_error naming a missing or odd field).
Manifest readManifest(const std::string& dir);

/// One 3-D texture per manifest texture, by name, with the manifest's sampler (linear,
/// clamp-to-edge, no mipmaps): rgba16_sfloat -> GL_RGBA16F from GL_HALF_FLOAT texels,
/// rgba32_sfloat -> GL_RGBA32F, rgba8_unorm -> GL_RGBA8 (UNORM: samples as byte / 255).
/// Throws std::runtime_error if a file's header disagrees with the manifest.
std::map<std::string, std::unique_ptr<Texture3D>> loadTextures(const Manifest& manifest, const std::string& dir);

}  // namespace vdblight::gpu
