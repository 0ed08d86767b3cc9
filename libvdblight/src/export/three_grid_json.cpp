// probe_grid.json of `export --format three` (three_grid_json.h).
#include "three_grid_json.h"

#include <iomanip>
#include <sstream>

#include "vdblight/export/engines.h"

namespace vdblight::exporter {

namespace {
// Positions with 17 significant digits (setprecision below): they read back as the same doubles.
struct Vec3Json {
    Vec3d v;
};
std::ostream& operator<<(std::ostream& s, const Vec3Json& a) {
    return s << "[" << a.v.x << ", " << a.v.y << ", " << a.v.z << "]";
}
}  // namespace

std::string threeGridJson(const ThreeGridJsonInput& in) {
    const TextureLattice& l = *in.lattice;
    const Vec3d h = l.spacing();
    // Probes sit at cell centres in LightProbeGridWebGL: its box is the probes' box grown by h / 2.
    const Vec3d lo = l.lo - h * 0.5, hi = l.hi + h * 0.5;
    std::ostringstream s;
    s << std::setprecision(17);
    s << "{\n"
      << "  \"format\": \"vdblight-three-light-probe-grid\",\n"
      << "  \"version\": 1,\n"
      << "  \"three\": \"LightProbeGridWebGL of three.js r187 (npm three 0.187.0)\",\n"
      << "  \"resolution\": [" << l.dims[0] << ", " << l.dims[1] << ", " << l.dims[2] << "],\n"
      << "  \"bounds_min\": " << Vec3Json{lo} << ",\n"
      << "  \"bounds_max\": " << Vec3Json{hi} << ",\n"
      << "  \"center\": " << Vec3Json{(lo + hi) * 0.5} << ",\n"
      << "  \"size\": " << Vec3Json{hi - lo} << ",\n"
      << "  \"probe_min\": " << Vec3Json{l.lo} << ",\n"
      << "  \"probe_max\": " << Vec3Json{l.hi} << ",\n"
      << "  \"probe_spacing\": " << Vec3Json{h} << ",\n"
      << "  \"border_probes\": 1,\n"
      << "  \"texture\": {\n"
      << "    \"file\": \"" << kThreeGridAtlasFile << "\",\n"
      << "    \"type\": \"" << (in.halfFloat ? "float16" : "float32") << "\",\n"
      << "    \"three_type\": \"" << (in.halfFloat ? "HalfFloatType" : "FloatType") << "\",\n"
      << "    \"format\": \"RGBAFormat\",\n"
      << "    \"width\": " << l.dims[0] << ",\n"
      << "    \"height\": " << l.dims[1] << ",\n"
      << "    \"depth\": " << in.atlasDepth << ",\n"
      << "    \"byte_length\": " << uint64_t(l.dims[0]) * uint64_t(l.dims[1]) * uint64_t(in.atlasDepth) * (in.halfFloat ? 8u : 16u)
      << ",\n"
      << "    \"texel_order\": \"RGBA little-endian, x fastest, then y, then atlas slice; no header\",\n"
      << "    \"atlas\": \"7 sub-volumes along z, each 1 padding slice (copy of its first data slice), nz data slices, "
         "1 padding slice (copy of its last); sub-volume t holds floats 4t..4t+3 of c0.rgb c1.rgb ... c8.rgb 0\"\n"
      << "  },\n"
      << "  \"coefficients\": \"c_j = radiance SH coefficient j = l(l+1)+m of docs/format.md (orthonormal, no "
         "Condon-Shortley phase), bands 0..2; three's shader returns E(n) = sum_j A_l c_j Y_j(n), W/m^2 in the "
         "scene's units\",\n"
      << "  \"basis\": \"" << in.basisKind << "\",\n"
      << "  \"depth_moments\": " << (in.hasDepthMoments ? "true" : "false") << ",\n"
      << (in.foldedDirect.empty() ? std::string() : "  \"direct_light\": " + in.foldedDirect + ",\n")
      << "  \"interpolation\": \"trilinear at the shader's sample point (the fragment moved half a probe spacing "
         "along its normal); "
      << (in.hasDepthMoments ? "the volume's depth moments are not used (match: vdblight query --sh-order 2 "
                               "--no-depth-weights)"
                             : "match: vdblight query --sh-order 2")
      << "\"\n"
      << "}\n";
    return s.str();
}

}  // namespace vdblight::exporter
