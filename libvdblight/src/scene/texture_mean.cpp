// See texture_mean.h. A minimal PNG reader (ISO/IEC 15948): chunks, zlib inflate of the IDAT
// stream one row at a time, the five row filters, sRGB to linear, a running double sum.
#include "texture_mean.h"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace vdblight {

namespace {

uint32_t be32(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

struct Image {
    uint32_t width = 0, height = 0;
    int depth = 0, colourType = -1, channels = 0;
    std::size_t bpp = 0, rowBytes = 0;  ///< bytes per pixel (at least 1), bytes per row
    std::vector<Rgb> palette;
};

/// Sum of the linear RGB of one unfiltered row.
void addRow(const Image& im, const uint8_t* row, const double* lut8, double sum[3]) {
    for (uint32_t x = 0; x < im.width; ++x) {
        const uint8_t* px = row + std::size_t(x) * im.bpp;
        double rgb[3];
        if (im.colourType == 3) {
            const std::size_t i = px[0];
            const Rgb c = i < im.palette.size() ? im.palette[i] : Rgb(0, 0, 0);
            rgb[0] = c.x; rgb[1] = c.y; rgb[2] = c.z;
        } else {
            double v[4];
            for (int k = 0; k < std::min(im.channels, 3); ++k)
                v[k] = im.depth == 8 ? lut8[px[k]] : srgbToLinear((px[2 * k] << 8 | px[2 * k + 1]) / 65535.0);
            const bool grey = im.colourType == 0 || im.colourType == 4;
            for (int k = 0; k < 3; ++k) rgb[k] = grey ? v[0] : v[k];
        }
        for (int k = 0; k < 3; ++k) sum[k] += rgb[k];
    }
}

}  // namespace

bool pngMeanLinear(const uint8_t* data, std::size_t size, Rgb& mean, std::string& why) {
    static const uint8_t kSignature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    if (size < 8 || std::memcmp(data, kSignature, 8) != 0) { why = "not a PNG file"; return false; }
    double lut8[256];
    for (int i = 0; i < 256; ++i) lut8[i] = srgbToLinear(i / 255.0);

    Image im;
    z_stream z{};
    if (inflateInit(&z) != Z_OK) { why = "zlib failed"; return false; }
    std::vector<uint8_t> row, prev;
    std::size_t filled = 0;
    uint32_t rows = 0;
    double sum[3] = {0, 0, 0};
    bool ok = true, ended = false;
    auto fail = [&](const char* w) { why = w; ok = false; };

    for (std::size_t at = 8; ok && !ended && at + 12 <= size;) {
        const uint32_t length = be32(data + at);
        const uint8_t* type = data + at + 4;
        const uint8_t* body = data + at + 8;
        if (length > size - at - 12) { fail("a chunk runs past the end of the file"); break; }
        at += 12 + std::size_t(length);
        if (std::memcmp(type, "IHDR", 4) == 0) {
            if (length != 13) { fail("bad IHDR"); break; }
            im.width = be32(body); im.height = be32(body + 4);
            im.depth = body[8]; im.colourType = body[9];
            static const int kChannels[7] = {1, 0, 3, 1, 2, 0, 4};
            im.channels = im.colourType <= 6 ? kChannels[im.colourType] : 0;
            if (im.channels == 0 || body[10] != 0 || body[11] != 0) { fail("unknown PNG colour type or method"); break; }
            if (body[12] != 0) { fail("interlaced PNG (not read)"); break; }
            if (!(im.depth == 8 || (im.depth == 16 && im.colourType != 3))) { fail("PNG bit depth other than 8 or 16 (not read)"); break; }
            if (im.width == 0 || im.height == 0 || uint64_t(im.width) * im.height > (uint64_t(1) << 28)) {
                fail("PNG of no or more than 2^28 pixels"); break;
            }
            im.bpp = std::size_t(im.channels) * std::size_t(im.depth / 8);
            im.rowBytes = std::size_t(im.width) * im.bpp;
            row.assign(1 + im.rowBytes, 0);
            prev.assign(1 + im.rowBytes, 0);
        } else if (std::memcmp(type, "PLTE", 4) == 0) {
            for (uint32_t i = 0; i + 3 <= length; i += 3)
                im.palette.emplace_back(float(lut8[body[i]]), float(lut8[body[i + 1]]), float(lut8[body[i + 2]]));
        } else if (std::memcmp(type, "IDAT", 4) == 0) {
            if (row.empty()) { fail("IDAT before IHDR"); break; }
            z.next_in = const_cast<Bytef*>(body);
            z.avail_in = length;
            while (ok && z.avail_in > 0 && rows < im.height) {
                z.next_out = row.data() + filled;
                z.avail_out = uInt(row.size() - filled);
                const int r = inflate(&z, Z_NO_FLUSH);
                if (r != Z_OK && r != Z_STREAM_END) { fail("corrupt PNG data"); break; }
                filled = row.size() - z.avail_out;
                if (filled == row.size()) {  // a whole row: unfilter against the previous one
                    const std::size_t bpp = im.bpp;
                    uint8_t* cur = row.data() + 1;
                    const uint8_t* up = prev.data() + 1;
                    const int filter = row[0];
                    if (filter > 4) { fail("unknown PNG row filter"); break; }
                    for (std::size_t i = 0; i < im.rowBytes; ++i) {
                        const int a = i >= bpp ? cur[i - bpp] : 0, b = up[i], c = i >= bpp ? up[i - bpp] : 0;
                        const int pred = filter == 1 ? a : filter == 2 ? b : filter == 3 ? (a + b) / 2
                                         : filter == 4 ? paeth(a, b, c) : 0;
                        cur[i] = uint8_t(cur[i] + pred);
                    }
                    addRow(im, cur, lut8, sum);
                    std::swap(row, prev);
                    filled = 0;
                    ++rows;
                }
                if (r == Z_STREAM_END) break;
            }
        } else if (std::memcmp(type, "IEND", 4) == 0) {
            ended = true;
        }
    }
    inflateEnd(&z);
    if (!ok) return false;
    if (im.colourType < 0) { why = "no IHDR"; return false; }
    if (rows < im.height) { why = "PNG image data ends early"; return false; }
    const double n = double(im.width) * double(im.height);
    mean = Rgb(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
    return true;
}

}  // namespace vdblight
