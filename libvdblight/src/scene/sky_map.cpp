// Equirectangular sky maps: reading them from EXR and looking up radiance by direction.
// The mapping is documented on SkyMap in scene.h and in docs/scene.md.
#include <algorithm>
#include <cmath>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

Rgb SkyMap::lookup(const Vec3f& dirToSky) const {
    if (texels.empty() || !isFinite(dirToSky)) return {0, 0, 0};
    const double v = std::acos(std::clamp(double(dirToSky.y), -1.0, 1.0)) * kInvPi;
    double u = 0.5 + std::atan2(double(dirToSky.z), double(dirToSky.x)) / (2 * kPi);
    u -= std::floor(u);
    const int col = std::clamp(int(u * width), 0, width - 1);
    const int row = std::clamp(int(v * height), 0, height - 1);
    return texels[std::size_t(row) * std::size_t(width) + std::size_t(col)];
}

namespace {

std::string oneLine(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

/// Reads R, G, B (or a luminance-only Y for all three) as float into map.texels.
void readTexels(const std::string& path, SkyMap& map) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    map.width = window.max.x - window.min.x + 1;
    map.height = window.max.y - window.min.y + 1;
    if (map.width <= 0 || map.height <= 0) throw IoError("sky map '" + path + "' is empty");
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb = channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
    if (!rgb && !channels.findChannel("Y"))
        throw IoError("sky map '" + path + "' has neither R, G, B nor Y channels");

    map.texels.assign(std::size_t(map.width) * std::size_t(map.height), Rgb{0, 0, 0});
    char* base = reinterpret_cast<char*>(map.texels.data());
    const std::size_t xStride = sizeof(Rgb), yStride = xStride * std::size_t(map.width);
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (rgb ? 3 : 1); ++c)
        fb.insert(rgb ? names[c] : "Y",
                  Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), window, xStride, yStride));
    file.setFrameBuffer(fb);
    file.readPixels(window.min.y, window.max.y);
    if (!rgb)
        for (Rgb& t : map.texels) t.y = t.z = t.x;
}

}  // namespace

std::shared_ptr<const SkyMap> loadSkyMap(const std::string& path) {
    auto map = std::make_shared<SkyMap>();
    map->path = path;
    try {
        readTexels(path, *map);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {  // Iex::BaseExc derives from std::exception
        throw IoError("cannot read sky map '" + path + "': " + oneLine(e.what()));
    }
    for (std::size_t i = 0; i < map->texels.size(); ++i) {
        Rgb& t = map->texels[i];
        if (!isFinite(t))
            throw IoError("sky map '" + path + "': texel (" + std::to_string(i % std::size_t(map->width)) +
                          ", " + std::to_string(i / std::size_t(map->width)) + ") is not finite");
        t = vmax(t, Rgb{0, 0, 0});  // small negative values come from filtering, not from light
    }
    return map;
}

}  // namespace vdblight
