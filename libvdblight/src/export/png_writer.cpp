// writePng (slice.h) through libpng's simplified write API (png_image, libpng 1.6): it encodes
// to memory and reports errors in the image's message instead of libpng's longjmp, so no C++
// exception crosses C code. The buffer is then written atomically like every other output.
#include <png.h>

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/slice.h"

namespace vdblight {

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    if (width < 1 || height < 1 || rgb.size() != std::size_t(width) * height * 3)
        throw ValueError("PNG image data does not match its size");
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(width);
    image.height = png_uint_32(height);
    image.format = PNG_FORMAT_RGB;  // 8-bit sRGB values, as toneMapSlice makes them
    // First call: the encoded size; second: the bytes.
    png_alloc_size_t bytes = 0;
    if (!png_image_write_to_memory(&image, nullptr, &bytes, 0, rgb.data(), 0, nullptr))
        throw IoError("cannot encode the PNG '" + path + "': " + image.message);
    std::string file(bytes, '\0');
    if (!png_image_write_to_memory(&image, file.data(), &bytes, 0, rgb.data(), 0, nullptr))
        throw IoError("cannot encode the PNG '" + path + "': " + image.message);
    file.resize(bytes);
    writeFileAtomically(path, file);
}

}  // namespace vdblight
