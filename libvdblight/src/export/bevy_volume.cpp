// Bevy's IrradianceVolume texture (export_engines.h): ambient cubes in one KTX2 Rgba16Float
// 3-D texture of (Rx, 2 Ry, 3 Rz) texels, and a manifest with the Transform that places
// Bevy's unit cube over the volume.
//
// Face placement follows what Bevy's shader samples (irradiance_volume.wgsl adds 0.5 to v
// when the normal's component is negative, i.e. the + faces fill rows [0, Ry) and the - faces
// rows [Ry, 2 Ry)); the doc comment of irradiance_volume.rs states the opposite halves, and
// the shader is what renders. docs/engines.md ("Bevy") records this.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "export_internal.h"
#include "staged_files.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"

namespace vdblight {

using namespace exporter;

uint64_t bevyTexelIndex(const int r[3], int x, int y, int z, int axis, bool negative) {
    const uint64_t t = uint64_t(y + (negative ? r[1] : 0));
    const uint64_t p = uint64_t(z + axis * r[2]);
    return uint64_t(x) + uint64_t(r[0]) * (t + uint64_t(2 * r[1]) * p);
}

namespace {

// The manifest is built as a JSON object whose keys keep the order they are added in.
using Json = nlohmann::ordered_json;

Json vec(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }

// Bevy's unit cube [-0.5, 0.5]^3 stretched over the voxels: voxel i's centre is at
// (i + 0.5) / R - 0.5 in cube space, so the cube spans R spacings per axis, centred on the
// node box; an axis of one voxel gets the volume's finest spacing as its thickness.
Vec3d cubeScale(const TextureLattice& l, double finest) {
    const Vec3d h = l.spacing();
    Vec3d s;
    for (int a = 0; a < 3; ++a) s[a] = double(l.dims[a]) * (h[a] > 0 ? h[a] : finest);
    return s;
}

std::string bevyManifest(const TextureLattice& l, const Vec3d& scale, const std::string& file) {
    Json m;
    m["vdblight_export_version"] = 2;
    m["preset"] = "bevy";
    m["engine_frame"] = "right-handed, +Y up, metres (the volume's own frame)";
    m["textures"] = Json::array({{{"name", "irradiance_volume"}, {"file", file}, {"format", "rgba16_sfloat"},
                                  {"bytes_per_texel", 8}, {"vkFormat", 97},
                                  {"components", {"red: E / pi", "green: E / pi", "blue: E / pi", "1"}}}});
    m["voxels"] = {l.dims[0], l.dims[1], l.dims[2]};
    m["dims"] = {l.dims[0], 2 * l.dims[1], 3 * l.dims[2]};
    m["face_texel"] = "face S of voxel (x, y, z): (x, y + (S negative ? Ry : 0), z + a Rz), a = 0, 1, 2 for X, Y, Z (as "
                      "irradiance_volume.wgsl samples it)";
    m["bounds_min"] = vec(l.lo);
    m["bounds_max"] = vec(l.hi);
    m["transform"] = {{"translation", vec((l.lo + l.hi) * 0.5)}, {"rotation", {0, 0, 0, 1}}, {"scale", vec(scale)}};
    m["values"] = "E(n) / pi for the face's axis normal n: the radiance of a white Lambertian surface, in the scene's "
                  "radiance unit (W/(m^2 sr) for scenes in W); Bevy multiplies it by the albedo and by "
                  "IrradianceVolume::intensity, which converts it to cd/m^2";
    m["units"] = "W/(m^2 sr)";
    m["sampler"] = "linear filtering, clamp-to-edge (Bevy's default image sampler)";
    m["reconstruction"] = "E(n) / pi ~= face(sign n_x X) n_x^2 + face(sign n_y Y) n_y^2 + face(sign n_z Z) n_z^2 (Valve's "
                          "ambient cube, as Bevy's shader blends it); exact for the six axis normals";
    return m.dump(2) + "\n";
}

}  // namespace

PresetSummary exportBevyIrradianceVolume(const Volume& volume, const std::string& outDir, int resolution) {
    if (outDir.empty()) throw IoError("no output directory given");
    const IrradianceQuery query(volume);
    const double finest = finestSpacing(volume.levels);
    PresetSummary summary;
    summary.lattice = chooseLattice(query.bounds(), finest, resolution);
    const TextureLattice& l = summary.lattice;
    const int r[3] = {l.dims[0], l.dims[1], l.dims[2]};
    if (r[0] > 2048 || 2 * r[1] > 2048 || 3 * r[2] > 2048)
        throw ValueError("Bevy's texture would be " + std::to_string(r[0]) + " x " + std::to_string(2 * r[1]) + " x " +
                         std::to_string(3 * r[2]) + " texels, over the 2048-texel limit of a 3-D texture; lower --resolution");
    std::vector<float> rgba(l.texelCount() * 6 * 4, 0.0f);
    tbb::parallel_for(tbb::blocked_range<int>(0, r[2]), [&](const tbb::blocked_range<int>& range) {
        for (int z = range.begin(); z < range.end(); ++z)
            for (int y = 0; y < r[1]; ++y)
                for (int x = 0; x < r[0]; ++x)
                    for (int face = 0; face < 6; ++face) {
                        const int axis = face / 2;
                        const bool negative = face % 2 == 1;
                        Vec3f n(0, 0, 0);
                        n[axis] = negative ? -1.0f : 1.0f;
                        const Rgb e = query.irradianceWorld(l.point(x, y, z), n) * float(1.0 / M_PI);
                        float* t = rgba.data() + 4 * bevyTexelIndex(r, x, y, z, axis, negative);
                        for (int c = 0; c < 3; ++c) t[c] = e[c];
                        t[3] = 1.0f;
                    }
    });
    for (std::size_t i = 0; i < rgba.size(); ++i)
        if (!(std::fabs(rgba[i]) <= 65504.0f))
            throw ValueError("Bevy texel " + std::to_string(i / 4) + " holds " + std::to_string(rgba[i]) +
                             ", outside the half-float range of Rgba16Float (+-65504)");

    StagedFiles staged;
    staged.createDirectory(outDir);
    const std::string file = "irradiance_volume.ktx2";
    TextureImage image;
    image.rgba = rgba.data();
    image.dims[0] = r[0];
    image.dims[1] = 2 * r[1];
    image.dims[2] = 3 * r[2];
    image.format = TexelFormat::Float16;
    image.name = "irradiance_volume";
    writeKtx2(staged.stage(outDir, file), image);
    const std::string json = bevyManifest(l, cubeScale(l, finest), file);
    writeBytes(staged.stage(outDir, "manifest.json"), std::vector<uint8_t>(json.begin(), json.end()));
    summary.files = staged.commit();
    for (const std::string& f : summary.files) summary.bytes += std::filesystem::file_size(f);
    return summary;
}

}  // namespace vdblight
