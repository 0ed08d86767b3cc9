// The engine-size SH layouts sh1-16 and sh2-32 (compact_sh.h, docs/engine_layouts.md): their ranges
// hold every non-negative radiance unclipped, the 8-bit rounding stays within the bound that
// docs/engine_layouts.md argues, compactShRoundTrip is what the files decode to, and a volume whose
// basis cannot take them is refused before anything is written.
#include <gtest/gtest.h>

#include <cmath>

#include "../libvdblight/src/export/compact_sh.h"  // internal: packCompactTexel, unpackCompactTexel
#include "export_file_checks.h"
#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/core/errors.h"
#include "export/export_compact.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "basis/shadow_edges.h"
#include "basis/sh.h"
#include "volume/sh_truncate.h"

using namespace vdblight;
using namespace vdblight::exporter;
namespace fs = std::filesystem;

namespace {
const ExportLayout kLayouts[2] = {ExportLayout::Sh1x16, ExportLayout::Sh2x32};

Vec3f randomDirection(Rng& rng) {
    for (;;) {
        const Vec3f d(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
        const float l = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (l > 0.1f && l <= 1.0f) return d / l;
    }
}

// SH order-2 coefficients of radiance arriving from `count` directions with random colours:
// a non-negative radiance, the kind a bake stores (its estimates are sums of such samples).
void randomRadiance(Rng& rng, int count, Rgb L[9]) {
    for (int j = 0; j < 9; ++j) L[j] = Rgb(0, 0, 0);
    for (int s = 0; s < count; ++s) {
        const Vec3f w = randomDirection(rng);
        const Rgb colour(rng.uniform(), rng.uniform(), rng.uniform());
        float y[9];
        sh::evalUnrolled(w, y);
        for (int j = 0; j < 9; ++j) L[j] = L[j] + colour * y[j];
    }
}

// The texel as the files hold it: L0_L1Rx in half, the others in 8 bits.
std::vector<float> stored(ExportLayout layout, const Rgb L[9]) {
    std::vector<float> t(compactShTextures(layout).size() * 4);
    packCompactTexel(layout, L, t.data());
    for (std::size_t i = 0; i < t.size(); ++i)
        t[i] = i < 4 ? float(Imath::half(t[i])) : float(unorm8(t[i])) / 255.0f;
    return t;
}

// docs/engine_layouts.md's bound on |E_decoded - E| per unit of a (= A0 c0 L0 of the colour): every
// stored ratio is within range / 510, times the normal's polynomial of its term.
double boundPerA(ExportLayout layout, const Vec3f& n) {
    const double x = std::fabs(n.x), y = std::fabs(n.y), z = std::fabs(n.z);
    double b = compact_sh::kL1Range * (x + y + z);
    if (layout == ExportLayout::Sh2x32)
        b += compact_sh::kL2Range[0] * x * y + compact_sh::kL2Range[1] * y * z + compact_sh::kL2Range[3] * z * x +
             compact_sh::kL2Range[2] * std::fabs(3 * z * z - 1) + compact_sh::kL2CRange * std::fabs(x * x - y * y);
    return b / 510.0;
}

// The irradiance the layout stands for: bands 0..1 for sh1-16, 0..2 for sh2-32.
Rgb layoutIrradiance(ExportLayout layout, Rgb L[9], const Vec3f& n) {
    Rgb kept[9];
    for (int j = 0; j < 9; ++j) kept[j] = layout == ExportLayout::Sh1x16 && j >= 4 ? Rgb(0, 0, 0) : L[j];
    return sh::irradiance(kept, n);
}
}  // namespace

// One direction is the extreme of every ratio (|L1 term| = 2 a, |L4 term| = 15/8 a, ...): if a
// range were narrower than the bound docs/engine_layouts.md derives, such texels would be clipped.
TEST(CompactSh, SingleDirectionsRoundTripUnclippedBeforeRounding) {
    Rng rng(3);
    for (int s = 0; s < 2000; ++s) {
        Rgb L[9];
        randomRadiance(rng, 1, L);
        for (ExportLayout layout : kLayouts) {
            std::vector<float> t(compactShTextures(layout).size() * 4);
            packCompactTexel(layout, L, t.data());
            for (std::size_t i = 4; i < t.size(); ++i) ASSERT_TRUE(t[i] >= 0.0f && t[i] <= 1.0f) << i;
            Rgb back[9];
            unpackCompactTexel(layout, t.data(), back);
            const int kept = layout == ExportLayout::Sh1x16 ? 4 : 9;
            for (int j = 0; j < kept; ++j)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(back[j][c], L[j][c], 1e-5f * (1.0f + std::fabs(L[0][c]) * 4.0f))
                        << "sample " << s << " coefficient " << j << " colour " << c;
        }
    }
}

TEST(CompactSh, EightBitRoundingStaysWithinTheDocumentedBound) {
    Rng rng(11);
    double worstShare[2] = {0, 0};
    for (int s = 0; s < 3000; ++s) {
        Rgb L[9];
        randomRadiance(rng, 1 + s % 7, L);
        for (int li = 0; li < 2; ++li) {
            const ExportLayout layout = kLayouts[li];
            Rgb back[9];
            unpackCompactTexel(layout, stored(layout, L).data(), back);
            for (int k = 0; k < 8; ++k) {
                const Vec3f n = randomDirection(rng);
                const Rgb want = layoutIrradiance(layout, L, n), got = sh::irradiance(back, n);
                for (int c = 0; c < 3; ++c) {
                    const double a = sh::kCosineLobe[0] * 0.5 / std::sqrt(kPi) * L[0][c];
                    // + the half rounding of a (2^-11 relative) and of the red L1 ratio, float sums
                    const double bound = a * (boundPerA(layout, n) + 4.0 * std::ldexp(1.0, -11)) + 1e-6;
                    const double err = std::fabs(double(got[c]) - double(want[c]));
                    ASSERT_LE(err, bound) << "sample " << s << " colour " << c << " layout " << layoutName(layout);
                    worstShare[li] = std::max(worstShare[li], err / bound);
                }
            }
        }
    }
    // The bound is no loose guess: rounding reaches a good part of it.
    EXPECT_GT(worstShare[0], 0.3);
    EXPECT_GT(worstShare[1], 0.3);
}

// compactShRoundTrip is what the raw files decode to, node by node, and its query is the
// layout's irradiance of those texels.
TEST(CompactSh, RoundTripVolumeIsWhatTheFilesDecodeTo) {
    Volume v = test::randomShVolume(4, 3, 3, 0.5, 5);
    // Non-negative radiance at every node, as a bake's.
    Rng rng(7);
    for (std::size_t n = 0; n < v.levels[0].grid.nodeCount(); ++n) {
        Rgb L[9];
        randomRadiance(rng, 3, L);
        for (int j = 0; j < 9; ++j)
            for (int c = 0; c < 3; ++c) v.levels[0].data[(n * 9 + j) * 3 + c] = L[j][c];
    }
    for (ExportLayout layout : kLayouts) {
        test::TempDir dir;
        ExportOptions o;
        o.format = TextureFormat::Raw;
        o.layout = layout;
        exportTextures(v, dir.file("out"), o);
        const std::vector<TextureDesc> descs = compactShTextures(layout);
        std::vector<std::vector<uint8_t>> files;
        for (const TextureDesc& d : descs) files.push_back(test::readFile(dir.file("out/" + d.name + ".raw")));
        ASSERT_EQ(files[0].size(), v.levels[0].grid.nodeCount() * 8);  // RGBA16F
        for (std::size_t t = 1; t < files.size(); ++t) ASSERT_EQ(files[t].size(), v.levels[0].grid.nodeCount() * 4);  // RGBA8

        const Volume trip = compactShRoundTrip(v, layout);
        for (std::size_t n = 0; n < v.levels[0].grid.nodeCount(); ++n) {
            std::vector<float> texel(descs.size() * 4);
            for (int c = 0; c < 4; ++c) texel[std::size_t(c)] = test::f16(files[0], (n * 4 + std::size_t(c)) * 2);
            for (std::size_t t = 1; t < descs.size(); ++t)
                for (int c = 0; c < 4; ++c) texel[t * 4 + std::size_t(c)] = float(files[t][n * 4 + std::size_t(c)]) / 255.0f;
            Rgb L[9];
            unpackCompactTexel(layout, texel.data(), L);
            for (int j = 0; j < 9; ++j)
                for (int c = 0; c < 3; ++c)
                    ASSERT_FLOAT_EQ(trip.levels[0].data[(n * 9 + j) * 3 + std::size_t(c)], L[j][c]) << n << " " << j;
        }
        // Between nodes the query of the round trip stays within the bound of the truncated volume's.
        const IrradianceQuery exact(truncateSh(v, 2)), engine(trip);
        for (int k = 0; k < 200; ++k) {
            const Vec3f x(-0.5f + 1.5f * rng.uniform(), 0.25f + rng.uniform(), 1.0f + rng.uniform());
            const Vec3f nrm = randomDirection(rng);
            Rgb L[9];
            exact.lookup().shRadiance(Vec3d(x), L);
            const Rgb want = layoutIrradiance(layout, L, nrm);
            Rgb M[9];
            engine.lookup().shRadiance(Vec3d(x), M);
            const Rgb got = sh::irradiance(M, nrm);
            for (int c = 0; c < 3; ++c) {
                const double a = sh::kCosineLobe[0] * 0.5 / std::sqrt(kPi) * L[0][c];
                EXPECT_LE(std::fabs(double(got[c]) - double(want[c])),
                          a * (boundPerA(layout, nrm) + 4.0 * std::ldexp(1.0, -11)) + 1e-6);
            }
        }
    }
}

// A --direct occlusion volume with shadow edges: the engine-size export writes each node's edge
// distance and width (half, no ramp texture) and compactShRoundTrip holds exactly those values,
// so that the GPU-driver check's decoded volume is what the shader reads.
TEST(CompactSh, RoundTripShadowEdgesAreTheExportedHalfTexels) {
    Volume v = test::randomShVolume(4, 3, 3, 0.5, 5);
    VolumeLevel& level = v.levels[0];
    v.direct.mode = DirectMode::Occlusion;
    v.direct.lights.push_back(DirectLight{});  // a point light at the origin
    Rng rng(11);
    const std::size_t nodes = level.grid.nodeCount();
    for (std::size_t n = 0; n < nodes; ++n) {
        level.lightVisibility.push_back(rng.uniform());
        // Distances in +-3 cells and widths in [0, 2): values half rounds.
        level.lightShadowEdges.push_back(6.0f * rng.uniform() - 3.0f);
        level.lightShadowEdges.push_back(2.0f * rng.uniform());
        for (int part = 2; part < shadow_edge::kFloatsPerLight; ++part) level.lightShadowEdges.push_back(0.0f);  // no second edge
    }
    for (ExportLayout layout : kLayouts) {
        test::TempDir dir;
        ExportOptions o;
        o.format = TextureFormat::Raw;
        o.layout = layout;
        exportTextures(v, dir.file("out"), o);
        EXPECT_FALSE(fs::exists(dir.file("out/light_edge_ramp_0_0.raw"))) << "the engine-size layouts have no ramp texture";
        const std::vector<uint8_t> distance = test::readFile(dir.file("out/light_edge_distance_0_0.raw"));
        const std::vector<uint8_t> width = test::readFile(dir.file("out/light_edge_width_0_0.raw"));
        ASSERT_EQ(distance.size(), nodes * 8);  // RGBA16F
        ASSERT_EQ(width.size(), nodes * 8);
        const Volume trip = compactShRoundTrip(v, layout);
        int rounded = 0;
        for (std::size_t n = 0; n < nodes; ++n) {
            const std::size_t at = n * shadow_edge::kFloatsPerLight;
            const float d = trip.levels[0].lightShadowEdges[at], w = trip.levels[0].lightShadowEdges[at + 1];
            EXPECT_EQ(d, test::f16(distance, n * 8)) << n;  // light 0: component r
            EXPECT_EQ(w, test::f16(width, n * 8)) << n;
            rounded += d != level.lightShadowEdges[at];
        }
        EXPECT_GT(rounded, int(nodes) / 2) << "the stored distances should need rounding to half";
    }
}

TEST(CompactSh, VolumesWhoseBasisCannotTakeThemAreRefusedBeforeWriting) {
    bins::BasisSpec spec;
    spec.kind = bins::BasisSpec::Kind::Bins;
    spec.resolution = 4;
    const BasisDesc bins = bins::basis(spec);
    const Volume cases[] = {
        test::randomUniformVolume(iv::basis(), 3, 3, 3, 0.5, 1),        // irradiance vectors
        test::randomUniformVolume(bins, 3, 3, 3, 0.5, 2),               // bins:4
        test::randomUniformVolume(makeBasis("sh:1")->desc(), 3, 3, 3, 0.5, 3),  // only bands 0..1
    };
    for (const Volume& v : cases)
        for (ExportLayout layout : kLayouts)
            for (TextureFormat f : {TextureFormat::Ktx2, TextureFormat::Raw}) {
                test::TempDir dir;
                ExportOptions o;
                o.format = f;
                o.layout = layout;
                try {
                    exportTextures(v, dir.file("out"), o);
                    ADD_FAILURE() << v.basis.kind << " exported as " << layoutName(layout);
                } catch (const FormatError& e) {
                    const std::string what = e.what();
                    EXPECT_NE(what.find(layoutName(layout)), std::string::npos) << what;
                    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
                }
                EXPECT_FALSE(fs::exists(dir.file("out"))) << v.basis.kind;
                EXPECT_THROW(compactShRoundTrip(v, layout), FormatError) << v.basis.kind;
            }
}
