// manifest.json: everything a shader or loader needs to use the exported textures
// (docs/engines.md explains each field). Built as a JSON object (nlohmann-json3-dev) whose
// keys keep the order they are added in, so that the file reads top-down as the docs do:
// the lattice, the formula and its constants, the layout's own objects, the textures.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "compact_sh.h"
#include "export_internal.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "basis/shadow_edges.h"
#include "basis/sh.h"

namespace vdblight::exporter {

namespace {

using Json = nlohmann::ordered_json;

Json vec(const Vec3d& v) { return Json::array({v.x, v.y, v.z}); }
Json ints3(const int v[3]) { return Json::array({v[0], v[1], v[2]}); }
/// A float constant as the double of its shortest decimal that reads back as the same float
/// (0.02f is written 0.02, not 0.019999999552965164).
double shortestFloat(float v) {
    char buf[32];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf - 1, v);
    *r.ptr = '\0';
    return std::strtod(buf, nullptr);
}

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
Json compactShJson(ExportLayout layout) {
    const bool order2 = layout == ExportLayout::Sh2x32;
    Json j;
    j["l0_texture"] = "L0_L1Rx";
    j["l1_range"] = compact_sh::kL1Range;
    if (order2) {
        j["l2_range"] = Json(compact_sh::kL2Range);
        j["l2c_range"] = compact_sh::kL2CRange;
    }
    j["encode"] = "per colour c: a = A0*c0*L0 (stored as is in L0_L1Rx.rgb); every other value v is stored as "
                  "t = clamp(v / (range * a) + 0.5, 0, 1) (t = 0.5 where a <= 0), in 8-bit unorm except L0_L1Rx.a";
    j["decode"] = std::string("v = (t - 0.5) * range * a with a of the same texel and colour; b_c = (A1*c1*L3, A1*c1*L1, "
                              "A1*c1*L2) = L1 values of colour c (red: L0_L1Rx.a, L1G_L1Ry.a, L1B_L1Rz.a; green: "
                              "L1G_L1Ry.rgb; blue: L1B_L1Rz.rgb), range l1_range; shA_c = (b_c, a_c - d_c)") +
                  (order2 ? "; from L2_<c>.rgba with l2_range: (A2*c2*L4, A2*c2*L5, d = A2*c3*L6, A2*c2*L7), shB_c = "
                            "(L4 term, L5 term, 3 d, L7 term); shC.c = (L2_C.c - 0.5) * l2c_range * a_c"
                          : " with d_c = 0 (no band 2)");
    j["ranges_why"] = "the largest |v / a| of a non-negative radiance: |L1 term| <= 2 a, |L4, L5, L7 terms| <= 15/8 a, "
                      "-5/16 a <= d <= 5/8 a, |L8 term| <= 15/16 a (docs/engines.md)";
    j["bytes_per_probe"] = std::string(order2 ? "32" : "16") +
                           " with --half in ktx2, dds and raw (8 for L0_L1Rx, 4 for each other texture; the EXR atlas "
                           "stores them all in half or float)";
    return j;
}

/// The "bins" object of the bins layout: how a direction picks and blends the bin textures.
Json binsJson(const ManifestInput& in) {
    const int R = in.binResolution;
    Json j;
    j["basis"] = in.basisKind;
    j["resolution"] = R;
    j["count"] = 2 * R * R;
    j["moment_order"] = in.momentOrder;
    j["texture_of_bin"] = "bin (h, iu, iv) is texture index h*R*R + iv*R + iu, named bin_h<h>_u<iu>_v<iv>; its rgb is "
                          "the stored value, alpha 0";
    j["bin_of_direction"] =
        "unit d: h = 1 if d.z < 0 else 0; (px, py) = (d.x, d.y) / sqrt(1 + |d.z|); rho = |(px, py)|, phi = atan2(py, px) "
        "in [-pi/4, 7pi/4); phi < pi/4: a = rho, b = a*phi/(pi/4); phi < 3pi/4: b = rho, a = -b*(phi - pi/2)/(pi/4); "
        "phi < 5pi/4: a = -rho, b = a*(phi - pi)/(pi/4); else b = -rho, a = -b*(phi - 3pi/2)/(pi/4); u = clamp((a + 1)/2, "
        "0, 1), v = clamp((b + 1)/2, 0, 1); bin (h, min(floor(u*R), R-1), min(floor(v*R), R-1)) (docs/format.md)";
    j["blend"] = "vdblight query's default: gu = u*R - 0.5, gv = v*R - 0.5, iu0 = floor(gu), iv0 = floor(gv), fu = gu - "
                 "iu0, fv = gv - iv0; bins (iu0 + a, iv0 + b), a, b in {0, 1}, weight (a ? fu : 1 - fu) * (b ? fv : 1 - "
                 "fv); an index outside [0, R-1] is clamped and flips h (both outside: h flips twice)";
    Json bins = Json::array();
    for (int c = 0; c < 2 * R * R; ++c) bins.push_back(Json::array({c / (R * R), c % R, c % (R * R) / R}));
    j["bin_of_texture"] = std::move(bins);
    return j;
}

/// The "depth" object: the depth textures and their lookup, or why they were not exported.
Json depthJson(const ManifestInput& in) {
    Json j;
    j["exported"] = in.depth > 0;
    if (in.depth < 0) {
        j["reason"] = "depth moments belong to the volume's nodes; this lattice is not the finest level's nodes "
                      "(--resolution)";
        return j;
    }
    const TexelFormat f = in.texelFormats.back();  // the depth textures come last
    j["textures"] = {"depth_x", "depth_y", "depth_z"};
    j["format"] = texelFormatName(f);
    j["bytes_per_node"] = 3 * 4 * componentBytes(f);
    j["bias"] = shortestFloat(depth::kDepthBias);
    j["min_sigma"] = shortestFloat(depth::kDepthMinSigma);
    j["floor"] = shortestFloat(depth::kDepthFloor);
    j["units"] = "cells: distances divided by texel_spacing (the node spacing), clamped to 1";
    j["values"] = f == TexelFormat::Unorm8 ? "multiples of 1/255 stored exactly as 8-bit unorm: a texture fetch returns "
                                             "byte / 255, the value in cells"
                                           : "multiples of 1/255 (no 8-bit type in this container; half rounds them by up "
                                             "to 2^-12)";
    j["components"] = "depth_a.rgba = (mean of the +a face, mean of the -a face, sigma of +a, sigma of -a): the axial "
                      "depth along a of the first hits of the node's rays whose dominant axis is +a or -a";
    j["lookup"] = "fetch the 8 corner texels (no hardware filtering); corner offset o = (x - corner) / texel_spacing; per "
                  "axis a: mu, sigma = the face on the side of o_a, e = |o_a| - mu - bias, v_a = 1 if e <= 0 else s2 / "
                  "(s2 + e^2) with s2 = sigma^2 + min_sigma^2; vis = (v_x v_y v_z)^3; weight = trilinear * (vis + floor); "
                  "blend the layout's texels with the weights divided by their sum (docs/engines.md)";
    return j;
}

/// One light of the "direct" object, as exact_irradiance.h evaluates it.
Json lightJson(const DirectLight& l) {
    Json j;
    switch (l.kind) {
        case DirectLight::Kind::Point:
            j["kind"] = "point";
            j["intensity"] = vec(Vec3d(l.value));
            j["position"] = vec(l.position);
            break;
        case DirectLight::Kind::Spot:
            j["kind"] = "spot";
            j["intensity"] = vec(Vec3d(l.value));
            j["position"] = vec(l.position);
            j["direction"] = vec(l.direction);
            j["inner_cone"] = double(l.innerCone);
            j["outer_cone"] = double(l.outerCone);
            break;
        case DirectLight::Kind::Directional:
            j["kind"] = "directional";
            j["irradiance"] = vec(Vec3d(l.value));
            j["direction"] = vec(l.direction);
            break;
        case DirectLight::Kind::Polygon:
        case DirectLight::Kind::Mesh: {
            j["kind"] = l.kind == DirectLight::Kind::Mesh ? "mesh" : "polygon";
            j["radiance"] = vec(Vec3d(l.value));
            j["two_sided"] = l.twoSided;
            if (l.kind == DirectLight::Kind::Polygon) j["normal"] = vec(l.normal);
            Json loops = Json::array();
            for (const auto& loop : l.loops) {
                Json points = Json::array();
                for (const Vec3d& p : loop) points.push_back(vec(p));
                loops.push_back(std::move(points));
            }
            j["loops"] = std::move(loops);
            break;
        }
    }
    return j;
}

/// The "direct" object (bake --direct; docs/engines.md, "Direct light").
Json directJson(const DirectLightSet& d, const std::vector<std::string>& visibility,
                const std::vector<std::string>& edges) {
    Json j;
    j["mode"] = directModeName(d.mode);
    switch (d.mode) {
        case DirectMode::Baked: j["meaning"] = "the textures hold all light, direct included"; break;
        case DirectMode::Runtime:
            j["meaning"] = "the textures hold indirect light only; add each listed light's direct light with your own "
                           "shadows (docs/engines.md)";
            break;
        case DirectMode::Occlusion:
            j["meaning"] = "the textures hold indirect light and the direct light of unlisted lights; add for each "
                           "listed light exact_irradiance(light, x, n) * visibility, visibility = its component of its "
                           "light_visibility texture sampled like the others (docs/engines.md)";
            break;
    }
    // shadow_edges.h, docs/shadow_visibility.md. The engine-size layouts export no ramp
    // textures: their lookup fetches the corners and computes each corner's ramp.
    const bool rampTextures =
        std::any_of(edges.begin(), edges.end(), [](const std::string& e) { return e.rfind("light_edge_ramp_", 0) == 0; });
    if (!edges.empty())
        j["shadow_edges"] = {{"textures", edges},
                             {"units", "cells (texel_spacing)"},
                             {"min_width", shortestFloat(shadow_edge::kMinWidth)},
                             {"lookup", rampTextures
                                            ? "sample distance d, width w, ramp r and visibility v of the light like the other "
                                              "textures; visibility = clamp(clamp(0.5 + d / max(w, min_width), 0, 1) + v - r, "
                                              "0, 1) (docs/shadow_visibility.md)"
                                            : "fetch distance d_c, width w_c and visibility v_c of the light at the 8 corner "
                                              "texels and blend them with the corners' normalised weights wt_c (trilinear, or "
                                              "the depth weights); with ramp(d, w) = clamp(0.5 + d / max(w, min_width), 0, 1): "
                                              "visibility = clamp(ramp(sum wt_c d_c, sum wt_c w_c) + sum wt_c (v_c - "
                                              "ramp(d_c, w_c)), 0, 1) (docs/engine_visibility.md)"}};
    // The second edge (shadow_edges.h, "A second edge" in docs/shadow_visibility.md).
    std::vector<std::string> strips;
    for (const std::string& e : edges)
        if (e.rfind("light_edge_strip_", 0) == 0) strips.push_back(e);
    if (!strips.empty())
        j["shadow_edges"]["strips"] = {
            {"textures", strips},
            {"components", "direction x, y, z (unit, from the node towards its nearest edge), far (cells; 0 = no strip)"},
            {"lookup", "where a corner of weight > 0 has far > 0, fetch the 8 corners: each such corner adds its weight times "
                       "its strip model at the point (t = dot(direction, offset from the corner in cells), s = sign(d), "
                       "before = ramp(s (|d| - t), w), beyond = ramp(s (t - far), w): s > 0 ? max : min of the two), the "
                       "others together their weight times ramp of their own blended d and w, plus every corner's "
                       "weight times (v_c - ramp(d_c, w_c)); elsewhere the lookup above (docs/shadow_visibility.md)"}};
    Json lights = Json::array();
    for (std::size_t i = 0; i < d.lights.size(); ++i) {
        Json light = lightJson(d.lights[i]);
        // Four lights share one RGBA visibility texture (visibilityTextures).
        if (d.hasVisibility() && i / 4 < visibility.size())
            light["visibility"] = {{"texture", visibility[i / 4]}, {"component", std::string(1, "rgba"[i % 4])}};
        lights.push_back(std::move(light));
    }
    j["lights"] = std::move(lights);
    return j;
}

/// The container's own object ("ktx2", "dds", "exr_atlas" or "raw"): its key and value.
std::pair<const char*, Json> containerJson(const ExportOptions& o, const TextureLattice& l) {
    switch (o.format) {
        case TextureFormat::Ktx2:
            return {"ktx2", {{"vkFormat", vkFormatOf(lightingTexelFormat(o.halfFloat))}, {"KTXorientation", "ruo"}, {"levels", 1}}};
        case TextureFormat::Dds:
            return {"dds", {{"dxgiFormat", dxgiFormatOf(lightingTexelFormat(o.halfFloat))},
                            {"resourceDimension", "TEXTURE3D"}, {"arraySize", 1}, {"mipLevels", 1}}};
        case TextureFormat::ExrAtlas: {
            const AtlasGrid g = atlasGrid(l.dims[2]);
            return {"exr_atlas", {{"columns", g.columns}, {"rows", g.rows}, {"slice_width", l.dims[0]},
                                  {"slice_height", l.dims[1]}, {"slices", l.dims[2]}, {"width", g.columns * l.dims[0]},
                                  {"height", g.rows * l.dims[1]},
                                  {"placement", "slice z is the tile at column z % columns, row z / columns (z = 0 top "
                                                "left); image row r of a tile holds texel row j = r; unused tiles are 0"}}};
        }
        case TextureFormat::Raw: return {"raw", {{"header_bytes", 0}}};
    }
    return {"raw", {{"header_bytes", 0}}};
}

/// The "textures" list: per texture its file, texel format, where its texels start and what
/// its four components hold.
Json texturesJson(const ManifestInput& in) {
    const ExportOptions& o = *in.options;
    Json list = Json::array();
    for (std::size_t t = 0; t < in.textures.size(); ++t) {
        const TextureDesc& d = in.textures[t];
        const TexelFormat f = in.texelFormats.at(t);
        Json j;
        j["name"] = d.name;
        j["file"] = in.fileNames.at(t);
        j["format"] = texelFormatName(f);
        j["bytes_per_texel"] = 4 * componentBytes(f);
        if (o.format == TextureFormat::Ktx2) j["vkFormat"] = vkFormatOf(f);
        if (o.format == TextureFormat::Dds) j["dxgiFormat"] = dxgiFormatOf(f);
        if (o.format != TextureFormat::ExrAtlas) j["data_offset"] = in.dataOffsets.at(t);
        j["components"] = d.components;
        list.push_back(std::move(j));
    }
    return list;
}

/// The lattice and how a world position maps to texture coordinates.
void addLattice(Json& m, const TextureLattice& l) {
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
    m["dims"] = ints3(l.dims);
    m["bounds_min"] = vec(l.lo);
    m["bounds_max"] = vec(l.hi);
    m["texel_spacing"] = vec(h);
    m["texel_points"] = "texel (i, j, k) holds the volume at bounds_min + texel_spacing * (i, j, k); between texel points "
                        "the volume is trilinear";
    m["uvw_scale"] = vec(scale);
    m["uvw_bias"] = vec(bias);
    m["uvw_formula"] = "uvw = x * uvw_scale + uvw_bias = ((x - bounds_min) / texel_spacing + 0.5) / dims (the half-texel "
                       "offset puts texel centres on the texel points)";
    m["sampler"] = {{"filter", "linear"}, {"address", "clamp-to-edge"}, {"mipmaps", false}, {"srgb", false}};
    m["texel_order"] = "RGBA per texel; x fastest, then y, then z (texel (i, j, k) at index i + dims[0] * (j + dims[1] * k))";
}

/// The SH constants the layouts' formulas name (sh.h, docs/format.md).
Json constantsJson() {
    return {{"A0", sh::kCosineLobe[0]}, {"A1", sh::kCosineLobe[1]}, {"A2", sh::kCosineLobe[2]},
            {"c0", 0.5 / std::sqrt(kPi)}, {"c1", std::sqrt(3.0 / (4.0 * kPi))}, {"c2", std::sqrt(15.0 / (4.0 * kPi))},
            {"c3", std::sqrt(5.0 / (16.0 * kPi))}, {"c4", std::sqrt(15.0 / (16.0 * kPi))}};
}

}  // namespace

std::string manifestJson(const ManifestInput& in) {
    const ExportOptions& o = *in.options;
    Json m;
    // Version 2: every texture states its own texel format (the depth textures are 8-bit unorm).
    m["vdblight_export_version"] = 2;
    m["volume_kind"] = in.volumeKind;
    m["format"] = formatName(o.format);
    m["layout"] = layoutName(o.layout);
    m["component_type"] = o.halfFloat ? "float16" : "float32";
    m["byte_order"] = "little-endian";
    addLattice(m, *in.lattice);
    m["irradiance"] = o.layout == ExportLayout::Basis ? in.basisFormula : std::string(irradianceFormula(o.layout));
    if (o.layout == ExportLayout::Basis) m["basis"] = in.basisKind;
    // An sh:N volume (N > 2; the default bake stores sh:4) in an SH order-2 layout: its bands
    // 0..2 (sh_truncate.h), which `vdblight query --sh-order 2` answers with.
    const bool shLayout = o.layout == ExportLayout::Sh2 || o.layout == ExportLayout::Sh2Packed || o.layout == ExportLayout::Sh1 ||
                          isCompactSh(o.layout);
    BasisDesc basis;
    basis.kind = in.basisKind;
    if (shLayout && basis.isRealSh() && !basis.isSh2() && basis.shOrder() != 2)
        m["truncated_from"] = {{"basis", in.basisKind},
                               {"kept", "bands 0..2 of the volume's SH (the projection onto them); vdblight query "
                                        "--sh-order 2 gives the same irradiance; export --layout basis holds every band"}};
    m["units"] = "irradiance in W/m^2 (or the scene's radiometric unit times sr); positions in scene units";
    m["constants"] = constantsJson();
    if (isCompactSh(o.layout)) m["compact_sh"] = compactShJson(o.layout);
    if (o.layout == ExportLayout::Bins) m["bins"] = binsJson(in);
    if (in.depth != 0) m["depth"] = depthJson(in);
    if (in.direct) m["direct"] = directJson(*in.direct, in.visibilityTextures, in.edgeTextures);
    auto [container, containerFields] = containerJson(o, *in.lattice);
    m[container] = std::move(containerFields);
    m["textures"] = texturesJson(in);
    try {
        return m.dump(2) + "\n";
    } catch (const nlohmann::json::type_error&) {  // a name from the volume's metadata that is not UTF-8
        throw FormatError("manifest.json: a texture, basis or volume name is not valid UTF-8");
    }
}

}  // namespace vdblight::exporter
