// The engine-size SH layouts sh1-16 and sh2-32: their textures, the encoding of a texel and
// its inverse (compact_sh.h), and the round trip of a whole volume (export_compact.h).
#include "compact_sh.h"

#include <half.h>

#include <cmath>

#include "export_internal.h"
#include "vdblight/core/errors.h"
#include "export/export_compact.h"
#include "basis/sh.h"
#include "volume/sh_truncate.h"

namespace vdblight::exporter {

namespace {

// Per colour: the factor from L_j to its sh2-packed term, in the order the texels keep them.
const int kL1Coeff[3] = {3, 1, 2};          // n.x, n.y, n.z
const int kL2Coeff[4] = {4, 5, 6, 7};        // xy, yz, the L6 term, zx
double l1Factor() { return kA1 * kC1; }
double l2Factor(int k) { return kA2 * (k == 2 ? kC3 : kC2); }

double channel(const Rgb& c, int ch) { return ch == 0 ? c.x : (ch == 1 ? c.y : c.z); }
void setChannel(Rgb& c, int ch, double v) { (ch == 0 ? c.x : (ch == 1 ? c.y : c.z)) = float(v); }

// v / a mapped to [0, 1]; no light (a <= 0) holds nothing in the higher bands.
float encode(double v, double a, double range) {
    if (!(a > 0)) return 0.5f;
    const double t = v / (range * a) + 0.5;
    return float(t < 0 ? 0 : (t > 1 ? 1 : t));
}
double decode(float t, double a, double range) { return (double(t) - 0.5) * range * a; }
}  // namespace

bool isCompactSh(ExportLayout layout) { return layout == ExportLayout::Sh1x16 || layout == ExportLayout::Sh2x32; }

std::vector<TextureDesc> compactShTextures(ExportLayout layout) {
    const std::string l1 = " (L1 / L0: t = b / (4 a) + 0.5)";
    std::vector<TextureDesc> t = {
        {"L0_L1Rx", {"a red = A0*c0*L0", "a green", "a blue", "red b.x" + l1}},
        {"L1G_L1Ry", {"green b.x" + l1, "green b.y", "green b.z", "red b.y"}},
        {"L1B_L1Rz", {"blue b.x" + l1, "blue b.y", "blue b.z", "red b.z"}},
    };
    if (layout == ExportLayout::Sh2x32) {
        const char* names[3] = {"L2_R", "L2_G", "L2_B"};
        const char* colour[3] = {"red", "green", "blue"};
        for (int c = 0; c < 3; ++c) {
            const std::string ch = colour[c];
            t.push_back({names[c],
                         {ch + " B.xy (A2*c2*L4 / a: t = v / (3.75 a) + 0.5)", ch + " B.yz (A2*c2*L5, range 3.75)",
                          ch + " d (A2*c3*L6, range 1.25)", ch + " B.zx (A2*c2*L7, range 3.75)"}});
        }
        t.push_back({"L2_C", {"red C (A2*c4*L8 / a: t = v / (1.875 a) + 0.5)", "green C", "blue C", "unused (0)"}});
    }
    return t;
}

void packCompactTexel(ExportLayout layout, const Rgb L[9], float* out) {
    const bool order2 = layout == ExportLayout::Sh2x32;
    float* l1[3] = {out + 4 * 0, out + 4 * 1, out + 4 * 2};  // L0_L1Rx, L1G_L1Ry, L1B_L1Rz
    for (int c = 0; c < 3; ++c) {
        const double a = kA0 * kC0 * channel(L[0], c);
        out[c] = float(a);
        for (int axis = 0; axis < 3; ++axis) {
            const float t = encode(l1Factor() * channel(L[kL1Coeff[axis]], c), a, compact_sh::kL1Range);
            // Red's three components go into the alpha channels (Unity APV's arrangement).
            if (c == 0) l1[axis][3] = t;
            else l1[c][axis] = t;
        }
        if (!order2) continue;
        float* l2 = out + 12 + 4 * c;
        for (int k = 0; k < 4; ++k) l2[k] = encode(l2Factor(k) * channel(L[kL2Coeff[k]], c), a, compact_sh::kL2Range[k]);
        out[24 + c] = encode(kA2 * kC4 * channel(L[8], c), a, compact_sh::kL2CRange);
    }
    if (order2) out[27] = 0.0f;
}

void unpackCompactTexel(ExportLayout layout, const float* texel, Rgb L[9]) {
    const bool order2 = layout == ExportLayout::Sh2x32;
    for (int j = 0; j < 9; ++j) L[j] = Rgb(0.0f, 0.0f, 0.0f);
    for (int c = 0; c < 3; ++c) {
        const double a = texel[c];
        setChannel(L[0], c, a / (kA0 * kC0));
        for (int axis = 0; axis < 3; ++axis) {
            const float t = c == 0 ? texel[4 * axis + 3] : texel[4 * c + axis];
            setChannel(L[kL1Coeff[axis]], c, decode(t, a, compact_sh::kL1Range) / l1Factor());
        }
        if (!order2) continue;
        const float* l2 = texel + 12 + 4 * c;
        for (int k = 0; k < 4; ++k) setChannel(L[kL2Coeff[k]], c, decode(l2[k], a, compact_sh::kL2Range[k]) / l2Factor(k));
        setChannel(L[8], c, decode(texel[24 + c], a, compact_sh::kL2CRange) / (kA2 * kC4));
    }
}

}  // namespace vdblight::exporter

namespace vdblight {

Volume compactShRoundTrip(const Volume& volume, ExportLayout layout, bool halfFloat) {
    using namespace exporter;
    if (!isCompactSh(layout))
        throw FormatError(std::string("compactShRoundTrip takes sh1-16 or sh2-32, not '") + layoutName(layout) + "'");
    if (storedShOrder(volume) < 2)
        throw FormatError(std::string("layout '") + layoutName(layout) + "' does not fit a '" + volume.basis.kind +
                          "' volume (it needs real SH of order 2 or more)");
    Volume out = truncateSh(volume, 2);
    const std::size_t textures = compactShTextures(layout).size();
    const TexelFormat first = lightingTexelFormat(halfFloat);
    std::vector<float> texel(textures * 4);
    for (VolumeLevel& level : out.levels) {
        const std::size_t nodes = level.heldNodes();
        for (std::size_t n = 0; n < nodes; ++n) {
            float* d = level.data.data() + n * sh::kCoeffs * 3;
            Rgb L[9];
            for (int j = 0; j < 9; ++j) L[j] = Rgb(d[3 * j], d[3 * j + 1], d[3 * j + 2]);
            packCompactTexel(layout, L, texel.data());
            // As the files store them: the first texture half (or float), the others 8-bit.
            for (std::size_t i = 0; i < texel.size(); ++i) {
                const bool l0Texture = i < 4;
                if (l0Texture && first == TexelFormat::Float16) texel[i] = float(Imath::half(texel[i]));
                if (!l0Texture) texel[i] = float(unorm8(texel[i])) / 255.0f;
            }
            unpackCompactTexel(layout, texel.data(), L);
            for (int j = 0; j < 9; ++j) d[3 * j] = L[j].x, d[3 * j + 1] = L[j].y, d[3 * j + 2] = L[j].z;
        }
        for (float& v : level.lightVisibility) v = float(unorm8(v)) / 255.0f;
        // The shadow edges' distance and width go in the lighting format (signed, in cells).
        if (first == TexelFormat::Float16)
            for (float& e : level.lightShadowEdges) e = float(Imath::half(e));
    }
    return out;
}

}  // namespace vdblight
