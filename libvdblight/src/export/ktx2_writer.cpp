// KTX 2.0 writer for one uncompressed RGBA 3-D texture, one mip level (KTX 2.0
// specification, Khronos; the Data Format Descriptor after the Khronos Data Format
// Specification 1.3, basic descriptor block as KTX-Software's dfdutils writes it for
// R16G16B16A16_SFLOAT, R32G32B32A32_SFLOAT and R8G8B8A8_UNORM).
//
// File layout written here (offsets in bytes):
//   0   identifier (12)         48  index (32)          80  level index (24)
//   104 DFD: dfdTotalSize + basic block with 4 samples (4 + 24 + 4 * 16 = 92)
//   196 key/value data: KTXorientation "ruo", KTXwriter (sorted by key, each padded to 4)
//   ... zero padding up to a multiple of lcm(texel size, 4), then the level's texels.
#include "export_internal.h"

namespace vdblight::exporter {

namespace {
void put32(std::vector<uint8_t>& out, uint32_t v) {
    for (int b = 0; b < 4; ++b) out.push_back(uint8_t(v >> (8 * b)));
}
void put64(std::vector<uint8_t>& out, uint64_t v) {
    for (int b = 0; b < 8; ++b) out.push_back(uint8_t(v >> (8 * b)));
}
void padTo(std::vector<uint8_t>& out, std::size_t alignment) {
    while (out.size() % alignment != 0) out.push_back(0);
}

// Basic data format descriptor, little-endian, one sample per channel. A float sample is
// FLOAT|SIGNED with sampleLower -1.0f, sampleUpper 1.0f; an unorm sample has no qualifier
// bits, sampleLower 0 and sampleUpper 2^bits - 1 (255: the integer that reads as 1.0).
std::vector<uint8_t> dataFormatDescriptor(TexelFormat format) {
    const uint32_t samples = 4;
    const uint32_t blockSize = 24 + 16 * samples;
    const uint32_t bytesPerComponent = uint32_t(componentBytes(format));
    const bool unorm = format == TexelFormat::Unorm8;
    std::vector<uint8_t> d;
    put32(d, 4 + blockSize);                       // dfdTotalSize
    put32(d, 0);                                   // vendorId = KHRONOS (0), descriptorType = BASICFORMAT (0)
    put32(d, 2u | (blockSize << 16));              // versionNumber = 2, descriptorBlockSize
    put32(d, 1u | (1u << 8) | (1u << 16) | (0u << 24));  // model RGBSDA, primaries BT709, transfer LINEAR, flags 0
    put32(d, 0);                                   // texelBlockDimension0..3 = 0 (1x1x1x1)
    put32(d, 4 * bytesPerComponent);               // bytesPlane0 = texel size, bytesPlane1..3 = 0
    put32(d, 0);                                   // bytesPlane4..7 = 0
    const uint32_t channelIds[4] = {0, 1, 2, 15};  // RED, GREEN, BLUE, ALPHA
    const uint32_t qualifiers = unorm ? 0 : 0x80 | 0x40;  // none, or FLOAT | SIGNED
    const uint32_t bits = 8 * bytesPerComponent;
    for (uint32_t s = 0; s < samples; ++s) {
        put32(d, (s * bits) | ((bits - 1) << 16) | ((qualifiers | channelIds[s]) << 24));
        put32(d, 0);                                 // samplePosition0..3
        put32(d, unorm ? 0 : 0xBF800000);            // sampleLower: 0, or -1.0f
        put32(d, unorm ? 255 : 0x3F800000);          // sampleUpper: 255, or 1.0f
    }
    return d;
}

void putKeyValue(std::vector<uint8_t>& out, const std::string& key, const std::string& value) {
    put32(out, uint32_t(key.size() + 1 + value.size() + 1));
    out.insert(out.end(), key.begin(), key.end());
    out.push_back(0);
    out.insert(out.end(), value.begin(), value.end());
    out.push_back(0);
    padTo(out, 4);
}
}  // namespace

uint64_t writeKtx2(const std::string& path, const TextureImage& image) {
    const int typeSize = componentBytes(image.format);
    const uint32_t texelBytes = uint32_t(4 * typeSize);
    const uint64_t texels = uint64_t(image.dims[0]) * image.dims[1] * image.dims[2];
    const uint64_t levelBytes = texels * texelBytes;

    const std::vector<uint8_t> dfd = dataFormatDescriptor(image.format);
    std::vector<uint8_t> kvd;
    putKeyValue(kvd, "KTXorientation", "ruo");  // x right, y up, z towards the viewer
    putKeyValue(kvd, "KTXwriter", "vdblight 0.1.0");

    const uint32_t dfdOffset = 12 + 36 + 32 + 24;
    const uint32_t kvdOffset = dfdOffset + uint32_t(dfd.size());
    const uint64_t kvdEnd = kvdOffset + kvd.size();
    const uint64_t alignment = texelBytes;  // lcm(texel size, 4) = texel size for 4, 8 or 16 bytes
    const uint64_t levelOffset = (kvdEnd + alignment - 1) / alignment * alignment;

    static const uint8_t identifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    std::vector<uint8_t> out(identifier, identifier + 12);
    put32(out, vkFormatOf(image.format));
    put32(out, uint32_t(typeSize));        // typeSize: bytes of one component
    put32(out, uint32_t(image.dims[0]));
    put32(out, uint32_t(image.dims[1]));
    put32(out, uint32_t(image.dims[2]));   // pixelDepth > 0: a 3-D texture
    put32(out, 0);                         // layerCount: not an array
    put32(out, 1);                         // faceCount
    put32(out, 1);                         // levelCount
    put32(out, 0);                         // supercompressionScheme: none
    put32(out, dfdOffset);
    put32(out, uint32_t(dfd.size()));
    put32(out, kvdOffset);
    put32(out, uint32_t(kvd.size()));
    put64(out, 0);  // sgdByteOffset
    put64(out, 0);  // sgdByteLength
    put64(out, levelOffset);
    put64(out, levelBytes);
    put64(out, levelBytes);  // uncompressedByteLength
    out.insert(out.end(), dfd.begin(), dfd.end());
    out.insert(out.end(), kvd.begin(), kvd.end());
    padTo(out, std::size_t(alignment));  // mipPadding
    const std::vector<uint8_t> data = encodeTexels(image.rgba, texels * 4, image.format);
    out.insert(out.end(), data.begin(), data.end());
    writeBytes(path, out);
    return levelOffset;
}

}  // namespace vdblight::exporter
