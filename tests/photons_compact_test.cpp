// The compact colour + direction form (Pacanowski et al. section 4.2,
// irradiance_vectors_compact.h): exact for parallel colour vectors, the definition for others,
// and a photon bake written as half-float compact grids and read back through the query
// registry, against the full form.
#include <gtest/gtest.h>

#include <cmath>

#include "grids.h"
#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "basis/irradiance_vectors_compact.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/query/query.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"
#include "volume/volume_compact.h"

using namespace vdblight;

namespace {
/// One node whose direction d holds I_c = colour[c] * v_c.
void setDirection(float* node, int d, const Rgb& colour, const Vec3f v[3]) {
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) node[9 * d + 3 * c + k] = colour[c] * v[c][k];
}
}  // namespace

TEST(CompactVectors, ExactWhenTheColourVectorsAreParallel) {
    float full[iv::kFloatsPerNode], compact[iv::kCompactFloatsPerNode];
    Rng rng(7);
    for (int d = 0; d < iv::kDirections; ++d) {
        Vec3f w = uniformSphere(rng.uniform(), rng.uniform());
        // Inside the hemisphere of delta, as photon sums are.
        const int a = d / 2;
        const float sign = d % 2 ? -1.0f : 1.0f;
        if (w[a] * sign < 0) w[a] = -w[a];
        const Vec3f v[3] = {w, w, w};
        setDirection(full, d, Rgb(1.0f + d, 0.5f, 0.25f * d), v);
    }
    iv::compactNode(full, compact);
    for (int i = 0; i < 200; ++i) {
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb a = iv::irradiance(full, n), b = iv::compactIrradiance(compact, n);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(b[c], a[c], 1e-5f * (1 + std::abs(a[c]))) << "normal " << i;
    }
}

TEST(CompactVectors, ColourIsTheNormsDirectionTheNormalisedSum) {
    float full[iv::kFloatsPerNode] = {}, compact[iv::kCompactFloatsPerNode];
    const Vec3f v[3] = {normalize(Vec3f(1, 0.2f, 0)), normalize(Vec3f(1, -0.3f, 0.1f)), Vec3f(1, 0, 0)};
    const int d = iv::direction(0, false);  // +x
    setDirection(full, d, Rgb(2, 3, 4), v);
    iv::compactNode(full, compact);
    EXPECT_NEAR(compact[6 * d + 0], 2.0f, 1e-6f);
    EXPECT_NEAR(compact[6 * d + 1], 3.0f, 1e-6f);
    EXPECT_NEAR(compact[6 * d + 2], 4.0f, 1e-6f);
    const Vec3f sum = v[0] * 2.0f + v[1] * 3.0f + v[2] * 4.0f;
    const Vec3f dir = normalize(sum);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(compact[6 * d + 3 + k], dir[k], 1e-6f);
    // Facing +x: E_c = |I_c| <d, x>, not <I_c, x>.
    const Rgb e = iv::compactIrradiance(compact, Vec3f(1, 0, 0));
    EXPECT_NEAR(e.x, 2.0f * dir.x, 1e-5f);
    EXPECT_NEAR(e.z, 4.0f * dir.x, 1e-5f);
    // Directions with no light stay zero and give zero irradiance.
    EXPECT_EQ(iv::compactIrradiance(compact, Vec3f(-1, 0, 0)).x, 0.0f);
}

TEST(CompactVectors, RefusesOtherVolumes) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels.resize(1);
    EXPECT_THROW(iv::compact(v), FormatError);
}

namespace {
/// Relative RMS difference between the full volume's lookup and its compact form written as
/// halves, read back and looked up through the query registry, at random points and normals.
/// With `atNodes`, the points are nodes (no interpolation).
double compactDifference(const Scene& s, const GridSpec& g, bool atNodes) {
    const Tracer tracer(s);
    PhotonOptions o;
    o.photons = 200000;
    const Volume full = bakePhotons(s, tracer, g, o);
    test::TempDir dir;
    const std::string path = dir.file("compact.vdb");
    WriteOptions w;
    w.halfFloat = true;
    writeVolume(iv::compact(full), path, w);
    const Volume back = readVolume(path);
    EXPECT_EQ(back.basis.kind, "irradiance_vectors_compact");
    EXPECT_EQ(back.basis.channelCount(), 12);
    EXPECT_EQ(back.basis.channelNames[0], "ivc_xpos_rgb");
    EXPECT_EQ(back.basis.channelNames[11], "ivc_zneg_dir");
    EXPECT_FALSE(metaString(back.meta, "compact_form").empty());

    const IrradianceQuery query(back);  // through the registry
    const VectorGridLookup fullLookup(full, OutsidePolicy::Clamp);
    const VectorGridLookup cubicCompact(back, OutsidePolicy::Clamp, Interpolation::Tricubic);
    Rng rng(3);
    double num = 0, den = 0;
    for (int i = 0; i < 500; ++i) {
        Vec3f x = Vec3f(g.origin) + Vec3f(rng.uniform(), rng.uniform(), rng.uniform()) * float((g.nx - 1) * g.spacing);
        if (atNodes) x = Vec3f(g.node(rng.next() % g.nodeCount()));
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        const Rgb a = fullLookup.irradiance(x, n), b = query.irradiance(x, n);
        for (int c = 0; c < 3; ++c) num += double(b[c] - a[c]) * (b[c] - a[c]), den += double(a[c]) * a[c];
        const Rgb cub = cubicCompact.irradiance(x, n);
        EXPECT_TRUE(std::isfinite(cub.x) && std::isfinite(cub.y) && std::isfinite(cub.z));
    }
    return std::sqrt(num / den);
}

Scene floorCorner() {
    Scene s;
    s.name = "floor";
    Material m;
    m.albedo = {0.5f, 0.5f, 0.5f};  // grey: reflected photons keep the light's colour ratios
    const uint32_t id = addMaterial(s, m);
    addTriangle(s, {0, 0, 0}, {2, 0, 0}, {0, 0, 2}, id);
    return s;
}

GridSpec smallGrid() { return test::makeGrid({0.1, 0.1, 0.1}, 0.3, 5, 5, 5); }
}  // namespace

// One coloured light and a grey floor: every photon has the light's colour ratios, so the
// three colour vectors are parallel and at the nodes the compact form differs only by half
// rounding; between nodes, by interpolating colour and direction separately.
TEST(CompactVectors, OneLightThroughAHalfFloatFileIsNearlyExact) {
    Scene s = floorCorner();
    s.directionalLights.push_back({normalize(Vec3f(0.3f, -1, 0.2f)), Rgb(1.0f, 0.6f, 0.3f)});
    const double atNodes = compactDifference(s, smallGrid(), true), between = compactDifference(s, smallGrid(), false);
    std::printf("compact (half) vs full, one coloured light: relative RMS difference %.5f at nodes, %.5f between "
                "(colour and direction are interpolated separately)\n",
                atNodes, between);
    EXPECT_LT(atNodes, 1e-3);  // half rounding: 2^-11 per value
    EXPECT_LT(between, 0.01);
}

// Two lights of different colours from different directions: the compact form is then an
// approximation (each colour keeps its magnitude, all share one direction).
TEST(CompactVectors, TwoColouredLightsAreApproximated) {
    Scene s = floorCorner();
    s.directionalLights.push_back({normalize(Vec3f(0.3f, -1, 0.2f)), Rgb(1.0f, 0.6f, 0.3f)});
    s.directionalLights.push_back({normalize(Vec3f(-0.5f, -0.6f, -0.4f)), Rgb(0.1f, 0.3f, 0.8f)});
    const double rel = compactDifference(s, smallGrid(), false);
    std::printf("compact (half) vs full, two coloured lights: relative RMS difference %.4f\n", rel);
    EXPECT_GT(rel, 0.01);
    EXPECT_LT(rel, 0.25);
}
