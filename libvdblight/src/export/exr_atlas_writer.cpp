// OpenEXR atlas of z slices: slice z is the tile at column z % columns, row z / columns,
// z = 0 at the top left; inside a tile, image row r holds texel row j = r (the same order
// as the raw data). Unused tiles are zero. The header carries the atlas geometry.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <half.h>

#include <cmath>

#include "export_internal.h"
#include "vdblight/core/errors.h"

namespace vdblight::exporter {

AtlasGrid atlasGrid(int depth) {
    AtlasGrid g;
    g.columns = std::max(1, int(std::ceil(std::sqrt(double(depth)))));
    g.rows = (depth + g.columns - 1) / g.columns;
    return g;
}

namespace {
template <typename T>
void writeAtlas(const std::string& path, const TextureImage& image, Imf::PixelType type) {
    const int nx = image.dims[0], ny = image.dims[1], nz = image.dims[2];
    const AtlasGrid g = atlasGrid(nz);
    const int width = g.columns * nx, height = g.rows * ny;
    std::vector<T> pixels(std::size_t(width) * height * 4, T(0.0f));
    for (int k = 0; k < nz; ++k) {
        const int x0 = (k % g.columns) * nx, y0 = (k / g.columns) * ny;
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const float* src = image.rgba + ((std::size_t(k) * ny + j) * nx + i) * 4;
                T* dst = pixels.data() + (std::size_t(y0 + j) * width + (x0 + i)) * 4;
                for (int c = 0; c < 4; ++c) dst[c] = T(src[c]);
            }
    }
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[4] = {"R", "G", "B", "A"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(type));
    header.insert("vdblightAtlasColumns", Imf::IntAttribute(g.columns));
    header.insert("vdblightAtlasRows", Imf::IntAttribute(g.rows));
    header.insert("vdblightSliceWidth", Imf::IntAttribute(nx));
    header.insert("vdblightSliceHeight", Imf::IntAttribute(ny));
    header.insert("vdblightSlices", Imf::IntAttribute(nz));
    header.insert("vdblightTexture", Imf::StringAttribute(image.name));
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(T) * 4, ys = xs * std::size_t(width);
    for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(type, reinterpret_cast<char*>(pixels.data() + c), xs, ys));
    try {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(height);
    } catch (const std::exception& e) {
        throw IoError("cannot write '" + path + "': " + e.what());
    }
}
}  // namespace

uint64_t writeExrAtlas(const std::string& path, const TextureImage& image) {
    switch (image.format) {
        case TexelFormat::Float16: writeAtlas<Imath::half>(path, image, Imf::HALF); break;
        case TexelFormat::Float32: writeAtlas<float>(path, image, Imf::FLOAT); break;
        case TexelFormat::Unorm8:  // depthTexelFormat keeps half / float for the atlas
            throw ValueError("texture '" + image.name + "': OpenEXR has no 8-bit channel type");
    }
    return 0;
}

}  // namespace vdblight::exporter
