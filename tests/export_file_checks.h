// Readers of the exported files written here from the specifications (KTX 2.0, Khronos Data
// Format 1.3, Microsoft DDS), shared by the export tests: little-endian fields and a checker
// for every header field the writers set.
#pragma once

#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <gtest/gtest.h>
#include <half.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace vdblight::test {

// The texel formats of the export (VkFormat for KTX2, DXGI_FORMAT for DDS).
constexpr uint32_t kVkRgba16Sfloat = 97, kVkRgba32Sfloat = 109, kVkRgba8Unorm = 37;
constexpr uint32_t kDxgiRgba16Float = 10, kDxgiRgba32Float = 2, kDxgiRgba8Unorm = 28;

/// Bytes of one component (the KTX2 header's typeSize) of an exported vkFormat.
inline uint32_t ktx2TypeSize(uint32_t vkFormat) {
    EXPECT_TRUE(vkFormat == kVkRgba16Sfloat || vkFormat == kVkRgba32Sfloat || vkFormat == kVkRgba8Unorm) << vkFormat;
    return vkFormat == kVkRgba16Sfloat ? 2 : (vkFormat == kVkRgba32Sfloat ? 4 : 1);
}
/// Bytes per RGBA texel of an exported DXGI format.
inline uint32_t ddsTexelSize(uint32_t dxgi) {
    EXPECT_TRUE(dxgi == kDxgiRgba16Float || dxgi == kDxgiRgba32Float || dxgi == kDxgiRgba8Unorm) << dxgi;
    return dxgi == kDxgiRgba16Float ? 8 : (dxgi == kDxgiRgba32Float ? 16 : 4);
}

/// The RGBA pixels of an EXR atlas page as floats, row-major over its data window (width x
/// height x 4).
inline std::vector<float> readExrRgba(Imf::InputFile& file) {
    const Imath::Box2i dw = file.header().dataWindow();
    const int width = dw.max.x - dw.min.x + 1, height = dw.max.y - dw.min.y + 1;
    std::vector<float> px(std::size_t(width) * height * 4);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data() + c), 16, 16 * std::size_t(width)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return px;
}

inline std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}
inline uint32_t u32(const std::vector<uint8_t>& b, std::size_t at) {
    return uint32_t(b.at(at)) | uint32_t(b.at(at + 1)) << 8 | uint32_t(b.at(at + 2)) << 16 | uint32_t(b.at(at + 3)) << 24;
}
inline uint64_t u64(const std::vector<uint8_t>& b, std::size_t at) { return u32(b, at) | uint64_t(u32(b, at + 4)) << 32; }
inline float f32(const std::vector<uint8_t>& b, std::size_t at) {
    const uint32_t bits = u32(b, at);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}
inline float f16(const std::vector<uint8_t>& b, std::size_t at) {
    Imath::half h;
    h.setBits(uint16_t(b.at(at) | b.at(at + 1) << 8));
    return float(h);
}

// KTX 2.0 checker, field by field (KTX 2.0 spec sections "File Structure", "Index", "Level
// Index", "Data Format Descriptor", "Key/Value Data", "KTXorientation"). Returns the
// level-0 data offset.
inline uint64_t checkKtx2(const std::vector<uint8_t>& b, uint32_t vkFormat, int nx, int ny, int nz) {
    const uint8_t id[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    EXPECT_EQ(std::memcmp(b.data(), id, 12), 0);
    const uint32_t typeSize = ktx2TypeSize(vkFormat), texelSize = 4 * typeSize;
    const bool unorm = vkFormat == kVkRgba8Unorm;
    EXPECT_EQ(u32(b, 12), vkFormat);
    EXPECT_EQ(u32(b, 16), typeSize);
    EXPECT_EQ(u32(b, 20), uint32_t(nx));
    EXPECT_EQ(u32(b, 24), uint32_t(ny));
    EXPECT_EQ(u32(b, 28), uint32_t(nz));  // pixelDepth > 0: 3-D
    EXPECT_EQ(u32(b, 32), 0u);            // layerCount
    EXPECT_EQ(u32(b, 36), 1u);            // faceCount
    EXPECT_EQ(u32(b, 40), 1u);            // levelCount
    EXPECT_EQ(u32(b, 44), 0u);            // supercompressionScheme
    const uint32_t dfdOffset = u32(b, 48), dfdLength = u32(b, 52), kvdOffset = u32(b, 56), kvdLength = u32(b, 60);
    EXPECT_EQ(u64(b, 64), 0u);  // sgdByteOffset
    EXPECT_EQ(u64(b, 72), 0u);  // sgdByteLength
    const uint64_t levelOffset = u64(b, 80), levelLength = u64(b, 88), uncompressed = u64(b, 96);
    EXPECT_EQ(dfdOffset, 104u);  // right after the one-entry level index
    // DFD: total size, then one basic block with four samples.
    EXPECT_EQ(u32(b, dfdOffset), dfdLength);
    EXPECT_EQ(dfdLength, 4u + 24u + 4u * 16u);
    EXPECT_EQ(kvdOffset, dfdOffset + dfdLength);  // dfdTotalSize == kvdByteOffset - dfdByteOffset
    const std::size_t blk = dfdOffset + 4;
    EXPECT_EQ(u32(b, blk) & 0x1FFFFu, 0u);       // vendorId KHRONOS
    EXPECT_EQ(u32(b, blk) >> 17, 0u);            // descriptorType BASICFORMAT
    EXPECT_EQ(u32(b, blk + 4) & 0xFFFFu, 2u);    // versionNumber
    EXPECT_EQ(u32(b, blk + 4) >> 16, 88u);       // descriptorBlockSize
    EXPECT_EQ(b[blk + 8], 1);                    // colorModel RGBSDA
    EXPECT_EQ(b[blk + 9], 1);                    // colorPrimaries BT709
    EXPECT_EQ(b[blk + 10], 1);                   // transferFunction LINEAR
    EXPECT_EQ(b[blk + 11], 0);                   // flags ALPHA_STRAIGHT
    EXPECT_EQ(u32(b, blk + 12), 0u);             // texelBlockDimension0..3: 1x1x1x1
    EXPECT_EQ(b[blk + 16], texelSize);           // bytesPlane0
    for (int p = 1; p < 8; ++p) EXPECT_EQ(b[blk + 16 + p], 0) << p;
    const int channel[4] = {0, 1, 2, 15};
    for (int s = 0; s < 4; ++s) {
        const std::size_t at = blk + 24 + 16 * s;
        EXPECT_EQ(u32(b, at) & 0xFFFFu, uint32_t(s) * typeSize * 8) << "bitOffset of sample " << s;
        EXPECT_EQ((u32(b, at) >> 16) & 0xFFu, typeSize * 8 - 1) << "bitLength of sample " << s;
        EXPECT_EQ(b[at + 3] & 0x0F, channel[s]) << "channelType of sample " << s;
        EXPECT_EQ(u32(b, at + 4), 0u);  // samplePosition
        if (unorm) {  // no qualifiers; sampleLower 0 and sampleUpper 255 (the integer that reads as 1.0)
            EXPECT_EQ(b[at + 3] & 0xF0, 0) << "qualifiers of unorm sample " << s;
            EXPECT_EQ(u32(b, at + 8), 0u);
            EXPECT_EQ(u32(b, at + 12), 255u);
        } else {
            EXPECT_EQ(b[at + 3] & 0xF0, 0x80 | 0x40) << "qualifiers FLOAT|SIGNED of sample " << s;
            EXPECT_EQ(f32(b, at + 8), -1.0f);
            EXPECT_EQ(f32(b, at + 12), 1.0f);
        }
    }
    // Key/value data: sorted keys, each entry padded to 4, lengths adding up to kvdByteLength.
    std::size_t at = kvdOffset;
    std::vector<std::string> keys;
    std::string orientation;
    while (at < kvdOffset + kvdLength) {
        const uint32_t len = u32(b, at);
        const std::string kv(reinterpret_cast<const char*>(&b[at + 4]), len);
        const std::string key = kv.substr(0, kv.find('\0'));
        if (key == "KTXorientation") orientation = kv.substr(key.size() + 1);
        keys.push_back(key);
        at += 4 + (len + 3) / 4 * 4;
    }
    EXPECT_EQ(at, std::size_t(kvdOffset) + kvdLength);
    EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
    EXPECT_EQ(orientation, std::string("ruo", 4));  // NUL-terminated, matches /^[rl][du][oi]$/
    // Level data: aligned to lcm(texel size, 4), zero padding before it, exact length, at the end.
    EXPECT_EQ(levelOffset % texelSize, 0u);
    EXPECT_GE(levelOffset, uint64_t(at));
    EXPECT_LT(levelOffset - at, texelSize);
    for (uint64_t p = at; p < levelOffset; ++p) EXPECT_EQ(b[p], 0);
    EXPECT_EQ(levelLength, uint64_t(nx) * ny * nz * texelSize);
    EXPECT_EQ(uncompressed, levelLength);
    EXPECT_EQ(b.size(), levelOffset + levelLength);
    return levelOffset;
}

// DDS checker (Microsoft: DDS_HEADER, DDS_PIXELFORMAT, DDS_HEADER_DXT10). Returns the data offset.
inline uint64_t checkDds(const std::vector<uint8_t>& b, uint32_t dxgi, int nx, int ny, int nz) {
    EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "DDS ");
    EXPECT_EQ(u32(b, 4), 124u);  // dwSize
    const uint32_t flags = u32(b, 8);
    for (uint32_t required : {0x1u, 0x2u, 0x4u, 0x1000u, 0x800000u})  // CAPS HEIGHT WIDTH PIXELFORMAT DEPTH
        EXPECT_EQ(flags & required, required) << std::hex << required;
    EXPECT_EQ(u32(b, 12), uint32_t(ny));
    EXPECT_EQ(u32(b, 16), uint32_t(nx));
    const uint32_t texelSize = ddsTexelSize(dxgi);
    if (flags & 0x8) {
        EXPECT_EQ(u32(b, 20), uint32_t(nx) * texelSize);  // pitch
    }
    EXPECT_EQ(u32(b, 24), uint32_t(nz));
    EXPECT_LE(u32(b, 28), 1u);  // mip count 0 or 1
    EXPECT_EQ(u32(b, 76), 32u);  // ddspf.dwSize
    EXPECT_EQ(u32(b, 80) & 0x4u, 0x4u);  // DDPF_FOURCC
    EXPECT_EQ(std::string(b.begin() + 84, b.begin() + 88), "DX10");
    EXPECT_EQ(u32(b, 108) & 0x1000u, 0x1000u);  // DDSCAPS_TEXTURE
    EXPECT_EQ(u32(b, 112) & 0x200000u, 0x200000u);  // DDSCAPS2_VOLUME
    EXPECT_EQ(u32(b, 128), dxgi);
    EXPECT_EQ(u32(b, 132), 4u);  // D3D10_RESOURCE_DIMENSION_TEXTURE3D
    EXPECT_EQ(u32(b, 136) & 0x4u, 0u);  // not a cube map
    EXPECT_EQ(u32(b, 140), 1u);  // arraySize
    EXPECT_EQ(b.size(), 148u + uint64_t(nx) * ny * nz * texelSize);
    return 148;
}
}  // namespace vdblight::test
