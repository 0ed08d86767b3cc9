// Slices: irradiance on an axis-aligned plane through a volume, sampled through
// IrradianceQuery, written as a linear EXR or a tone-mapped PNG (slice.h).
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <ImfDoubleAttribute.h>
#include <ImfVecAttribute.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "vdblight/export/slice.h"

namespace vdblight {

namespace {
constexpr int kUAxis[3] = {2, 0, 0};
constexpr int kVAxis[3] = {1, 2, 1};

double srgbEncode(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }

std::string lower(std::string s) {
    for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}

void writeExr(const std::string& path, const SliceImage& image, int axis, double at, const Vec3f& normal) {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    header.insert("vdblightAxis", Imf::StringAttribute(std::string(1, "xyz"[axis])));
    header.insert("vdblightAt", Imf::DoubleAttribute(at));
    header.insert("vdblightNormal", Imf::V3fAttribute(Imath::V3f(normal.x, normal.y, normal.z)));
    header.insert("vdblightUnits", Imf::StringAttribute("irradiance W/m^2"));
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float) * 3, ys = xs * std::size_t(image.width);
    for (int c = 0; c < 3; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(image.rgb.data() + c)), xs, ys));
    try {
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        throw IoError("cannot write '" + path + "': " + e.what());
    }
}
}  // namespace

Vec3d SliceImage::pixelCentre(int c, int r, int axis, double at) const {
    Vec3d p;
    p[axis] = at;
    p[uAxis] = box.lo[uAxis] + (c + 0.5) * (box.hi[uAxis] - box.lo[uAxis]) / width;
    p[vAxis] = box.hi[vAxis] - (r + 0.5) * (box.hi[vAxis] - box.lo[vAxis]) / height;
    return p;
}

SliceImage sliceVolume(const Volume& volume, const SliceOptions& o) {
    if (o.axis < 0 || o.axis > 2) throw ValueError("slice axis must be x, y or z");
    const Vec3f n = o.normal;
    if (!(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) || !(length(n) > 0))
        throw ValueError("slice normal must be a finite, non-zero vector");
    if (o.size < 1 || o.size > 16384) throw ValueError("slice size must be 1 to 16384 pixels");
    const IrradianceQuery query(volume);
    SliceImage img;
    img.box = query.bounds();
    const char name = "xyz"[o.axis];
    if (!(o.at >= img.box.lo[o.axis] && o.at <= img.box.hi[o.axis])) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "slice position %c = %g is outside the volume (%g to %g)", name, o.at,
                      img.box.lo[o.axis], img.box.hi[o.axis]);
        throw ValueError(buf);
    }
    img.uAxis = kUAxis[o.axis];
    img.vAxis = kVAxis[o.axis];
    const double su = img.box.hi[img.uAxis] - img.box.lo[img.uAxis], sv = img.box.hi[img.vAxis] - img.box.lo[img.vAxis];
    const double longest = std::max(su, sv);
    img.width = longest > 0 ? std::max(1, int(std::lround(o.size * su / longest))) : o.size;
    img.height = longest > 0 ? std::max(1, int(std::lround(o.size * sv / longest))) : o.size;
    img.rgb.resize(std::size_t(img.width) * img.height * 3);
    const Vec3f unit = normalize(n);
    tbb::parallel_for(tbb::blocked_range<int>(0, img.height), [&](const tbb::blocked_range<int>& rows) {
        for (int r = rows.begin(); r < rows.end(); ++r)
            for (int c = 0; c < img.width; ++c) {
                const Rgb e = query.irradianceWorld(img.pixelCentre(c, r, o.axis, o.at), unit);
                float* px = img.rgb.data() + (std::size_t(r) * img.width + c) * 3;
                px[0] = e.x;
                px[1] = e.y;
                px[2] = e.z;
            }
    });
    return img;
}

std::vector<uint8_t> toneMapSlice(const SliceImage& image, const ToneMap& tone) {
    const std::size_t pixels = std::size_t(image.width) * image.height;
    double k = 1.0;
    if (tone.autoExposure) {
        double sum = 0;  // fixed order: deterministic
        for (std::size_t p = 0; p < pixels; ++p) {
            const float* px = image.rgb.data() + 3 * p;
            sum += std::max(0.0, double(luminance(Rgb(px[0], px[1], px[2]))) / kPi);
        }
        const double mean = pixels ? sum / double(pixels) : 0.0;
        if (mean > 0 && std::isfinite(mean)) k = 0.18 / mean;
    }
    const double scale = std::exp2(tone.exposure) * k / kPi;
    std::vector<uint8_t> out(pixels * 3);
    for (std::size_t i = 0; i < pixels * 3; ++i) {
        double L = std::max(0.0, double(image.rgb[i]) * scale);
        if (!std::isfinite(L)) L = 0.0;
        const double d = srgbEncode(L / (1.0 + L));
        out[i] = uint8_t(std::clamp(std::lround(d * 255.0), 0L, 255L));
    }
    return out;
}

void writeSlice(const std::string& path, const SliceImage& image, const ToneMap& tone, int axis, double at,
                const Vec3f& normal) {
    namespace fs = std::filesystem;
    const std::string ext = lower(fs::path(path).extension().string());
    if (ext != ".png" && ext != ".exr")
        throw ValueError("slice output '" + path + "' must end in .png (tone-mapped) or .exr (linear)");
    if (ext == ".png") writePng(path, image.width, image.height, toneMapSlice(image, tone));
    else writeFileAtomically(path, [&](const std::string& temp) { writeExr(temp, image, axis, at, normal); });
}

}  // namespace vdblight
