// Texel formats of the exported textures and their little-endian encoding. The lighting
// textures are half or float (--half / --float); the depth textures are 8-bit unorm where
// the container has an 8-bit type (depth moments are multiples of 1/255, depth_moments.h).
#include <half.h>

#include <cmath>
#include <cstring>

#include "export_internal.h"

namespace vdblight::exporter {

namespace {
void putLe(std::vector<uint8_t>& out, uint32_t v, int bytes) {
    for (int b = 0; b < bytes; ++b) out.push_back(uint8_t(v >> (8 * b)));
}
}  // namespace

int componentBytes(TexelFormat f) {
    switch (f) {
        case TexelFormat::Float16: return 2;
        case TexelFormat::Float32: return 4;
        case TexelFormat::Unorm8: return 1;
    }
    return 0;
}

const char* texelFormatName(TexelFormat f) {
    switch (f) {
        case TexelFormat::Float16: return "rgba16_sfloat";
        case TexelFormat::Float32: return "rgba32_sfloat";
        case TexelFormat::Unorm8: return "rgba8_unorm";
    }
    return "?";
}

uint32_t vkFormatOf(TexelFormat f) {
    switch (f) {
        case TexelFormat::Float16: return kVkR16G16B16A16Sfloat;
        case TexelFormat::Float32: return kVkR32G32B32A32Sfloat;
        case TexelFormat::Unorm8: return kVkR8G8B8A8Unorm;
    }
    return 0;
}

uint32_t dxgiFormatOf(TexelFormat f) {
    switch (f) {
        case TexelFormat::Float16: return kDxgiR16G16B16A16Float;
        case TexelFormat::Float32: return kDxgiR32G32B32A32Float;
        case TexelFormat::Unorm8: return kDxgiR8G8B8A8Unorm;
    }
    return 0;
}

TexelFormat lightingTexelFormat(bool half) { return half ? TexelFormat::Float16 : TexelFormat::Float32; }

TexelFormat depthTexelFormat(TextureFormat container, bool half) {
    // OpenEXR stores half, float or 32-bit uint channels only: no 8-bit type.
    return container == TextureFormat::ExrAtlas ? lightingTexelFormat(half) : TexelFormat::Unorm8;
}

uint8_t unorm8(float v) {
    const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // NaN -> 0
    return uint8_t(std::nearbyint(double(c) * 255.0));
}

std::vector<uint8_t> encodeTexels(const float* values, std::size_t count, TexelFormat format) {
    std::vector<uint8_t> out;
    out.reserve(count * std::size_t(componentBytes(format)));
    for (std::size_t i = 0; i < count; ++i) {
        switch (format) {
            case TexelFormat::Float16: putLe(out, Imath::half(values[i]).bits(), 2); break;
            case TexelFormat::Float32: {
                uint32_t bits;
                std::memcpy(&bits, &values[i], 4);
                putLe(out, bits, 4);
                break;
            }
            case TexelFormat::Unorm8: out.push_back(unorm8(values[i])); break;
        }
    }
    return out;
}

}  // namespace vdblight::exporter
