// Plain file writing and the `raw` format (no header; texels as encodeTexels gives them).
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "export_internal.h"
#include "vdblight/core/errors.h"

namespace vdblight::exporter {

const char* textureExtension(TextureFormat f) {
    switch (f) {
        case TextureFormat::Ktx2: return ".ktx2";
        case TextureFormat::Dds: return ".dds";
        case TextureFormat::ExrAtlas: return ".exr";
        case TextureFormat::Raw: return ".raw";
    }
    return "";
}

void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw IoError("cannot write '" + path + "': " + std::strerror(errno));
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    if (!ok || !closed) throw IoError("cannot write '" + path + "': disk full or I/O error");
}

uint64_t writeRaw(const std::string& path, const TextureImage& image) {
    const std::size_t texels = std::size_t(image.dims[0]) * image.dims[1] * image.dims[2];
    writeBytes(path, encodeTexels(image.rgba, texels * 4, image.format));
    return 0;
}

}  // namespace vdblight::exporter
