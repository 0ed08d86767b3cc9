// The GPU-driver check (issue 33, item 1): exports written by `vdblight export`, loaded as an
// engine loads them (3-D textures from the KTX2 / DDS bytes, the manifest's sampler) into a
// real OpenGL 4.5 driver (Mesa llvmpipe, headless through EGL), evaluated by the GLSL of
// docs/engine_layouts.md and docs/engine_visibility.md (read when the test runs) in a compute
// shader at 10 000 random points and normals, and compared with the library's query
// (`vdblight query`'s answer). Where no OpenGL context can be made the test fails; it never skips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>

#include "bar_scene.h"
#include "cli_util.h"
#include "gpu/doc_blocks.h"
#include "gpu/export_loader.h"
#include "gpu/gl_compute.h"
#include "gpu/layout_cases.h"
#include "test_util.h"
#include "basis/shadow_edges.h"
#include "query/bins_lookup.h"
#include "export/export_compact.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "volume/sh_truncate.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;
using namespace vdblight::gpu;

namespace {

constexpr int kPoints = 10000;

// Tolerance, relative to the irradiance scale of the texels a point blends (texelScale: the
// largest mean irradiance over the six axis normals at the eight texel points around it).
// - Half floats keep 11 significant bits: a stored value is rounded by at most half a step,
//   2^-12 = 2.4e-4 of itself (the step, 2^-11 = 4.9e-4).
// - E is a sum of terms f_t(n) * (blend of the corner texels of component t); the rounding
//   adds at most 2^-12 * sum_t |f_t(n)| * max_corner |v_t|. For light that is a non-negative
//   function of direction, the band-l terms are bounded by (2l + 1) times the band-0 term
//   (|Y_lm| <= sqrt((2l + 1) / 4 pi)), so that sum stays within a few times the mean
//   irradiance; the bound adds a factor of a few: about 1e-3.
// - llvmpipe's filter: measured by the float32 row (same formula, no half rounding); its
//   error stays far below the half rounding (figures in docs/engine_visibility.md).
// - The eight-weight depth blend and the bounded blend of the irradiance vectors are
//   Lipschitz in their texels with constants of order 1 at these points: same bound.
// - bins: E = sum_k w_k(d) (trilinear blend of bin k), w_k >= 0 summing to 1, so the rounding
//   is at most 2^-12 times the largest bin value blended; a bin (the irradiance facing its
//   direction) is at most the integral of L, at most 6 times the mean over the six axis
//   normals (|w_x| + |w_y| + |w_z| >= 1): 6 * 2^-12 = 1.5e-3.
// - Shadow edges and their strips (shadow_edges.h): the ramp's slope, 1 / kMinWidth = 16 per
//   cell, multiplies the rounding of a distance, a far side (|d|, far <= 4: 2^-12 * 4 = 1e-3
//   cells) or of t = direction . offset (2^-12 * 3 = 7e-4 cells), but only inside the ramp's
//   band, 1/16 cell around an edge: there the visibility may be off by up to ~0.03 of the light's
//   term, outside it not at all (the ramp is flat). The rows bound what they measure instead:
//   few of the 10 000 points fall in a band (edges row 4.1e-4, strips row 6.5e-4 at worst).
// 2e-3 leaves a factor of about 2 over the worst point measured on any row.
constexpr double kTolerance = 2e-3;

// Small bakes of the default scene (a Cornell box with one polygon luminaire): a few hundred
// nodes and few rays, so that every row runs in about a second. Each is baked once per
// process, when a row first needs it.
const std::map<std::string, std::string>& bakeOptions() {
    static const std::map<std::string, std::string> options = {
        {"sh4.vdb", "--resolution 5 --rays 32 --bounces 2 --no-depth-moments --direct baked"},
        {"sh4_bilevel.vdb", "--resolution 4 --rays 32 --bounces 2 --no-depth-moments --direct baked --layout bilevel --refine 2"},
        {"sh4_bilevel_depth.vdb", "--resolution 6 --rays 32 --bounces 2 --depth-moments --direct baked --layout bilevel --refine 2"},
        {"sh4_depth.vdb", "--resolution 5 --rays 32 --bounces 2 --depth-moments --direct baked"},
        {"occlusion.vdb", "--resolution 5 --rays 32 --bounces 2 --no-depth-moments --direct occlusion --no-shadow-edges"},
        {"occlusion_edges.vdb", "--resolution 5 --rays 32 --bounces 2 --no-depth-moments --direct occlusion"},
        {"default_kind.vdb", "--resolution 5 --rays 32 --bounces 2 --depth-moments --direct occlusion"},
        {"photons.vdb", "--method photons --photons 20000 --resolution 5 --no-depth-moments"},
        {"bins4.vdb", "--basis bins:4 --resolution 5 --rays 32 --bounces 2 --no-depth-moments --direct baked"},
        // bins:3 (18 textures): with the 3 depth textures bins:4 would need 35 samplers, over
        // llvmpipe's 32 per compute shader.
        {"bins3_depth.vdb", "--basis bins:3 --resolution 5 --rays 32 --bounces 2 --depth-moments --direct baked"},
        {"bins4_bilevel.vdb", "--basis bins:4 --resolution 4 --rays 32 --bounces 2 --no-depth-moments --direct baked --layout bilevel --refine 2"},
        {"photons_compact.vdb", "--method photons --photons 20000 --resolution 5 --no-depth-moments --compact"},
        // Not the Cornell box: barScene's thin shadow, a strip narrower than a cell (shadow edges' second edge).
        {"strips.vdb", "--bounds -0.5,0,-0.5,0.5,0.4,0.5 --resolution 9 --rays 32 --bounces 2 --no-depth-moments --direct occlusion"},
    };
    return options;
}

class GpuExport : public ::testing::TestWithParam<std::size_t> {
protected:
    static void TearDownTestSuite() { dir_.reset(); }

    static std::string bake(const std::string& name) {
        if (!dir_) dir_ = std::make_unique<test::TempDir>();
        const std::string path = dir_->file(name);
        if (!std::filesystem::exists(path)) {
            std::string log;
            const std::string scene = name == "strips.vdb" ? " " + test::barScene(*dir_) : "";
            if (test::runCommand(test::cliPath() + " bake -q -o " + path + " " + bakeOptions().at(name) + scene, &log) != 0)
                throw std::runtime_error("bake of " + name + " failed: " + log);
        }
        return path;
    }
    static std::string exportDir(const std::string& name) { return dir_->file(name); }

private:
    static inline std::unique_ptr<test::TempDir> dir_;
};

// Random points in the node box and a margin of 10 % outside it (clamp-to-edge must give the
// query's clamping), random unit normals; float, as an engine holds them.
void randomPoints(const Manifest& m, std::vector<float>& x, std::vector<float>& n) {
    Rng rng(33);
    for (int i = 0; i < kPoints; ++i) {
        for (int a = 0; a < 3; ++a) {
            const float size = m.boundsMax[a] - m.boundsMin[a];
            x.push_back(m.boundsMin[a] - 0.1f * size + 1.2f * size * rng.uniform());
        }
        const Vec3f d = uniformSphere(rng.uniform(), rng.uniform());
        n.insert(n.end(), {d.x, d.y, d.z});
    }
}

Rgb clampedQuery(const IrradianceQuery& q, const Vec3f& x, const Vec3f& n) {
    const Rgb e = q.irradiance(x, n);  // `vdblight query` clamps SH ringing below 0
    return Rgb(std::max(e.x, 0.0f), std::max(e.y, 0.0f), std::max(e.z, 0.0f));
}


// Every sampler the shader reads must have a texture: an unbound one reads unit 0 silently.
void expectEverySamplerBound(const ComputeProgram& program, const Bindings& bindings) {
    GLint count = 0;
    glGetProgramiv(program.id(), GL_ACTIVE_UNIFORMS, &count);
    for (GLint u = 0; u < count; ++u) {
        char name[256];
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(program.id(), GLuint(u), sizeof(name), nullptr, &size, &type, name);
        if (type != GL_SAMPLER_3D) continue;
        std::string base(name);
        if (base.size() > 3 && base.compare(base.size() - 3, 3, "[0]") == 0) base.resize(base.size() - 3);
        for (GLint k = 0; k < size; ++k) {
            const std::string element = size > 1 || base != name ? base + "[" + std::to_string(k) + "]" : base;
            if (program.uniform(element) == -1) continue;  // an element the shader never reads
            const bool bound = std::any_of(bindings.begin(), bindings.end(), [&](const auto& b) { return b.first == element; });
            EXPECT_TRUE(bound) << "the shader reads sampler " << element << " but no texture is bound to it";
        }
    }
}

// Binds the row's textures and the manifest's uniforms (those the shader uses).
void bindExport(const LayoutCase& c, const Manifest& manifest, const ComputeProgram& program,
                const std::map<std::string, std::unique_ptr<Texture3D>>& textures) {
    glUseProgram(program.id());
    const Bindings bindings = c.bind(manifest);
    ASSERT_FALSE(bindings.empty());
    for (std::size_t unit = 0; unit < bindings.size(); ++unit) {
        const auto& [sampler, texture] = bindings[unit];
        ASSERT_TRUE(textures.count(texture)) << "the manifest has no texture " << texture;
        ASSERT_NE(program.uniform(sampler), -1) << "the shader reads no sampler " << sampler;
        glActiveTexture(GL_TEXTURE0 + GLenum(unit));
        glBindTexture(GL_TEXTURE_3D, textures.at(texture)->id);
        glUniform1i(program.uniform(sampler), GLint(unit));
    }
    expectEverySamplerBound(program, bindings);
    const auto setVec = [&](const char* name, const std::array<float, 3>& v) {
        if (program.uniform(name) != -1) glUniform3f(program.uniform(name), v[0], v[1], v[2]);
    };
    setVec("uvwScale", manifest.uvwScale);
    setVec("uvwBias", manifest.uvwBias);
    setVec("boundsMin", manifest.boundsMin);
    setVec("texelSpacing", manifest.texelSpacing);
    if (program.uniform("dims") != -1) glUniform3i(program.uniform("dims"), manifest.dims[0], manifest.dims[1], manifest.dims[2]);
    if (c.setUniforms) c.setUniforms(manifest, program);
    checkGl("setting the uniforms");
}

// The irradiance scale the stored values of point x are relative to: per channel, the
// largest over the eight texel points around x of the mean irradiance over the six axis
// normals (kTolerance says why).
Rgb texelScale(const IrradianceQuery& q, const Manifest& m, const Vec3f& x) {
    int i0[3];
    for (int a = 0; a < 3; ++a) {
        const float g = std::clamp(((&x.x)[a] - m.boundsMin[a]) / m.texelSpacing[a], 0.0f, float(m.dims[a] - 1));
        i0[a] = std::min(int(g), std::max(m.dims[a] - 2, 0));
    }
    Rgb scale(0, 0, 0);
    for (int k = 0; k < 8; ++k) {
        Vec3f corner;
        for (int a = 0; a < 3; ++a)
            (&corner.x)[a] = m.boundsMin[a] + m.texelSpacing[a] * float(std::min(i0[a] + ((k >> a) & 1), m.dims[a] - 1));
        Rgb mean(0, 0, 0);
        for (int a = 0; a < 6; ++a) {
            Vec3f axis(0, 0, 0);
            (&axis.x)[a / 2] = a % 2 ? -1.0f : 1.0f;
            mean += clampedQuery(q, corner, axis) * (1.0f / 6.0f);
        }
        scale = Rgb(std::max(scale.x, mean.x), std::max(scale.y, mean.y), std::max(scale.z, mean.z));
    }
    return scale;
}

double relativeError(const Rgb& got, const Rgb& want, const Rgb& scale) {
    double e = 0;
    for (int ch = 0; ch < 3; ++ch)
        e = std::max(e, std::abs(double((&got.x)[ch]) - (&want.x)[ch]) /
                            std::max({double(std::abs((&want.x)[ch])), double((&scale.x)[ch]), 1e-30}));
    return e;
}

// sh1-16 / sh2-32: the query of what the textures decode to against the query of the bands
// they hold, relative to the same texel scale, within the row's 8-bit bound (layout_cases.cpp).
void expectQuantisationWithinBound(const LayoutCase& c, const Manifest& m, const IrradianceQuery& bands,
                                   const IrradianceQuery& decoded, const std::vector<float>& x, const std::vector<float>& n) {
    double worst = 0, sum = 0;
    int worstAt = 0;
    for (int i = 0; i < kPoints; ++i) {
        const Vec3f p(x[3 * i], x[3 * i + 1], x[3 * i + 2]), d(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        const double e = relativeError(clampedQuery(decoded, p, d), clampedQuery(bands, p, d), texelScale(bands, m, p));
        sum += e;
        if (e > worst) worst = e, worstAt = i;
    }
    const int i = worstAt;
    std::printf("[%s] 8-bit quantisation (decoded volume's query vs bands 0..%d): max relative error %.3g (bound %.3g) "
                "at x=(%.4f, %.4f, %.4f) n=(%.4f, %.4f, %.4f); mean %.3g\n",
                c.name, c.shOrder, worst, c.quantisation, x[3 * i], x[3 * i + 1], x[3 * i + 2], n[3 * i], n[3 * i + 1],
                n[3 * i + 2], sum / kPoints);
    EXPECT_LE(worst, c.quantisation) << c.name << ": the 8-bit round trip exceeds the documented bound";
    EXPECT_GT(worst, kTolerance) << c.name << ": no 8-bit rounding visible (are the textures 8-bit?)";
}

}  // namespace

TEST_P(GpuExport, DocGlslOnLlvmpipeMatchesQuery) {
    const LayoutCase& c = layoutCases().at(GetParam());
    std::unique_ptr<GlContext> gl;
    try {
        gl = std::make_unique<GlContext>();
    } catch (const GlError& e) {
        FAIL() << e.what();
    }
    std::printf("[%s] %s\n", c.name, gl->describe().c_str());

    const std::string volume = bake(c.volume);
    const std::string out = exportDir(std::string("export_") + std::to_string(GetParam()));
    std::string log;
    ASSERT_EQ(test::runCommand(test::cliPath() + " export -q " + volume + " -o " + out + " " + c.exportArgs, &log), 0) << log;
    const Manifest manifest = readManifest(out);
    const auto textures = loadTextures(manifest, out);
    // The engine pages' blocks and those of docs/shadow_visibility.md (the shadow edges' row).
    std::vector<std::string> blocks = fencedBlocks(readEngineDocs(), "glsl");
    for (std::string& b : fencedBlocks(readDoc("shadow_visibility.md"), "glsl")) blocks.push_back(std::move(b));
    const ComputeProgram program(computeShader(c, manifest, blocks));
    bindExport(c, manifest, program, textures);
    if (HasFatalFailure()) return;

    std::vector<float> x, n;
    randomPoints(manifest, x, n);
    const std::vector<float> gpu = runOverPoints(program, x, n);

    const Volume stored = readVolume(volume);
    const Volume bands = c.shOrder ? truncateSh(stored, c.shOrder) : stored;
    // sh1-16 / sh2-32: what the 8-bit textures decode to (their quantisation is checked below).
    const Volume v = c.compactSh ? compactShRoundTrip(stored, *c.compactSh) : bands;
    const IrradianceQuery query(v);
    const IrradianceQuery unweighted(v, OutsidePolicy::Clamp, false);
    EXPECT_EQ(query.depthWeighted(), c.depthWeighted);
    // bins: the nearest bin alone, to prove that the four-bin blend is what the shader matches.
    const bool bins = manifest.root.value("layout", "") == "bins";
    const std::unique_ptr<IrradianceQuery> nearestBin =
        bins ? std::make_unique<IrradianceQuery>(std::make_unique<BinsLookup>(v, OutsidePolicy::Clamp, false), "bins") : nullptr;
    // Shadow edges: the same volume without them, to prove that the rows exercise them.
    const bool edges = !v.levels[0].lightShadowEdges.empty();
    Volume withoutEdges = edges ? v : Volume();
    for (VolumeLevel& level : withoutEdges.levels) level.lightShadowEdges.clear();
    const std::unique_ptr<IrradianceQuery> noEdges = edges ? std::make_unique<IrradianceQuery>(withoutEdges) : nullptr;
    // The second edge, where the export carries it: the same volume with one edge per node.
    const bool strips = manifest.root.contains("/direct/shadow_edges/strips"_json_pointer);
    Volume oneEdge = strips ? v : Volume();
    for (std::size_t k = shadow_edge::kFar; strips && k < oneEdge.levels[0].lightShadowEdges.size(); k += shadow_edge::kFloatsPerLight)
        oneEdge.levels[0].lightShadowEdges[k] = 0.0f;
    const std::unique_ptr<IrradianceQuery> noStrips = strips ? std::make_unique<IrradianceQuery>(oneEdge) : nullptr;
    double worst = 0;
    int worstAt = 0, weightsMatter = 0, blendMatters = 0, edgesMatter = 0, stripsMatter = 0;
    std::vector<double> errors;
    for (int i = 0; i < kPoints; ++i) {
        const Vec3f p(x[3 * i], x[3 * i + 1], x[3 * i + 2]), d(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        const Rgb want = clampedQuery(query, p, d), got(gpu[3 * i], gpu[3 * i + 1], gpu[3 * i + 2]);
        const Rgb scale = texelScale(query, manifest, p);
        errors.push_back(relativeError(got, want, scale));
        if (errors.back() > worst) worst = errors.back(), worstAt = i;
        if (c.depthWeighted && relativeError(clampedQuery(unweighted, p, d), want, scale) > 10 * kTolerance) ++weightsMatter;
        if (bins && relativeError(clampedQuery(*nearestBin, p, d), want, scale) > 10 * kTolerance) ++blendMatters;
        if (edges && relativeError(clampedQuery(*noEdges, p, d), want, scale) > 10 * kTolerance) ++edgesMatter;
        if (strips && relativeError(clampedQuery(*noStrips, p, d), want, scale) > 10 * kTolerance) ++stripsMatter;
    }
    std::sort(errors.begin(), errors.end());
    const int i = worstAt;
    const Vec3f p(x[3 * i], x[3 * i + 1], x[3 * i + 2]), d(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
    const Rgb want = clampedQuery(query, p, d);
    std::printf("[%s] %d points: max relative error %.3g (tolerance %.3g) at x=(%.4f, %.4f, %.4f) n=(%.4f, %.4f, %.4f): "
                "got (%.6g, %.6g, %.6g) want (%.6g, %.6g, %.6g); p99 %.3g\n",
                c.name, kPoints, worst, kTolerance, p.x, p.y, p.z, d.x, d.y, d.z, gpu[3 * i], gpu[3 * i + 1], gpu[3 * i + 2],
                want.x, want.y, want.z, errors[std::size_t(0.99 * kPoints)]);
    EXPECT_LE(worst, kTolerance) << c.name;
    if (c.compactSh) expectQuantisationWithinBound(c, manifest, IrradianceQuery(bands), query, x, n);
    if (bins) {
        std::printf("[%s] the nearest bin alone differs by more than 10x the tolerance at %d points\n", c.name, blendMatters);
        EXPECT_GT(blendMatters, kPoints / 10) << "the four-bin blend changes too few points to prove it";
    }
    if (edges) {
        std::printf("[%s] the lookup without the shadow edges differs by more than 10x the tolerance at %d points\n", c.name,
                    edgesMatter);
        EXPECT_GT(edgesMatter, kPoints / 100) << "the shadow edges change too few points to prove them";
    }
    if (strips) {
        std::printf("[%s] the lookup with one edge per node differs by more than 10x the tolerance at %d points\n", c.name,
                    stripsMatter);
        EXPECT_GT(stripsMatter, kPoints / 100) << "the second edges change too few points to prove them";
    }
    if (c.depthWeighted) {
        std::printf("[%s] the unweighted lookup differs by more than 10x the tolerance at %d points\n", c.name, weightsMatter);
        EXPECT_GT(weightsMatter, kPoints / 100) << "the depth weights change too few points to prove the blend";
    }
}

INSTANTIATE_TEST_SUITE_P(EveryLayout, GpuExport, ::testing::Range<std::size_t>(0, layoutCases().size()));
