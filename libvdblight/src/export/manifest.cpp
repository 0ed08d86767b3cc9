// manifest.json: everything a shader or loader needs to use the exported textures
// (docs/engines.md explains each field).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "compact_sh.h"
#include "export_internal.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "basis/sh.h"

namespace vdblight::exporter {

namespace {
std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
            continue;
        }
        out += c;
    }
    return out + "\"";
}
std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
/// A float constant as the shortest decimal that reads back as the same float.
std::string numFloat(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", double(v));
    for (int digits = 1; digits <= 9; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, double(v));
        if (std::strtof(buf, nullptr) == v) break;
    }
    return buf;
}
std::string vec(const Vec3d& v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }

const char* irradianceFormula(ExportLayout layout) {
    switch (layout) {
        case ExportLayout::Sh2:
            return "E = sum_j A_l(j) * L_j * Y_j(n) per colour channel, L_j = texture sh2_<j>.rgb, "
                   "Y_j as in docs/format.md (c0..c4 below), A_0 = A0, A_1 = A1, A_2 = A2";
        case ExportLayout::Sh2Packed:
            return "E_c = dot(shAc, (n, 1)) + dot(shBc, (n.x*n.y, n.y*n.z, n.z*n.z, n.z*n.x)) "
                   "+ shC.c * (n.x*n.x - n.y*n.y), for c in r, g, b and a unit normal n";
        case ExportLayout::Sh1:
            return "E_c = dot(shAc, (n, 1)) for c in r, g, b and a unit normal n "
                   "(order-1 SH: the band-2 part of the volume's irradiance is left out)";
        case ExportLayout::Vectors:
            return "E_c = clamp(Q_c, max(0, max over the six d of dot(I_d c, n)), sum_a |n_a| E_(a, sign n_a) c) with "
                   "Q_c = 1/2 sum_a V_a n_a + 1/4 sum_a sum_b G_ab n_a n_b + 1/4 sum_a G_aa n_a^2, "
                   "V_a = I_(a,pos) c[a] + I_(a,neg) c[a], G_ab = I_(a,pos) c[b] - I_(a,neg) c[b], "
                   "E_(a,pos) c = I_(a,pos) c[a], E_(a,neg) c = -I_(a,neg) c[a], I_(a, s) c = texture "
                   "iv_<a><pos|neg>_<c>.rgb (world x, y, z in r, g, b), for c in r, g, b and a unit normal n "
                   "(the bounded blend of docs/format.md, what vdblight query does)";
        case ExportLayout::Compact:
            return "I_(a, s) c = ivc_<a><pos|neg>_colour.c * normalize(ivc_<a><pos|neg>_dir.rgb) (Pacanowski et al. "
                   "section 4.2: lossy where the three colours' vectors differ in direction), then E_c as for the vectors "
                   "layout (bounded blend), for c in r, g, b and a unit normal n";
        case ExportLayout::Bins:
            return "E(d).rgb = texture of the bin of direction d (bins.bin_of_direction; d = the normal n for bins:R, "
                   "the view vector mirrored about n for moment:n), or the bilinear blend of the four bins of "
                   "bins.blend (what vdblight query does)";
        case ExportLayout::Basis:
            return "";  // the basis's own (ManifestInput::basisFormula)
        case ExportLayout::Sh1x16:
            return "decode each texel (compact_sh.decode) into shAr, shAg, shAb, then E_c = dot(shAc, (n, 1)) as for sh1; "
                   "decode the 8 corner texels and blend them (trilinear, or the depth weights): decoding after hardware "
                   "filtering is not exact between texels";
        case ExportLayout::Sh2x32:
            return "decode each texel (compact_sh.decode) into shAr..shC, then E_c as for sh2-packed: dot(shAc, (n, 1)) + "
                   "dot(shBc, (n.x*n.y, n.y*n.z, n.z*n.z, n.z*n.x)) + shC.c * (n.x*n.x - n.y*n.y); decode the 8 corner "
                   "texels and blend them (trilinear, or the depth weights): decoding after hardware filtering is not exact "
                   "between texels";
    }
    return "";
}
/// The "compact_sh" object of sh1-16 / sh2-32: the decode constants (compact_sh.h).
std::string compactShJson(ExportLayout layout) {
    std::ostringstream s;
    s << "  \"compact_sh\": {\"l0_texture\": \"L0_L1Rx\", \"l1_range\": " << num(compact_sh::kL1Range);
    if (layout == ExportLayout::Sh2x32)
        s << ", \"l2_range\": [" << num(compact_sh::kL2Range[0]) << ", " << num(compact_sh::kL2Range[1]) << ", "
          << num(compact_sh::kL2Range[2]) << ", " << num(compact_sh::kL2Range[3]) << "], \"l2c_range\": "
          << num(compact_sh::kL2CRange);
    s << ",\n    \"encode\": \"per colour c: a = A0*c0*L0 (stored as is in L0_L1Rx.rgb); every other value v is stored as "
         "t = clamp(v / (range * a) + 0.5, 0, 1) (t = 0.5 where a <= 0), in 8-bit unorm except L0_L1Rx.a\",\n"
      << "    \"decode\": \"v = (t - 0.5) * range * a with a of the same texel and colour; b_c = (A1*c1*L3, A1*c1*L1, "
         "A1*c1*L2) = L1 values of colour c (red: L0_L1Rx.a, L1G_L1Ry.a, L1B_L1Rz.a; green: L1G_L1Ry.rgb; blue: "
         "L1B_L1Rz.rgb), range l1_range; shA_c = (b_c, a_c - d_c)";
    if (layout == ExportLayout::Sh2x32)
        s << "; from L2_<c>.rgba with l2_range: (A2*c2*L4, A2*c2*L5, d = A2*c3*L6, A2*c2*L7), shB_c = (L4 term, L5 term, "
             "3 d, L7 term); shC.c = (L2_C.c - 0.5) * l2c_range * a_c";
    else
        s << " with d_c = 0 (no band 2)";
    s << "\",\n    \"ranges_why\": \"the largest |v / a| of a non-negative radiance: |L1 term| <= 2 a, |L4, L5, L7 terms| <= "
         "15/8 a, -5/16 a <= d <= 5/8 a, |L8 term| <= 15/16 a (docs/engines.md)\",\n"
      << "    \"bytes_per_probe\": \"" << (layout == ExportLayout::Sh2x32 ? 32 : 16)
      << " with --half in ktx2, dds and raw (8 for L0_L1Rx, 4 for each other texture; the EXR atlas stores them all in "
         "half or float)\"},\n";
    return s.str();
}

/// The "direct" object (bake --direct; docs/engines.md, "Direct light").
std::string directJson(const DirectLightSet& d, const std::vector<std::string>& visibility) {
    std::ostringstream s;
    s << "  \"direct\": {\"mode\": " << quote(directModeName(d.mode)) << ",\n";
    switch (d.mode) {
        case DirectMode::Baked:
            s << "    \"meaning\": \"the textures hold all light, direct included\",\n";
            break;
        case DirectMode::Runtime:
            s << "    \"meaning\": \"the textures hold indirect light only; add each listed light's direct light with "
                 "your own shadows (docs/engines.md)\",\n";
            break;
        case DirectMode::Occlusion:
            s << "    \"meaning\": \"the textures hold indirect light and the direct light of unlisted lights; add for each "
                 "listed light exact_irradiance(light, x, n) * visibility, visibility = its component of its "
                 "light_visibility texture sampled like the others (docs/engines.md)\",\n";
            break;
    }
    s << "    \"lights\": [";
    for (std::size_t i = 0; i < d.lights.size(); ++i) {
        const DirectLight& l = d.lights[i];
        s << (i ? ",\n" : "\n") << "      {";
        switch (l.kind) {
            case DirectLight::Kind::Point:
                s << "\"kind\": \"point\", \"intensity\": " << vec(Vec3d(l.value)) << ", \"position\": " << vec(l.position);
                break;
            case DirectLight::Kind::Spot:
                s << "\"kind\": \"spot\", \"intensity\": " << vec(Vec3d(l.value)) << ", \"position\": " << vec(l.position)
                  << ", \"direction\": " << vec(l.direction) << ", \"inner_cone\": " << num(l.innerCone)
                  << ", \"outer_cone\": " << num(l.outerCone);
                break;
            case DirectLight::Kind::Directional:
                s << "\"kind\": \"directional\", \"irradiance\": " << vec(Vec3d(l.value)) << ", \"direction\": " << vec(l.direction);
                break;
            case DirectLight::Kind::Polygon:
            case DirectLight::Kind::Mesh:
                s << "\"kind\": " << (l.kind == DirectLight::Kind::Mesh ? "\"mesh\"" : "\"polygon\"") << ", \"radiance\": "
                  << vec(Vec3d(l.value)) << ", \"two_sided\": " << (l.twoSided ? "true" : "false");
                if (l.kind == DirectLight::Kind::Polygon) s << ", \"normal\": " << vec(l.normal);
                s << ", \"loops\": [";
                for (std::size_t k = 0; k < l.loops.size(); ++k) {
                    s << (k ? ", [" : "[");
                    for (std::size_t v = 0; v < l.loops[k].size(); ++v) s << (v ? ", " : "") << vec(l.loops[k][v]);
                    s << "]";
                }
                s << "]";
                break;
        }
        if (d.hasVisibility() && i / 4 < visibility.size())
            s << ", \"visibility\": {\"texture\": " << quote(visibility[i / 4]) << ", \"component\": \""
              << "rgba"[i % 4] << "\"}";
        s << "}";
    }
    s << (d.lights.empty() ? "]\n" : "\n    ]\n") << "  },\n";
    return s.str();
}
}  // namespace

std::string manifestJson(const ManifestInput& in) {
    const ExportOptions& o = *in.options;
    const TextureLattice& l = *in.lattice;
    const Vec3d h = l.spacing();
    Vec3d scale, bias;
    for (int a = 0; a < 3; ++a) {
        if (l.dims[a] > 1) {
            scale[a] = 1.0 / (h[a] * l.dims[a]);
            bias[a] = (0.5 - l.lo[a] / h[a]) / l.dims[a];
        } else {
            scale[a] = 0.0;
            bias[a] = 0.5;
        }
    }
    std::ostringstream s;
    s << "{\n";
    // Version 2: every texture states its own texel format (the depth textures are 8-bit unorm).
    s << "  \"vdblight_export_version\": 2,\n";
    s << "  \"volume_kind\": " << quote(in.volumeKind) << ",\n";
    s << "  \"format\": " << quote(formatName(o.format)) << ",\n";
    s << "  \"layout\": " << quote(layoutName(o.layout)) << ",\n";
    s << "  \"component_type\": " << quote(o.halfFloat ? "float16" : "float32") << ",\n";
    s << "  \"byte_order\": \"little-endian\",\n";
    s << "  \"dims\": [" << l.dims[0] << ", " << l.dims[1] << ", " << l.dims[2] << "],\n";
    s << "  \"bounds_min\": " << vec(l.lo) << ",\n";
    s << "  \"bounds_max\": " << vec(l.hi) << ",\n";
    s << "  \"texel_spacing\": " << vec(h) << ",\n";
    s << "  \"texel_points\": \"texel (i, j, k) holds the volume at bounds_min + texel_spacing * (i, j, k); "
         "between texel points the volume is trilinear\",\n";
    s << "  \"uvw_scale\": " << vec(scale) << ",\n";
    s << "  \"uvw_bias\": " << vec(bias) << ",\n";
    s << "  \"uvw_formula\": \"uvw = x * uvw_scale + uvw_bias = ((x - bounds_min) / texel_spacing + 0.5) / dims "
         "(the half-texel offset puts texel centres on the texel points)\",\n";
    s << "  \"sampler\": {\"filter\": \"linear\", \"address\": \"clamp-to-edge\", \"mipmaps\": false, \"srgb\": false},\n";
    s << "  \"texel_order\": \"RGBA per texel; x fastest, then y, then z (texel (i, j, k) at index i + dims[0] * (j + "
         "dims[1] * k))\",\n";
    s << "  \"irradiance\": " << quote(o.layout == ExportLayout::Basis ? in.basisFormula : irradianceFormula(o.layout)) << ",\n";
    if (o.layout == ExportLayout::Basis) s << "  \"basis\": " << quote(in.basisKind) << ",\n";
    // An sh:N volume (N > 2; the default bake stores sh:4) in an SH order-2 layout: its bands
    // 0..2 (sh_truncate.h), which `vdblight query --sh-order 2` answers with.
    const bool shLayout = o.layout == ExportLayout::Sh2 || o.layout == ExportLayout::Sh2Packed || o.layout == ExportLayout::Sh1 ||
                          isCompactSh(o.layout);
    BasisDesc basis;
    basis.kind = in.basisKind;
    if (shLayout && basis.isRealSh() && !basis.isSh2() && basis.shOrder() != 2)
        s << "  \"truncated_from\": {\"basis\": " << quote(in.basisKind)
          << ", \"kept\": \"bands 0..2 of the volume's SH (the projection onto them); vdblight query --sh-order 2 "
             "gives the same irradiance; export --layout basis holds every band\"},\n";
    s << "  \"units\": \"irradiance in W/m^2 (or the scene's radiometric unit times sr); positions in scene units\",\n";
    s << "  \"constants\": {\"A0\": " << num(sh::kCosineLobe[0]) << ", \"A1\": " << num(sh::kCosineLobe[1])
      << ", \"A2\": " << num(sh::kCosineLobe[2]) << ", \"c0\": " << num(0.5 / std::sqrt(kPi))
      << ", \"c1\": " << num(std::sqrt(3.0 / (4.0 * kPi))) << ", \"c2\": " << num(std::sqrt(15.0 / (4.0 * kPi)))
      << ", \"c3\": " << num(std::sqrt(5.0 / (16.0 * kPi))) << ", \"c4\": " << num(std::sqrt(15.0 / (16.0 * kPi)))
      << "},\n";
    if (isCompactSh(o.layout)) s << compactShJson(o.layout);
    if (o.layout == ExportLayout::Bins) {
        const int R = in.binResolution;
        s << "  \"bins\": {\"basis\": " << quote(in.basisKind) << ", \"resolution\": " << R
          << ", \"count\": " << 2 * R * R << ", \"moment_order\": " << in.momentOrder << ",\n";
        s << "    \"texture_of_bin\": \"bin (h, iu, iv) is texture index h*R*R + iv*R + iu, named "
             "bin_h<h>_u<iu>_v<iv>; its rgb is the stored value, alpha 0\",\n";
        s << "    \"bin_of_direction\": \"unit d: h = 1 if d.z < 0 else 0; (px, py) = (d.x, d.y) / sqrt(1 + |d.z|); "
             "rho = |(px, py)|, phi = atan2(py, px) in [-pi/4, 7pi/4); phi < pi/4: a = rho, b = a*phi/(pi/4); "
             "phi < 3pi/4: b = rho, a = -b*(phi - pi/2)/(pi/4); phi < 5pi/4: a = -rho, b = a*(phi - pi)/(pi/4); "
             "else b = -rho, a = -b*(phi - 3pi/2)/(pi/4); u = clamp((a + 1)/2, 0, 1), v = clamp((b + 1)/2, 0, 1); "
             "bin (h, min(floor(u*R), R-1), min(floor(v*R), R-1)) (docs/format.md)\",\n";
        s << "    \"blend\": \"vdblight query's default: gu = u*R - 0.5, gv = v*R - 0.5, iu0 = floor(gu), iv0 = floor(gv), "
             "fu = gu - iu0, fv = gv - iv0; bins (iu0 + a, iv0 + b), a, b in {0, 1}, weight (a ? fu : 1 - fu) * "
             "(b ? fv : 1 - fv); an index outside [0, R-1] is clamped and flips h (both outside: h flips twice)\",\n";
        s << "    \"bin_of_texture\": [";
        for (int c = 0; c < 2 * R * R; ++c)
            s << (c ? ", " : "") << "[" << c / (R * R) << ", " << c % R << ", " << c % (R * R) / R << "]";
        s << "]},\n";
    }
    if (in.depth != 0) {
        s << "  \"depth\": {\"exported\": " << (in.depth > 0 ? "true" : "false");
        if (in.depth > 0) {
            const TexelFormat f = in.texelFormats.back();  // the depth textures come last
            s << ", \"textures\": [\"depth_x\", \"depth_y\", \"depth_z\"], \"format\": " << quote(texelFormatName(f))
              << ", \"bytes_per_node\": " << 3 * 4 * componentBytes(f) << ", \"bias\": " << numFloat(depth::kDepthBias)
              << ", \"min_sigma\": " << numFloat(depth::kDepthMinSigma) << ", \"floor\": " << numFloat(depth::kDepthFloor)
              << ",\n    \"units\": \"cells: distances divided by texel_spacing (the node spacing), clamped to 1\",\n"
              << "    \"values\": " << quote(f == TexelFormat::Unorm8
                                           ? "multiples of 1/255 stored exactly as 8-bit unorm: a texture fetch returns byte / 255, "
                                             "the value in cells"
                                           : "multiples of 1/255 (no 8-bit type in this container; half rounds them by up to 2^-12)")
              << ",\n"
              << "    \"components\": \"depth_a.rgba = (mean of the +a face, mean of the -a face, sigma of +a, sigma of -a): "
                 "the axial depth along a of the first hits of the node's rays whose dominant axis is +a or -a\",\n"
              << "    \"lookup\": \"fetch the 8 corner texels (no hardware filtering); corner offset o = (x - corner) / "
                 "texel_spacing; per axis a: mu, sigma = the face on the side of o_a, e = |o_a| - mu - bias, v_a = 1 if e <= 0 "
                 "else s2 / (s2 + e^2) with s2 = sigma^2 + min_sigma^2; vis = (v_x v_y v_z)^3; weight = trilinear * (vis + floor); "
                 "blend the layout's texels with the weights divided by their sum (docs/engines.md)\"";
        } else {
            s << ", \"reason\": \"depth moments belong to the volume's nodes; this lattice is not the finest level's "
                 "nodes (--resolution)\"";
        }
        s << "},\n";
    }
    if (in.direct) s << directJson(*in.direct, in.visibilityTextures);
    switch (o.format) {
        case TextureFormat::Ktx2:
            s << "  \"ktx2\": {\"vkFormat\": " << vkFormatOf(lightingTexelFormat(o.halfFloat))
              << ", \"KTXorientation\": \"ruo\", \"levels\": 1},\n";
            break;
        case TextureFormat::Dds:
            s << "  \"dds\": {\"dxgiFormat\": " << dxgiFormatOf(lightingTexelFormat(o.halfFloat))
              << ", \"resourceDimension\": \"TEXTURE3D\", \"arraySize\": 1, \"mipLevels\": 1},\n";
            break;
        case TextureFormat::ExrAtlas: {
            const AtlasGrid g = atlasGrid(l.dims[2]);
            s << "  \"exr_atlas\": {\"columns\": " << g.columns << ", \"rows\": " << g.rows
              << ", \"slice_width\": " << l.dims[0] << ", \"slice_height\": " << l.dims[1]
              << ", \"slices\": " << l.dims[2] << ", \"width\": " << g.columns * l.dims[0]
              << ", \"height\": " << g.rows * l.dims[1]
              << ", \"placement\": \"slice z is the tile at column z % columns, row z / columns (z = 0 top left); "
                 "image row r of a tile holds texel row j = r; unused tiles are 0\"},\n";
            break;
        }
        case TextureFormat::Raw:
            s << "  \"raw\": {\"header_bytes\": 0},\n";
            break;
    }
    s << "  \"textures\": [\n";
    for (std::size_t t = 0; t < in.textures.size(); ++t) {
        const TextureDesc& d = in.textures[t];
        const TexelFormat f = in.texelFormats.at(t);
        s << "    {\"name\": " << quote(d.name) << ", \"file\": " << quote(in.fileNames[t]) << ", \"format\": "
          << quote(texelFormatName(f)) << ", \"bytes_per_texel\": " << 4 * componentBytes(f);
        if (o.format == TextureFormat::Ktx2) s << ", \"vkFormat\": " << vkFormatOf(f);
        if (o.format == TextureFormat::Dds) s << ", \"dxgiFormat\": " << dxgiFormatOf(f);
        if (o.format != TextureFormat::ExrAtlas) s << ", \"data_offset\": " << in.dataOffsets[t];
        s << ", \"components\": [" << quote(d.components[0]) << ", " << quote(d.components[1]) << ", "
          << quote(d.components[2]) << ", " << quote(d.components[3]) << "]}"
          << (t + 1 < in.textures.size() ? "," : "") << "\n";
    }
    s << "  ]\n}\n";
    return s.str();
}

}  // namespace vdblight::exporter
