// A minimal PNG encoder (PNG specification, 2nd edition): signature, IHDR (8-bit RGB),
// one IDAT with the zlib stream of the scanlines (filter type 0 each), IEND. CRCs and the
// deflate stream come from zlib.
#include <zlib.h>

#include "vdblight/atomic_file.h"
#include "vdblight/errors.h"
#include "vdblight/slice.h"

namespace vdblight {

namespace {
void putU32(std::vector<uint8_t>& out, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t(v >> s));
}

void chunk(std::vector<uint8_t>& out, const char type[4], const std::vector<uint8_t>& data) {
    putU32(out, uint32_t(data.size()));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    const uLong crc = crc32(0L, out.data() + start, uInt(out.size() - start));
    putU32(out, uint32_t(crc));
}
}  // namespace

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    if (width < 1 || height < 1 || rgb.size() != std::size_t(width) * height * 3)
        throw ValueError("PNG image data does not match its size");
    std::vector<uint8_t> raw;
    raw.reserve((std::size_t(width) * 3 + 1) * height);
    for (int r = 0; r < height; ++r) {
        raw.push_back(0);  // filter type None
        const uint8_t* row = rgb.data() + std::size_t(r) * width * 3;
        raw.insert(raw.end(), row, row + std::size_t(width) * 3);
    }
    uLongf packedSize = compressBound(uLong(raw.size()));
    std::vector<uint8_t> packed(packedSize);
    if (compress2(packed.data(), &packedSize, raw.data(), uLong(raw.size()), 6) != Z_OK)
        throw IoError("cannot compress the PNG data of '" + path + "'");
    packed.resize(packedSize);

    std::vector<uint8_t> file = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<uint8_t> ihdr;
    putU32(ihdr, uint32_t(width));
    putU32(ihdr, uint32_t(height));
    ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // bit depth 8, colour type RGB, deflate, filter 0, no interlace
    chunk(file, "IHDR", ihdr);
    chunk(file, "IDAT", packed);
    chunk(file, "IEND", {});

    writeFileAtomically(path, std::string(file.begin(), file.end()));
}

}  // namespace vdblight
