#include "layout_cases.h"

#include <cctype>
#include <stdexcept>

#include "doc_blocks.h"

namespace vdblight::gpu {
namespace {

bool startsWith(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

// The k-th manifest texture whose name starts with `prefix` -> sampler `array[k]`.
Bindings inOrder(const Manifest& m, const std::string& prefix, const std::string& array, Bindings b = {}) {
    int k = 0;
    for (const ManifestTexture& t : m.textures)
        if (startsWith(t.name, prefix)) b.emplace_back(array + "[" + std::to_string(k++) + "]", t.name);
    return b;
}

// The textures the doc's sh2-packed / sh1 GLSL names as they are named in the manifest.
Bindings packedSh(const Manifest& m) {
    Bindings b;
    for (const ManifestTexture& t : m.textures)
        if (startsWith(t.name, "shA") || startsWith(t.name, "shB") || t.name == "shC") b.emplace_back(t.name, t.name);
    return b;
}

// packedSh, plus light 0's visibility and shadow-edge textures (the doc's
// vdblightIrradianceOcclusionEdges).
Bindings packedShWithEdges(const Manifest& m) {
    Bindings b = packedSh(m);
    b.emplace_back("lightVisibility0", "light_visibility_0_0");
    b.emplace_back("lightEdgeDistance0", "light_edge_distance_0_0");
    b.emplace_back("lightEdgeWidth0", "light_edge_width_0_0");
    b.emplace_back("lightEdgeRamp0", "light_edge_ramp_0_0");
    return b;
}

// depth_x -> depthX, ... (the doc's visibility-aware GLSL).
Bindings withDepth(Bindings b) {
    for (const char* axis : {"x", "y", "z"})
        b.emplace_back(std::string("depth") + char(std::toupper(axis[0])), std::string("depth_") + axis);
    return b;
}

// The one listed light of an occlusion export: the doc's occlusion GLSL takes one polygon.
void setPolygonLight(const Manifest& m, const ComputeProgram& p) {
    const nlohmann::json lights = m.root.value("/direct/lights"_json_pointer, nlohmann::json::array());
    if (lights.size() != 1) throw std::runtime_error("the occlusion row needs one listed light");
    const nlohmann::json& light = lights[0];
    if (light.value("kind", "") != "polygon" || light.value("two_sided", true) || light.value("loops", nlohmann::json()).size() != 1 ||
        light.value("/visibility/component"_json_pointer, "") != "r")
        throw std::runtime_error("the occlusion row needs a one-sided polygon light with visibility in component r");
    const auto vec = [](const nlohmann::json& v) { return std::array<float, 3>{v.at(0).get<float>(), v.at(1).get<float>(), v.at(2).get<float>()}; };
    const nlohmann::json& loop = light.at("loops").at(0);
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const auto v = vec(loop[i]);
        glUniform3f(p.uniform("lightVertices[" + std::to_string(i) + "]"), v[0], v[1], v[2]);
    }
    glUniform1i(p.uniform("lightVertexCount"), GLint(loop.size()));
    const auto n = vec(light.at("normal")), l = vec(light.at("radiance"));
    glUniform3f(p.uniform("lightNormal"), n[0], n[1], n[2]);
    glUniform3f(p.uniform("lightRadiance"), l[0], l[1], l[2]);
}

// VDBLIGHT_SH_ORDER = the N of the manifest's basis (sh2: 2, sh:N: N), as the doc says.
std::string shOrderDefine(const Manifest& m) {
    if (!m.root.contains("basis")) throw std::runtime_error("a basis export's manifest has no 'basis'");
    const std::string b = m.root.at("basis").get<std::string>();
    const int order = b == "sh2" ? 2 : startsWith(b, "sh:") ? std::stoi(b.substr(3)) : 0;
    if (order < 1) throw std::runtime_error("basis '" + b + "' is not real SH");
    return "#define VDBLIGHT_SH_ORDER " + std::to_string(order) + "\n";
}

const char* const kPacked = "vec3 vdblightIrradiance(";
const char* const kCallPacked = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradiance(x, n); }\n";
const char* const kCallSh2 =
    "uniform sampler3D sh2[9];\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceSh2(sh2, x * uvwScale + uvwBias, n); }\n";
const char* const kCallShN = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceShN(x, n); }\n";
const char* const kCallVisible = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceVisible(x, n); }\n";
const char* const kCallVectors =
    "uniform sampler3D iv[18];\n"
    "uniform vec3 uvwScale, uvwBias;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceVectors(iv, x * uvwScale + uvwBias, n); }\n";
const char* const kCallCompact =
    "uniform sampler3D colour[6], dirs[6];\n"
    "uniform vec3 uvwScale, uvwBias;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceCompact(colour, dirs, x * uvwScale + uvwBias, n); }\n";
const char* const kCallOcclusion =
    "uniform vec3 lightVertices[VDBLIGHT_MAX_VERTS], lightNormal, lightRadiance;\n"
    "uniform int lightVertexCount;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) {\n"
    "    return vdblightIrradianceOcclusion(x, n, lightVertices, lightVertexCount, lightNormal, lightRadiance);\n"
    "}\n";

// bins: VDBLIGHT_BINS_R = the manifest's bins.resolution, as the doc says.
std::string binsResolutionDefine(const Manifest& m) {
    const int r = m.root.value("/bins/resolution"_json_pointer, 0);
    if (r < 1) throw std::runtime_error("a bins export's manifest has no bins.resolution");
    return "#define VDBLIGHT_BINS_R " + std::to_string(r) + "\n";
}

// bins[c] = texture c = h R^2 + iv R + iu, named bin_h<h>_u<iu>_v<iv> (the doc's index, not
// the manifest's order, so that a wrong index in either is seen).
Bindings binTextures(const Manifest& m) {
    const int r = m.root.value("/bins/resolution"_json_pointer, 0);
    Bindings b;
    for (int c = 0; c < 2 * r * r; ++c)
        b.emplace_back("bins[" + std::to_string(c) + "]", "bin_h" + std::to_string(c / (r * r)) + "_u" + std::to_string(c % r) +
                                                              "_v" + std::to_string(c % (r * r) / r));
    return b;
}

const char* const kCallBins =
    "uniform sampler3D bins[2 * R * R];\n"
    "uniform vec3 uvwScale, uvwBias;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceBins(bins, x * uvwScale + uvwBias, n); }\n";

// bins with depth moments (docs/engine_visibility.md): the corners weighted by depth.
const char* const kCallBinsVisible =
    "uniform sampler3D bins[2 * R * R];\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceBinsVisible(bins, x, n); }\n";

// The shadow edges' GLSL of docs/shadow_visibility.md (the same light uniforms).
const char* const kCallOcclusionEdges =
    "uniform vec3 lightVertices[VDBLIGHT_MAX_VERTS], lightNormal, lightRadiance;\n"
    "uniform int lightVertexCount;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) {\n"
    "    return vdblightIrradianceOcclusionEdges(x, n, lightVertices, lightVertexCount, lightNormal, lightRadiance);\n"
    "}\n";

// The second edge's GLSL of docs/shadow_visibility.md (the same light uniforms).
const char* const kCallOcclusionStrips =
    "uniform vec3 lightVertices[VDBLIGHT_MAX_VERTS], lightNormal, lightRadiance;\n"
    "uniform int lightVertexCount;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) {\n"
    "    return vdblightIrradianceOcclusionStrips(x, n, lightVertices, lightVertexCount, lightNormal, lightRadiance);\n"
    "}\n";

// The sh1-16 / sh2-32 textures, named as the doc's GLSL names its samplers.
Bindings compactShTextures(const Manifest& m) {
    Bindings b;
    for (const ManifestTexture& t : m.textures)
        if (startsWith(t.name, "L0_") || startsWith(t.name, "L1") || startsWith(t.name, "L2_")) b.emplace_back(t.name, t.name);
    return b;
}

const char* const kCallSh2x32 = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceSh2x32(x, n); }\n";
const char* const kCallSh1x16 = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceSh1x16(x, n); }\n";

// sh2-32 / sh1-16 with depth moments and / or listed lights: the doc's switches, from the manifest.
std::string engineSizeDefines(const Manifest& m) {
    std::string s;
    if (m.root.value("layout", "") == "sh1-16") s += "#define VDBLIGHT_SH1_16\n";
    if (m.root.value("/depth/exported"_json_pointer, false)) s += "#define VDBLIGHT_DEPTH_MOMENTS\n";
    if (m.root.value("/direct/mode"_json_pointer, "") == "occlusion") s += "#define VDBLIGHT_LIGHT_VISIBILITY\n";
    if (m.root.contains("/direct/shadow_edges"_json_pointer)) s += "#define VDBLIGHT_SHADOW_EDGES\n";
    if (m.root.contains("/direct/shadow_edges/strips"_json_pointer)) s += "#define VDBLIGHT_SHADOW_STRIPS\n";
    return s;
}

Bindings engineSizeWithExtras(const Manifest& m) {
    Bindings b = compactShTextures(m);
    if (m.root.value("/depth/exported"_json_pointer, false)) b = withDepth(b);
    if (m.root.value("/direct/mode"_json_pointer, "") == "occlusion") b.emplace_back("lightVisibility0", "light_visibility_0_0");
    if (m.root.contains("/direct/shadow_edges"_json_pointer)) {
        // The shader computes each corner's ramp: these layouts export no ramp texture.
        const bool strips = m.root.contains("/direct/shadow_edges/strips"_json_pointer);
        const nlohmann::json expected = strips ? nlohmann::json{"light_edge_distance_0_0", "light_edge_width_0_0", "light_edge_strip_0"}
                                               : nlohmann::json{"light_edge_distance_0_0", "light_edge_width_0_0"};
        if (m.root.at("/direct/shadow_edges/textures"_json_pointer) != expected)
            throw std::runtime_error("an engine-size export's shadow_edges.textures should be " + expected.dump());
        b.emplace_back("lightEdgeDistance0", "light_edge_distance_0_0");
        b.emplace_back("lightEdgeWidth0", "light_edge_width_0_0");
        if (strips) b.emplace_back("lightEdgeStrip0", "light_edge_strip_0");
    }
    return b;
}

const char* const kDepthWeight = "float vdblightDepthWeight(";
const char* const kExactLights = "vec3 vdblightPolygonIrradiance(";
const char* const kEngineSizeBlend = "vec3 vdblightEngineSizeBlend(";
const char* const kCallEngineSize = "vec3 vdblightCheck(vec3 x, vec3 n) { return vdblightIrradianceEngineSize(x, n); }\n";
const char* const kCallEngineSizeOcclusion =
    "uniform vec3 lightVertices[VDBLIGHT_MAX_VERTS], lightNormal, lightRadiance;\n"
    "uniform int lightVertexCount;\n"
    "vec3 vdblightCheck(vec3 x, vec3 n) {\n"
    "    return vdblightIrradianceEngineSizeOcclusion(x, n, lightVertices, lightVertexCount, lightNormal, lightRadiance);\n"
    "}\n";

// The 8-bit rounding bound of docs/engine_layouts.md ("sh2-32", "Rounding error") as a fraction of
// the texels' L0 irradiance a (<= the row's scale: the mean of E over the six axis normals is
// a for bands 0..2): max over unit n of the decoded terms' ranges / 510, 2.22 % for sh2-32
// and 4 sqrt(3) / 510 = 1.36 % for sh1-16, plus the half-float tolerance of the row for a
// (rounded to half) and the terms it scales.
constexpr double kSh2x32Quantisation = 0.0222 + 2e-3;
constexpr double kSh1x16Quantisation = 0.0136 + 2e-3;
// Rows with a listed light add its 8-bit visibility: at most 1/510 of the light's exact
// irradiance at (x, n), which is at most 6 times its mean over the six axis normals
// (|n.x| + |n.y| + |n.z| >= 1 for any direction it comes from), a share of the row's scale.
constexpr double kVisibilityQuantisation = 6.0 / 510;

}  // namespace

const std::vector<LayoutCase>& layoutCases() {
    static const std::vector<LayoutCase> cases = {
        {"sh2-packed (ktx2, half)", "sh4.vdb", "--format ktx2 --layout sh2-packed", {kPacked}, nullptr, kCallPacked, packedSh, 2},
        {"sh2-packed (dds, half)", "sh4.vdb", "--format dds --layout sh2-packed", {kPacked}, nullptr, kCallPacked, packedSh, 2},
        {"sh2-packed (ktx2, float)", "sh4.vdb", "--format ktx2 --layout sh2-packed --float", {kPacked}, nullptr, kCallPacked,
         packedSh, 2},
        {"sh1 (ktx2, half)", "sh4.vdb", "--format ktx2 --layout sh1", {kPacked}, [](const Manifest&) { return std::string("#define VDBLIGHT_SH1\n"); }, kCallPacked,
         packedSh, 1},
        {"sh2 (dds, half)", "sh4.vdb", "--format dds --layout sh2", {kPacked}, nullptr, kCallSh2,
         [](const Manifest& m) { return inOrder(m, "sh2_", "sh2"); }, 2},
        {"basis sh:4 (ktx2, half)", "sh4.vdb", "--format ktx2 --layout basis", {"vec3 vdblightIrradianceShN("},
         shOrderDefine, kCallShN, [](const Manifest& m) { return inOrder(m, "sh_l", "L"); }},
        {"sh2-packed, bilevel (ktx2, half)", "sh4_bilevel.vdb", "--format ktx2 --layout sh2-packed", {kPacked}, nullptr,
         kCallPacked, packedSh, 2},
        {"basis of an sh2 volume, bilevel (ktx2, half)", "sh4_bilevel.vdb", "--format ktx2 --layout basis",
         {"vec3 vdblightIrradianceShN("}, shOrderDefine, kCallShN,
         [](const Manifest& m) { return inOrder(m, "sh_l", "L"); }},
        {"sh2-packed + depth moments (ktx2, half; depth rgba8_unorm)", "sh4_depth.vdb", "--format ktx2 --layout sh2-packed",
         {kDepthWeight, "vec3 vdblightIrradianceVisible("}, nullptr, kCallVisible, [](const Manifest& m) { return withDepth(packedSh(m)); }, 2, true},
        {"sh2-packed + depth moments (dds, half; depth rgba8_unorm)", "sh4_depth.vdb", "--format dds --layout sh2-packed",
         {kDepthWeight, "vec3 vdblightIrradianceVisible("}, nullptr, kCallVisible, [](const Manifest& m) { return withDepth(packedSh(m)); }, 2, true},
        {"sh2-packed + depth moments, bilevel (ktx2, half; the finest lattice)", "sh4_bilevel_depth.vdb", "--format ktx2 --layout sh2-packed",
         {kDepthWeight, "vec3 vdblightIrradianceVisible("}, nullptr, kCallVisible, [](const Manifest& m) { return withDepth(packedSh(m)); }, 2, true},
        {"sh2-packed + --direct occlusion (ktx2, half)", "occlusion.vdb", "--format ktx2 --layout sh2-packed",
         {kPacked, kExactLights, "vec3 vdblightIrradianceOcclusion("}, nullptr, kCallOcclusion,
         [](const Manifest& m) {
             Bindings b = packedSh(m);
             b.emplace_back("lightVisibility0", "light_visibility_0_0");
             return b;
         },
         2, false, setPolygonLight},
        {"sh2-packed + --direct occlusion + shadow edges (ktx2, half)", "occlusion_edges.vdb", "--format ktx2 --layout sh2-packed",
         {kPacked, kExactLights, "vec3 vdblightIrradianceOcclusion(", "vec3 vdblightIrradianceOcclusionEdges("}, nullptr, kCallOcclusionEdges,
         packedShWithEdges,
         2, false, setPolygonLight},
        // The second edge (docs/shadow_visibility.md): a thin shadow, narrower than a cell.
        {"sh2-packed + --direct occlusion + shadow edges + strips (ktx2, half)", "strips.vdb", "--format ktx2 --layout sh2-packed",
         {kPacked, kExactLights, "vec3 vdblightIrradianceOcclusion(", "vec3 vdblightIrradianceOcclusionEdges(",
          "float vdblightStripModel(", "vec3 vdblightIrradianceOcclusionStrips("},
         nullptr, kCallOcclusionStrips,
         [](const Manifest& m) {
             Bindings b = packedShWithEdges(m);
             b.emplace_back("lightEdgeStrip0", "light_edge_strip_0");
             return b;
         },
         2, false, setPolygonLight},
        {"vectors (ktx2, half)", "photons.vdb", "--format ktx2 --layout vectors", {"vec3 vdblightIrradianceVectors("}, nullptr,
         kCallVectors, [](const Manifest& m) { return inOrder(m, "iv_", "iv"); }},
        {"compact (ktx2, half)", "photons_compact.vdb", "--format ktx2 --layout compact",
         {"vec3 vdblightIrradianceCompact("}, nullptr, kCallCompact,
         [](const Manifest& m) {
             Bindings b;
             const char* dirs[6] = {"xpos", "xneg", "ypos", "yneg", "zpos", "zneg"};
             for (int k = 0; k < 6; ++k) {
                 b.emplace_back("colour[" + std::to_string(k) + "]", std::string("ivc_") + dirs[k] + "_colour");
                 b.emplace_back("dirs[" + std::to_string(k) + "]", std::string("ivc_") + dirs[k] + "_dir");
             }
             return b;
         }},
        {"bins of a bins:4 volume (ktx2, half; the four-bin blend)", "bins4.vdb", "--format ktx2 --layout bins",
         {"vec3 vdblightIrradianceBins("}, binsResolutionDefine, kCallBins, binTextures},
        {"bins of a bilevel bins:4 volume (dds, half)", "bins4_bilevel.vdb", "--format dds --layout bins",
         {"vec3 vdblightIrradianceBins("}, binsResolutionDefine, kCallBins, binTextures},
        {"bins of a bins:3 volume with depth moments (ktx2, half; depth rgba8_unorm)", "bins3_depth.vdb", "--format ktx2 --layout bins",
         {"vec3 vdblightIrradianceBins(", kDepthWeight, "vec3 vdblightIrradianceBinsVisible("}, binsResolutionDefine, kCallBinsVisible,
         [](const Manifest& m) { return withDepth(binTextures(m)); }, 0, true},
        {"sh2-32 (ktx2; L0 half, rgba8_unorm)", "sh4.vdb", "--format ktx2 --layout sh2-32", {"vec3 vdblightIrradianceSh2x32("},
         nullptr, kCallSh2x32, compactShTextures, 2, false, nullptr, ExportLayout::Sh2x32, kSh2x32Quantisation},
        {"sh2-32 (dds; L0 half, rgba8_unorm)", "sh4.vdb", "--format dds --layout sh2-32", {"vec3 vdblightIrradianceSh2x32("},
         nullptr, kCallSh2x32, compactShTextures, 2, false, nullptr, ExportLayout::Sh2x32, kSh2x32Quantisation},
        {"sh1-16 (ktx2; L0 half, rgba8_unorm)", "sh4.vdb", "--format ktx2 --layout sh1-16", {"vec3 vdblightIrradianceSh1x16("},
         nullptr, kCallSh1x16, compactShTextures, 1, false, nullptr, ExportLayout::Sh1x16, kSh1x16Quantisation},
        {"sh2-32 + depth moments + --direct occlusion + shadow edges (ktx2; the default bake's kind, 64 B per probe)", "default_kind.vdb",
         "--format ktx2 --layout sh2-32", {"vec3 vdblightIrradianceSh2x32(", kDepthWeight, kExactLights, kEngineSizeBlend},
         engineSizeDefines, kCallEngineSizeOcclusion, engineSizeWithExtras, 2, true, setPolygonLight, ExportLayout::Sh2x32,
         kSh2x32Quantisation + kVisibilityQuantisation},
        // The second edge in the engine-size layouts (docs/engine_visibility.md, VDBLIGHT_SHADOW_STRIPS).
        {"sh2-32 + --direct occlusion + shadow edges + strips (ktx2; trilinear)", "strips.vdb", "--format ktx2 --layout sh2-32",
         {"vec3 vdblightIrradianceSh2x32(", kExactLights, "float vdblightStripModel(", kEngineSizeBlend}, engineSizeDefines,
         kCallEngineSizeOcclusion, engineSizeWithExtras, 2, false, setPolygonLight, ExportLayout::Sh2x32,
         kSh2x32Quantisation + kVisibilityQuantisation},
        {"sh1-16 + depth moments (dds)", "sh4_depth.vdb", "--format dds --layout sh1-16",
         {"vec3 vdblightIrradianceSh1x16(", kDepthWeight, kEngineSizeBlend}, engineSizeDefines, kCallEngineSize,
         engineSizeWithExtras, 1, true, nullptr, ExportLayout::Sh1x16, kSh1x16Quantisation},
        {"sh1-16 + --direct occlusion (ktx2; 8-bit visibility, trilinear)", "occlusion.vdb", "--format ktx2 --layout sh1-16",
         {"vec3 vdblightIrradianceSh1x16(", kExactLights, kEngineSizeBlend}, engineSizeDefines, kCallEngineSizeOcclusion,
         engineSizeWithExtras, 1, false, setPolygonLight, ExportLayout::Sh1x16, kSh1x16Quantisation + kVisibilityQuantisation},
        {"sh1-16 + --direct occlusion + shadow edges (dds; trilinear)", "occlusion_edges.vdb", "--format dds --layout sh1-16",
         {"vec3 vdblightIrradianceSh1x16(", kExactLights, kEngineSizeBlend}, engineSizeDefines, kCallEngineSizeOcclusion,
         engineSizeWithExtras, 1, false, setPolygonLight, ExportLayout::Sh1x16, kSh1x16Quantisation + kVisibilityQuantisation},
    };
    return cases;
}

std::string computeShader(const LayoutCase& c, const Manifest& m, const std::vector<std::string>& glslBlocks) {
    std::string s = "#version 450\n";
    if (c.before) s += c.before(m);
    for (const char* declaration : c.docDeclarations) s += blockDeclaring(glslBlocks, declaration);
    s += c.glue;
    s += "layout(local_size_x = 64) in;\n"
         "layout(std430, binding = 0) readonly buffer Points { vec4 points[]; };\n"
         "layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };\n"
         "layout(std430, binding = 2) writeonly buffer Results { vec4 results[]; };\n"
         "uniform uint pointCount;\n"
         "void main() {\n"
         "    uint i = gl_GlobalInvocationID.x;\n"
         "    if (i < pointCount) results[i] = vec4(vdblightCheck(points[i].xyz, normals[i].xyz), 0.0);\n"
         "}\n";
    return s;
}

}  // namespace vdblight::gpu
