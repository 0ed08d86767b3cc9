// probe_grid.json of `export --format three` (three_grid_json.h).
#include "three_grid_json.h"

#include "vdblight/export/engines.h"

namespace vdblight::exporter {

namespace {
// Built as a JSON object whose keys keep the order they are added in.
using Json = nlohmann::ordered_json;

Json vec(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }
}  // namespace

std::string threeGridJson(const ThreeGridJsonInput& in) {
    const TextureLattice& l = *in.lattice;
    const Vec3d h = l.spacing();
    // Probes sit at cell centres in LightProbeGridWebGL: its box is the probes' box grown by h / 2.
    const Vec3d lo = l.lo - h * 0.5, hi = l.hi + h * 0.5;
    Json j;
    j["format"] = "vdblight-three-light-probe-grid";
    j["version"] = 1;
    j["three"] = "LightProbeGridWebGL of three.js r187 (npm three 0.187.0)";
    j["resolution"] = {l.dims[0], l.dims[1], l.dims[2]};
    j["bounds_min"] = vec(lo);
    j["bounds_max"] = vec(hi);
    j["center"] = vec((lo + hi) * 0.5);
    j["size"] = vec(hi - lo);
    j["probe_min"] = vec(l.lo);
    j["probe_max"] = vec(l.hi);
    j["probe_spacing"] = vec(h);
    j["border_probes"] = 1;
    Json texture;
    texture["file"] = kThreeGridAtlasFile;
    texture["type"] = in.halfFloat ? "float16" : "float32";
    texture["three_type"] = in.halfFloat ? "HalfFloatType" : "FloatType";
    texture["format"] = "RGBAFormat";
    texture["width"] = l.dims[0];
    texture["height"] = l.dims[1];
    texture["depth"] = in.atlasDepth;
    texture["byte_length"] = uint64_t(l.dims[0]) * uint64_t(l.dims[1]) * uint64_t(in.atlasDepth) * (in.halfFloat ? 8u : 16u);
    texture["texel_order"] = "RGBA little-endian, x fastest, then y, then atlas slice; no header";
    texture["atlas"] = "7 sub-volumes along z, each 1 padding slice (copy of its first data slice), nz data slices, 1 "
                       "padding slice (copy of its last); sub-volume t holds floats 4t..4t+3 of c0.rgb c1.rgb ... c8.rgb 0";
    j["texture"] = std::move(texture);
    j["coefficients"] = "c_j = radiance SH coefficient j = l(l+1)+m of docs/format.md (orthonormal, no Condon-Shortley "
                        "phase), bands 0..2; three's shader returns E(n) = sum_j A_l c_j Y_j(n), W/m^2 in the scene's units";
    j["basis"] = in.basisKind;
    j["depth_moments"] = in.hasDepthMoments;
    if (!in.foldedDirect.is_null()) j["direct_light"] = in.foldedDirect;
    j["interpolation"] = std::string("trilinear at the shader's sample point (the fragment moved half a probe spacing "
                                     "along its normal); ") +
                         (in.hasDepthMoments ? "the volume's depth moments are not used (match: vdblight query "
                                               "--sh-order 2 --no-depth-weights)"
                                             : "match: vdblight query --sh-order 2");
    return j.dump(2) + "\n";
}

}  // namespace vdblight::exporter
