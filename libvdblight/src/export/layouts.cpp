// Export layouts: which textures a layout writes and how nine SH order-2 radiance
// coefficients become their texels. The formulas are those of docs/engines.md.
#include <algorithm>
#include <cmath>

#include "compact_sh.h"
#include "export_internal.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "basis/sh.h"

namespace vdblight {

TextureFormat parseTextureFormat(const std::string& name) {
    if (name == "ktx2") return TextureFormat::Ktx2;
    if (name == "dds") return TextureFormat::Dds;
    if (name == "exr-atlas") return TextureFormat::ExrAtlas;
    if (name == "raw") return TextureFormat::Raw;
    throw ValueError("unknown export format '" + name + "' (choose ktx2, dds, exr-atlas, raw or vdb-preview)");
}

ExportLayout parseExportLayout(const std::string& name) {
    if (name == "sh2") return ExportLayout::Sh2;
    if (name == "sh2-packed") return ExportLayout::Sh2Packed;
    if (name == "sh1") return ExportLayout::Sh1;
    if (name == "sh1-16") return ExportLayout::Sh1x16;
    if (name == "sh2-32") return ExportLayout::Sh2x32;
    if (name == "vectors") return ExportLayout::Vectors;
    if (name == "compact") return ExportLayout::Compact;
    if (name == "bins") return ExportLayout::Bins;
    if (name == "basis") return ExportLayout::Basis;
    throw ValueError("unknown export layout '" + name + "' (choose sh2, sh2-packed, sh1, sh1-16, sh2-32, vectors, compact, bins or basis)");
}

const char* formatName(TextureFormat format) {
    switch (format) {
        case TextureFormat::Ktx2: return "ktx2";
        case TextureFormat::Dds: return "dds";
        case TextureFormat::ExrAtlas: return "exr-atlas";
        case TextureFormat::Raw: return "raw";
    }
    return "?";
}

const char* layoutName(ExportLayout layout) {
    switch (layout) {
        case ExportLayout::Sh2: return "sh2";
        case ExportLayout::Sh2Packed: return "sh2-packed";
        case ExportLayout::Sh1: return "sh1";
        case ExportLayout::Vectors: return "vectors";
        case ExportLayout::Compact: return "compact";
        case ExportLayout::Bins: return "bins";
        case ExportLayout::Basis: return "basis";
        case ExportLayout::Sh1x16: return "sh1-16";
        case ExportLayout::Sh2x32: return "sh2-32";
    }
    return "?";
}

namespace exporter {

namespace {

const char* const kRgb[3] = {"red", "green", "blue"};
// Direction names in irradiance_vectors.h order (as in the .vdb grid names).
const char* const kDirName[6] = {"xpos", "xneg", "ypos", "yneg", "zpos", "zneg"};

std::vector<TextureDesc> packedA(bool order2) {
    std::vector<TextureDesc> t;
    for (int c = 0; c < 3; ++c) {
        const std::string ch = kRgb[c];
        t.push_back({std::string("shA") + "rgb"[c],
                     {ch + ": A1*c1*L3 (coefficient of n.x)", ch + ": A1*c1*L1 (coefficient of n.y)",
                      ch + ": A1*c1*L2 (coefficient of n.z)", ch + (order2 ? ": A0*c0*L0 - A2*c3*L6 (constant term)" : ": A0*c0*L0 (constant term)")}});
    }
    return t;
}

double channel(const Rgb& c, int ch) { return ch == 0 ? c.x : (ch == 1 ? c.y : c.z); }
}  // namespace

std::vector<TextureDesc> layoutTextures(ExportLayout layout, int binResolution) {
    std::vector<TextureDesc> t;
    switch (layout) {
        case ExportLayout::Sh2:
            for (int j = 0; j < sh::kCoeffs; ++j) {
                const std::string L = "L" + std::to_string(j);
                t.push_back({std::string("sh2_") + sh::gridName(j),
                             {L + " red", L + " green", L + " blue", "unused (0)"}});
            }
            break;
        case ExportLayout::Sh1:
            t = packedA(false);
            break;
        case ExportLayout::Sh2Packed:
            t = packedA(true);
            for (int c = 0; c < 3; ++c) {
                const std::string ch = kRgb[c];
                t.push_back({std::string("shB") + "rgb"[c],
                             {ch + ": A2*c2*L4 (coefficient of n.x*n.y)", ch + ": A2*c2*L5 (coefficient of n.y*n.z)",
                              ch + ": 3*A2*c3*L6 (coefficient of n.z*n.z)", ch + ": A2*c2*L7 (coefficient of n.z*n.x)"}});
            }
            t.push_back({"shC",
                         {"red: A2*c4*L8 (coefficient of n.x^2 - n.y^2)", "green: A2*c4*L8", "blue: A2*c4*L8",
                          "unused (0)"}});
            break;
        case ExportLayout::Vectors:
            for (int d = 0; d < iv::kDirections; ++d)
                for (int c = 0; c < 3; ++c) {
                    const std::string what = std::string(kRgb[c]) + " irradiance vector I_" + kDirName[d];
                    t.push_back({std::string("iv_") + kDirName[d] + "_" + "rgb"[c],
                                 {what + " .x", what + " .y", what + " .z", "unused (0)"}});
                }
            break;
        case ExportLayout::Compact:
            for (int d = 0; d < iv::kDirections; ++d) {
                const std::string dir = kDirName[d];
                t.push_back({"ivc_" + dir + "_colour",
                             {"|I_" + dir + " red|", "|I_" + dir + " green|", "|I_" + dir + " blue|", "unused (0)"}});
                t.push_back({"ivc_" + dir + "_dir",
                             {"d.x", "d.y", "d.z: d = normalize(I_" + dir + " red + green + blue), 0 if that sum is 0",
                              "unused (0)"}});
            }
            break;
        case ExportLayout::Bins:
            for (int c = 0; c < 2 * binResolution * binResolution; ++c) {
                const std::string what = "bin " + std::to_string(c) + " (" + bins::channelName(binResolution, c) + ")";
                t.push_back({bins::channelName(binResolution, c), {what + " red", what + " green", what + " blue", "unused (0)"}});
            }
            break;
        case ExportLayout::Basis:
            throw FormatError("layout 'basis' takes its textures from the volume's basis (basisTextures)");
        case ExportLayout::Sh1x16:
        case ExportLayout::Sh2x32:
            t = compactShTextures(layout);
            break;
    }
    return t;
}

void packTexel(ExportLayout layout, const Rgb L[9], float* out) {
    if (isCompactSh(layout)) {
        packCompactTexel(layout, L, out);
        return;
    }
    if (layout == ExportLayout::Sh2) {
        for (int j = 0; j < sh::kCoeffs; ++j) {
            out[4 * j + 0] = L[j].x;
            out[4 * j + 1] = L[j].y;
            out[4 * j + 2] = L[j].z;
            out[4 * j + 3] = 0.0f;
        }
        return;
    }
    const bool order2 = layout == ExportLayout::Sh2Packed;
    for (int c = 0; c < 3; ++c) {
        float* a = out + 4 * c;
        a[0] = float(kA1 * kC1 * channel(L[3], c));
        a[1] = float(kA1 * kC1 * channel(L[1], c));
        a[2] = float(kA1 * kC1 * channel(L[2], c));
        a[3] = float(kA0 * kC0 * channel(L[0], c) - (order2 ? kA2 * kC3 * channel(L[6], c) : 0.0));
        if (!order2) continue;
        float* b = out + 12 + 4 * c;
        b[0] = float(kA2 * kC2 * channel(L[4], c));
        b[1] = float(kA2 * kC2 * channel(L[5], c));
        b[2] = float(3.0 * kA2 * kC3 * channel(L[6], c));
        b[3] = float(kA2 * kC2 * channel(L[7], c));
        out[24 + c] = float(kA2 * kC4 * channel(L[8], c));
    }
    if (order2) out[27] = 0.0f;
}

bool layoutIsSh(ExportLayout layout) {
    return layout != ExportLayout::Vectors && layout != ExportLayout::Compact && layout != ExportLayout::Bins &&
           layout != ExportLayout::Basis;
}

std::vector<TextureDesc> basisTextures(const Basis& basis) {
    std::vector<TextureDesc> out;
    for (const BasisTexture& t : basis.textures()) out.push_back({t.name, t.components});
    return out;
}

void packVectorTexel(ExportLayout layout, const float v[54], float* out) {
    for (int d = 0; d < iv::kDirections; ++d) {
        const float* vec[3] = {v + 3 * iv::channel(d, 0), v + 3 * iv::channel(d, 1), v + 3 * iv::channel(d, 2)};
        if (layout == ExportLayout::Vectors) {
            for (int c = 0; c < 3; ++c) {
                float* t = out + 4 * (3 * d + c);
                t[0] = vec[c][0], t[1] = vec[c][1], t[2] = vec[c][2], t[3] = 0.0f;
            }
            continue;
        }
        // Section 4.2: colour = the three vectors' lengths, direction = their normalised sum.
        float* colour = out + 8 * d;
        float* dir = colour + 4;
        double sum[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            const double x = vec[c][0], y = vec[c][1], z = vec[c][2];
            colour[c] = float(std::sqrt(x * x + y * y + z * z));
            sum[0] += x, sum[1] += y, sum[2] += z;
        }
        const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        for (int a = 0; a < 3; ++a) dir[a] = len > 0 ? float(sum[a] / len) : 0.0f;
        colour[3] = 0.0f;
        dir[3] = 0.0f;
    }
}

std::vector<TextureDesc> depthTextureDescs() {
    std::vector<TextureDesc> d;
    for (const char* axis : {"x", "y", "z"}) {
        const std::string a = axis;
        d.push_back({"depth_" + a, {"mean_pos_" + a, "mean_neg_" + a, "sigma_pos_" + a, "sigma_neg_" + a}});
    }
    return d;
}

std::vector<std::vector<float>> depthTextures(const Volume& volume, const TextureLattice& lattice) {
    if (volume.levels.empty() || !volume.hasDepth()) return {};
    // Only a lattice that is the finest level's own: depth moments belong to node positions
    // and the spacing they are measured in; they cannot be resampled.
    const VolumeLevel& finest = volume.levels.back();
    const GridSpec& g = finest.grid;
    if (lattice.dims[0] != g.nx || lattice.dims[1] != g.ny || lattice.dims[2] != g.nz) return {};
    const double tol = 1e-9 * std::max(1.0, g.spacing * std::max({g.nx, g.ny, g.nz}));
    for (int a = 0; a < 3; ++a)
        if (std::fabs(lattice.lo[a] - g.origin[a]) > tol) return {};
    // A texel that is no node of the finest level (a sparse level of a bilevel / adaptive
    // volume) lies where no cell of that level was refined into: refinement is complete (every
    // cell with geometry is refined, layout_levels.h), so no geometry lies in the texel cells
    // around it, and every face is free for a whole texel cell: mean 1, sigma 0, exactly what
    // the depth pass would measure there.
    constexpr float kFree[4] = {1.0f, 1.0f, 0.0f, 0.0f};
    std::vector<std::vector<float>> out(3, std::vector<float>(g.nodeCount() * 4));
    for (std::size_t n = 0; n < g.nodeCount(); ++n) {
        const int64_t at = finest.sparse() ? findNode(finest, n) : int64_t(n);
        const float* d = at >= 0 ? finest.nodeDepth(std::size_t(at)) : nullptr;
        for (int a = 0; a < 3; ++a) {
            float* t = &out[std::size_t(a)][n * 4];
            if (!d) {
                std::copy_n(kFree, 4, t);
                continue;
            }
            t[0] = d[depth::kMeanPositive * 3 + a];
            t[1] = d[depth::kMeanNegative * 3 + a];
            t[2] = d[depth::kSigmaPositive * 3 + a];
            t[3] = d[depth::kSigmaNegative * 3 + a];
        }
    }
    return out;
}

}  // namespace exporter
}  // namespace vdblight
