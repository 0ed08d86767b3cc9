// DDS writer for one uncompressed RGBA volume texture with the DX10 extension header
// (Microsoft "DDS_HEADER", "DDS_PIXELFORMAT" and "DDS_HEADER_DXT10" reference pages):
//   "DDS " | DDS_HEADER (124 bytes) | DDS_HEADER_DXT10 (20 bytes) | texels (z slices of rows).
#include "export_internal.h"

namespace vdblight::exporter {

namespace {
void put32(std::vector<uint8_t>& out, uint32_t v) {
    for (int b = 0; b < 4; ++b) out.push_back(uint8_t(v >> (8 * b)));
}

constexpr uint32_t DDSD_CAPS = 0x1, DDSD_HEIGHT = 0x2, DDSD_WIDTH = 0x4, DDSD_PITCH = 0x8,
                   DDSD_PIXELFORMAT = 0x1000, DDSD_DEPTH = 0x800000;
constexpr uint32_t DDPF_FOURCC = 0x4;
constexpr uint32_t DDSCAPS_TEXTURE = 0x1000;
constexpr uint32_t DDSCAPS2_VOLUME = 0x200000;
constexpr uint32_t kResourceDimensionTexture3D = 4;
}  // namespace

uint64_t writeDds(const std::string& path, const TextureImage& image) {
    const uint32_t texelBytes = uint32_t(4 * componentBytes(image.format));
    const uint64_t texels = uint64_t(image.dims[0]) * image.dims[1] * image.dims[2];
    std::vector<uint8_t> out = {'D', 'D', 'S', ' '};
    put32(out, 124);  // dwSize
    put32(out, DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | DDSD_PITCH | DDSD_PIXELFORMAT | DDSD_DEPTH);
    put32(out, uint32_t(image.dims[1]));               // dwHeight
    put32(out, uint32_t(image.dims[0]));               // dwWidth
    put32(out, uint32_t(image.dims[0]) * texelBytes);  // dwPitchOrLinearSize: bytes per row
    put32(out, uint32_t(image.dims[2]));               // dwDepth
    put32(out, 1);                                     // dwMipMapCount
    for (int i = 0; i < 11; ++i) put32(out, 0);        // dwReserved1
    put32(out, 32);                                    // ddspf.dwSize
    put32(out, DDPF_FOURCC);                           // ddspf.dwFlags
    out.insert(out.end(), {'D', 'X', '1', '0'});       // ddspf.dwFourCC
    for (int i = 0; i < 5; ++i) put32(out, 0);         // RGB bit count and masks (unused)
    put32(out, DDSCAPS_TEXTURE);                       // dwCaps
    put32(out, DDSCAPS2_VOLUME);                       // dwCaps2
    put32(out, 0);                                     // dwCaps3
    put32(out, 0);                                     // dwCaps4
    put32(out, 0);                                     // dwReserved2
    put32(out, dxgiFormatOf(image.format));            // dxgiFormat
    put32(out, kResourceDimensionTexture3D);           // resourceDimension
    put32(out, 0);                                     // miscFlag
    put32(out, 1);                                     // arraySize
    put32(out, 0);                                     // miscFlags2 (alpha mode unknown)
    const uint64_t dataOffset = out.size();  // 4 + 124 + 20 = 148
    const std::vector<uint8_t> data = encodeTexels(image.rgba, texels * 4, image.format);
    out.insert(out.end(), data.begin(), data.end());
    writeBytes(path, out);
    return dataOffset;
}

}  // namespace vdblight::exporter
