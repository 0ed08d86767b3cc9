// See texture_mean.h. PNG decoding through libpng (libpng-dev), row by row: its transforms
// bring every kind to 8- or 16-bit RGB samples as stored (palette looked up, grey copied to
// the three channels, alpha dropped, no gamma applied), and the sRGB decode and the sum are
// ours. libpng reports errors by longjmp; the one function that calls setjmp (sumRows)
// creates no C++ object after it, so the jump skips no destructor.
#include "texture_mean.h"

#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace vdblight {

namespace {

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

/// The PNG bytes libpng reads from, and where an error message goes.
struct Source {
    const uint8_t* data;
    std::size_t size;
    std::size_t at;
    char error[160];
};

void readBytes(png_structp png, png_bytep out, std::size_t n) {
    Source* s = static_cast<Source*>(png_get_io_ptr(png));
    if (n > s->size - s->at) png_error(png, "PNG data ends early");
    std::memcpy(out, s->data + s->at, n);
    s->at += n;
}
void onError(png_structp png, png_const_charp message) {
    std::snprintf(static_cast<Source*>(png_get_error_ptr(png))->error, sizeof(Source::error), "%s", message);
    png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}  // e.g. a bad ancillary chunk, which libpng skips

/// Adds the linear RGB of `width` pixels of 8- or 16-bit (big-endian) RGB samples to `sum`.
void addRow(const uint8_t* row, png_uint_32 width, int depth, const double* lut8, double sum[3]) {
    for (png_uint_32 x = 0; x < width; ++x)
        for (int k = 0; k < 3; ++k) {
            const std::size_t i = 3 * std::size_t(x) + std::size_t(k);
            sum[k] += depth == 8 ? lut8[row[i]] : srgbToLinear((row[2 * i] << 8 | row[2 * i + 1]) / 65535.0);
        }
}

/// Reads the image and sums its pixels in `sum`, their count in `pixels`. An interlaced image
/// is read pass by pass, each pass's pixels once (libpng skips the passes without pixels, as
/// PNG_PASS_COLS / PNG_PASS_ROWS count them). False (the message in the Source) on an error.
bool sumRows(png_structp png, png_infop info, std::vector<uint8_t>& row, const double* lut8, double sum[3],
             double& pixels) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_info(png, info);
    png_uint_32 width = 0, height = 0;
    int depth = 0, colourType = 0, interlace = 0;
    png_get_IHDR(png, info, &width, &height, &depth, &colourType, &interlace, nullptr, nullptr);
    if (uint64_t(width) * height > (uint64_t(1) << 28)) png_error(png, "PNG of more than 2^28 pixels");
    if (colourType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if ((colourType & PNG_COLOR_MASK_COLOR) == 0) {
        if (depth < 8) png_set_expand_gray_1_2_4_to_8(png);
        png_set_gray_to_rgb(png);
    }
    png_set_strip_alpha(png);
    png_read_update_info(png, info);
    const int outDepth = png_get_bit_depth(png, info);
    if (png_get_channels(png, info) != 3 || (outDepth != 8 && outDepth != 16)) png_error(png, "unexpected PNG transform");
    row.resize(png_get_rowbytes(png, info));
    const int passes = interlace == PNG_INTERLACE_ADAM7 ? PNG_INTERLACE_ADAM7_PASSES : 1;
    for (int pass = 0; pass < passes; ++pass) {
        const png_uint_32 cols = passes == 1 ? width : PNG_PASS_COLS(width, pass);
        const png_uint_32 rows = passes == 1 ? height : PNG_PASS_ROWS(height, pass);
        if (cols == 0) continue;
        for (png_uint_32 r = 0; r < rows; ++r) {
            png_read_row(png, row.data(), nullptr);
            addRow(row.data(), cols, outDepth, lut8, sum);
        }
        pixels += double(cols) * double(rows);
    }
    return true;
}

}  // namespace

bool pngMeanLinear(const uint8_t* data, std::size_t size, Rgb& mean, std::string& why) {
    if (size < 8 || png_sig_cmp(data, 0, 8) != 0) { why = "not a PNG file"; return false; }
    Source source{data, size, 0, ""};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &source, onError, onWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (info == nullptr) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        why = "libpng could not start";
        return false;
    }
    png_set_read_fn(png, &source, readBytes);
    double lut8[256];
    for (int i = 0; i < 256; ++i) lut8[i] = srgbToLinear(i / 255.0);
    std::vector<uint8_t> row;
    double sum[3] = {0, 0, 0}, pixels = 0;
    const bool ok = sumRows(png, info, row, lut8, sum, pixels);
    png_destroy_read_struct(&png, &info, nullptr);
    if (!ok) { why = source.error; return false; }
    mean = Rgb(float(sum[0] / pixels), float(sum[1] / pixels), float(sum[2] / pixels));
    return true;
}

}  // namespace vdblight
