// The export hook of the bins / moment lookup (BinsLookup::binValues) against the simple
// reference lookup (referenceBinsLookup, asked at each bin's centre direction) on a
// three-level adaptive volume with random node values, and at the nodes of a uniform volume
// against the nodes' own values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "random_volumes.h"
#include "vdblight/basis/bins.h"
#include "query/bins_lookup.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

using namespace vdblight;

namespace {
Volume binsVolume(LayoutKind kind, int levels, const bins::BasisSpec& spec) {
    return test::randomLevelsVolume(kind, levels, bins::basis(spec), 5, 0.0f, 2.0f);
}
}  // namespace

TEST(ExportBins, BinValuesMatchTheReferenceLookupOfEveryBinOnEveryLevel) {
    bins::BasisSpec spec;
    spec.kind = bins::BasisSpec::Kind::Bins;
    spec.resolution = 2;
    for (const int levels : {1, 3}) {
        const Volume v = binsVolume(LayoutKind::Adaptive, levels, spec);
        ASSERT_EQ(int(v.levels.size()), levels);
        const BinsLookup lookup(v, OutsidePolicy::Clamp);
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<float> values(std::size_t(spec.binCount()) * 3);
        for (int s = 0; s < 200; ++s) {
            const Vec3d x(0.05 + 0.9 * u(rng), 0.05 + 0.9 * u(rng), 0.05 + 0.9 * u(rng));
            lookup.binValues(x, values.data());
            for (int c = 0; c < spec.binCount(); ++c) {
                const Rgbd want = referenceBinsLookup(v, x, Vec3f(bins::binCentre(spec.resolution, c)));
                for (int ch = 0; ch < 3; ++ch)
                    ASSERT_NEAR(values[3 * c + ch], want[ch], 2e-5) << "levels " << levels << " bin " << c;
            }
        }
    }
}

TEST(ExportBins, BinValuesAtANodeAreThatNodesValues) {
    bins::BasisSpec spec;
    spec.kind = bins::BasisSpec::Kind::Moment;
    spec.order = 3;
    spec.resolution = 3;
    const Volume v = binsVolume(LayoutKind::Adaptive, 1, spec);
    const BinsLookup lookup(v, OutsidePolicy::Clamp);
    const GridSpec& g = v.levels[0].grid;
    const std::size_t floats = std::size_t(spec.binCount()) * 3;
    std::vector<float> values(floats);
    for (int k = 0; k < g.nz; ++k)
        for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i) {
                lookup.binValues(g.origin + Vec3d(i, j, k) * g.spacing, values.data());
                const float* node = v.levels[0].data.data() + g.index(i, j, k) * floats;
                for (std::size_t f = 0; f < floats; ++f) ASSERT_NEAR(values[f], node[f], 1e-5f * (1 + std::fabs(node[f])));
            }
}

TEST(ExportBins, OtherKindsHaveNoBinValues) {
    // The default hook of VolumeLookup throws FormatError (export turns it into a refusal).
    struct Plain final : VolumeLookup {
        Rgb irradiance(const Vec3f&, const Vec3f&) const override { return {0, 0, 0}; }
        Bounds bounds() const override { return {}; }
    } plain;
    float out[3];
    EXPECT_THROW(plain.binValues(Vec3d(0, 0, 0), out), FormatError);
}
