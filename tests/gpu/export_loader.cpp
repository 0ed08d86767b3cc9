#include "export_loader.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace vdblight::gpu {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open " + path);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

const nlohmann::json& field(const nlohmann::json& object, const std::string& key) {
    const auto it = object.find(key);
    if (it == object.end()) fail("manifest.json has no '" + key + "'");
    return *it;
}

std::string text(const nlohmann::json& object, const std::string& key) {
    const nlohmann::json& v = field(object, key);
    if (!v.is_string()) fail("manifest.json: '" + key + "' is not a string");
    return v.get<std::string>();
}

template <class T>
std::array<T, 3> triple(const nlohmann::json& object, const std::string& key) {
    const nlohmann::json& v = field(object, key);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        fail("manifest.json: '" + key + "' is not a triple");
    return {T(v[0].get<double>()), T(v[1].get<double>()), T(v[2].get<double>())};
}

uint32_t u32(const std::string& bytes, std::size_t at) {
    uint32_t v = 0;
    if (at + 4 > bytes.size()) fail("file too short for its header");
    std::memcpy(&v, bytes.data() + at, 4);  // little-endian files on a little-endian machine
    return v;
}

uint64_t u64(const std::string& bytes, std::size_t at) {
    uint64_t v = 0;
    if (at + 8 > bytes.size()) fail("file too short for its header");
    std::memcpy(&v, bytes.data() + at, 8);
    return v;
}

struct GlFormat {
    GLenum internal, type;
    std::size_t texelBytes;
    uint32_t vkFormat, dxgiFormat;
};

GlFormat glFormatOf(const std::string& format) {
    if (format == "rgba16_sfloat") return {GL_RGBA16F, GL_HALF_FLOAT, 8, 97, 10};
    if (format == "rgba32_sfloat") return {GL_RGBA32F, GL_FLOAT, 16, 109, 2};
    if (format == "rgba8_unorm") return {GL_RGBA8, GL_UNSIGNED_BYTE, 4, 37, 28};
    fail("unknown texel format '" + format + "'");
}

// The header of a KTX2 or DDS file must name the manifest's format, size and data offset.
void checkHeader(const std::string& bytes, const Manifest& m, const ManifestTexture& t, const GlFormat& f) {
    uint32_t width = 0, height = 0, depth = 0;
    std::size_t offset = 0;
    if (m.container == "ktx2") {
        static const unsigned char id[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
        if (bytes.size() < 104 || std::memcmp(bytes.data(), id, 12) != 0) fail(t.file + ": not a KTX2 file");
        if (u32(bytes, 12) != f.vkFormat) fail(t.file + ": vkFormat " + std::to_string(u32(bytes, 12)) + ", manifest says " + t.format);
        width = u32(bytes, 20), height = u32(bytes, 24), depth = u32(bytes, 28);
        if (u32(bytes, 40) > 1 || u32(bytes, 44) != 0) fail(t.file + ": more than one level, or supercompressed");
        offset = std::size_t(u64(bytes, 80));  // level 0's byteOffset in the level index
        if (u64(bytes, 88) != uint64_t(m.dims[0]) * m.dims[1] * m.dims[2] * f.texelBytes) fail(t.file + ": level 0 size");
    } else if (m.container == "dds") {
        if (bytes.size() < 148 || bytes.compare(0, 4, "DDS ") != 0 || bytes.compare(84, 4, "DX10") != 0)
            fail(t.file + ": not a DDS file with a DX10 header");
        if (u32(bytes, 128) != f.dxgiFormat) fail(t.file + ": DXGI format " + std::to_string(u32(bytes, 128)) + ", manifest says " + t.format);
        if (u32(bytes, 132) != 4) fail(t.file + ": not TEXTURE3D");
        height = u32(bytes, 12), width = u32(bytes, 16), depth = u32(bytes, 24);
        offset = 148;  // magic + DDS_HEADER + DDS_HEADER_DXT10
    } else {
        fail("format '" + m.container + "': the GPU check reads ktx2 and dds exports");
    }
    if (int(width) != m.dims[0] || int(height) != m.dims[1] || int(depth) != m.dims[2]) fail(t.file + ": size differs from dims");
    if (offset != t.dataOffset) fail(t.file + ": texels at " + std::to_string(offset) + ", manifest data_offset " + std::to_string(t.dataOffset));
    if (offset + std::size_t(width) * height * depth * f.texelBytes > bytes.size()) fail(t.file + ": truncated");
}

}  // namespace

Manifest readManifest(const std::string& dir) {
    Manifest m;
    m.root = nlohmann::json::parse(readFile(dir + "/manifest.json"));
    m.layout = text(m.root, "layout");
    m.container = text(m.root, "format");
    m.dims = triple<int>(m.root, "dims");
    m.boundsMin = triple<float>(m.root, "bounds_min");
    m.boundsMax = triple<float>(m.root, "bounds_max");
    m.texelSpacing = triple<float>(m.root, "texel_spacing");
    m.uvwScale = triple<float>(m.root, "uvw_scale");
    m.uvwBias = triple<float>(m.root, "uvw_bias");
    const nlohmann::json& sampler = field(m.root, "sampler");
    if (text(sampler, "filter") != "linear" || text(sampler, "address") != "clamp-to-edge" ||
        field(sampler, "mipmaps") != false)
        fail("manifest.json: a sampler other than linear, clamp-to-edge, no mipmaps");
    for (const nlohmann::json& t : field(m.root, "textures"))
        m.textures.push_back({text(t, "name"), text(t, "file"), text(t, "format"),
                              field(t, "data_offset").get<std::size_t>()});
    return m;
}

std::map<std::string, std::unique_ptr<Texture3D>> loadTextures(const Manifest& m, const std::string& dir) {
    std::map<std::string, std::unique_ptr<Texture3D>> out;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (const ManifestTexture& t : m.textures) {
        const GlFormat f = glFormatOf(t.format);
        const std::string bytes = readFile(dir + "/" + t.file);
        checkHeader(bytes, m, t, f);
        auto texture = std::make_unique<Texture3D>();
        glBindTexture(GL_TEXTURE_3D, texture->id);
        glTexImage3D(GL_TEXTURE_3D, 0, GLint(f.internal), m.dims[0], m.dims[1], m.dims[2], 0, GL_RGBA, f.type,
                     bytes.data() + t.dataOffset);
        // The manifest's sampler: linear, clamp-to-edge, one level (no mipmaps).
        glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
        for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
            glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
        checkGl(("uploading " + t.file).c_str());
        out[t.name] = std::move(texture);
    }
    return out;
}

}  // namespace vdblight::gpu
