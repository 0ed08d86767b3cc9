// Streamed lookups (query_stream.h, vdb_stream.h) give the same bits as the in-memory lookup
// of the same file, read only the leaves they touch, and refuse the kinds they do not read.
#include <gtest/gtest.h>

#include <cstring>

#include "random_volumes.h"
#include "test_util.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "query/light_visibility.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "query/query_levels.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {

bool sameBits(const Rgb& a, const Rgb& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Points in and around the node box (10 % beyond each side, so both clamping and the Throw
// policy are exercised), with random unit normals; a few exactly on nodes.
struct Probe {
    Vec3d x;
    Vec3f n;
};
std::vector<Probe> probes(const GridSpec& g, int count, uint64_t seed) {
    Rng rng(seed);
    const Bounds b = g.nodeBounds();
    std::vector<Probe> out;
    for (int p = 0; p < count; ++p) {
        Probe q;
        for (int a = 0; a < 3; ++a) q.x[a] = b.lo[a] + (rng.uniform() * 1.2 - 0.1) * (b.hi[a] - b.lo[a]);
        if (p % 10 == 0) q.x = g.node(p % g.nx, (p / 3) % g.ny, (p / 7) % g.nz);
        q.n = normalize(Vec3f(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f + 1e-3f));
        out.push_back(q);
    }
    return out;
}

// Every lookup of the streamed query equals the in-memory one bit for bit (or both throw).
void expectSameBits(const std::string& path, OutsidePolicy outside, bool depthWeights) {
    const Volume whole = readVolume(path);
    const IrradianceQuery memory(whole, outside, depthWeights);
    auto file = std::make_shared<StreamedVolume>(path);
    ASSERT_EQ(streamingSupported(*file), "");
    const IrradianceQuery streamed = makeStreamingQuery(file, outside, depthWeights);
    EXPECT_EQ(streamed.depthWeighted(), memory.depthWeighted());
    EXPECT_EQ(streamed.bounds().lo, memory.bounds().lo);
    EXPECT_EQ(streamed.bounds().hi, memory.bounds().hi);
    EXPECT_EQ(std::string(streamed.kind()), std::string(memory.kind()) + "-streamed");
    int compared = 0, finer = 0;
    const auto* levels = dynamic_cast<const ShLevelsLookup*>(&memory.lookup());
    const std::size_t channels = whole.basis.kind == "sh2" ? 0 : std::size_t(whole.basis.channelCount()) * 3;
    const std::size_t lights = whole.direct.hasVisibility() ? whole.direct.lights.size() : 0;
    const auto* visibility = dynamic_cast<const LightVisibility*>(&streamed.lookup());
    EXPECT_EQ(visibility != nullptr, lights > 0);
    for (const Probe& p : probes(whole.levels[0].grid, 400, 7)) {
        bool threwMemory = false, threwStreamed = false;
        Rgb a, b, c, d;
        try {
            a = memory.irradiance(Vec3f(p.x), p.n);
            c = memory.irradianceWorld(p.x, p.n);
        } catch (const ValueError&) { threwMemory = true; }
        try {
            b = streamed.irradiance(Vec3f(p.x), p.n);
            d = streamed.irradianceWorld(p.x, p.n);
        } catch (const ValueError&) { threwStreamed = true; }
        ASSERT_EQ(threwMemory, threwStreamed) << p.x.x << "," << p.x.y << "," << p.x.z;
        if (threwMemory) continue;
        if (levels && levels->levelAt(Vec3f(p.x)) > 0) ++finer;
        ASSERT_TRUE(sameBits(a, b)) << "irradiance at " << p.x.x << "," << p.x.y << "," << p.x.z;
        ASSERT_TRUE(sameBits(c, d)) << "irradianceWorld at " << p.x.x << "," << p.x.y << "," << p.x.z;
        if (channels == 0 || channels >= 27) {  // sh:1 stores no SH order-2 part: both refuse it
            Rgb sa[9], sb[9];
            memory.lookup().shRadiance(p.x, sa);
            streamed.lookup().shRadiance(p.x, sb);
            for (int j = 0; j < 9; ++j) ASSERT_TRUE(sameBits(sa[j], sb[j])) << "shRadiance " << j;
        } else {
            Rgb sa[9];
            EXPECT_THROW(memory.lookup().shRadiance(p.x, sa), FormatError);
            EXPECT_THROW(streamed.lookup().shRadiance(p.x, sa), FormatError);
        }
        if (channels > 0) {  // registered bases: the channel values export's basis layout reads
            std::vector<float> ca(channels), cb(channels);
            memory.lookup().channelValues(p.x, ca.data());
            streamed.lookup().channelValues(p.x, cb.data());
            ASSERT_EQ(std::memcmp(ca.data(), cb.data(), ca.size() * sizeof(float)), 0) << "channelValues";
        }
        if (visibility) {  // bake --direct occlusion: what export's visibility textures read
            std::vector<float> va(lights), vb(lights);
            dynamic_cast<const LightVisibility&>(memory.lookup()).visibility(p.x, va.data());
            visibility->visibility(p.x, vb.data());
            ASSERT_EQ(std::memcmp(va.data(), vb.data(), va.size() * sizeof(float)), 0) << "visibility";
        }
        ++compared;
    }
    EXPECT_GT(compared, 200);
    if (levels) {
        EXPECT_GT(finer, 40) << "too few probes in refined cells";
    }
}

TEST(QueryStream, SameBitsAsInMemoryLookup) {
    test::TempDir dir;
    const std::string path = dir.file("v.vdb");
    writeVolume(test::randomShVolume(19, 11, 23, 0.13, 3), path);
    for (OutsidePolicy outside : {OutsidePolicy::Clamp, OutsidePolicy::Throw}) expectSameBits(path, outside, true);
}

TEST(QueryStream, SameBitsWithHalfFloatsFlatAxesAndFarFromOrigin) {
    test::TempDir dir;
    Volume v = test::randomShVolume(9, 1, 12, 0.5, 5);  // one node along y
    writeVolume(v, dir.file("flat.vdb"), WriteOptions{true, true});
    expectSameBits(dir.file("flat.vdb"), OutsidePolicy::Clamp, true);
    Volume far = test::randomShVolume(10, 8, 6, 0.25, 9);
    far.levels[0].grid.origin = Vec3d(4.0e6, -2.5e5, 7.0e5);  // anchored lookups (shifted_lookup.h)
    writeVolume(far, dir.file("far.vdb"));
    expectSameBits(dir.file("far.vdb"), OutsidePolicy::Clamp, true);
    expectSameBits(dir.file("far.vdb"), OutsidePolicy::Throw, true);
}

TEST(QueryStream, SameBitsWithDepthMomentsOnAndOff) {
    test::TempDir dir;
    Volume v = test::randomShVolume(14, 9, 10, 0.2, 11);
    Rng rng(4);
    v.levels[0].depth.resize(v.levels[0].grid.nodeCount() * depth::kFloatsPerNode);
    for (float& f : v.levels[0].depth) f = float(int(rng.uniform() * 256.0f) % 256) / 255.0f;
    writeVolume(v, dir.file("d.vdb"));
    expectSameBits(dir.file("d.vdb"), OutsidePolicy::Clamp, true);
    expectSameBits(dir.file("d.vdb"), OutsidePolicy::Clamp, false);
}

TEST(QueryStream, ReadsOnlyTheLeavesItTouches) {
    test::TempDir dir;
    const std::string path = dir.file("big.vdb");
    writeVolume(test::randomShVolume(64, 64, 64, 0.1, 2), path);  // 8^3 leaves per grid
    auto file = std::make_shared<StreamedVolume>(path);
    EXPECT_EQ(file->totalLeaves(), 9u * 512u);
    EXPECT_EQ(file->loadedLeaves(), 0u);
    const uint64_t topology = file->residentBytes();
    EXPECT_LT(topology * 4, 64ull * 64 * 64 * 108);  // internal nodes of 9 grids: 6 MB here, fixed per grid
    const IrradianceQuery q = makeStreamingQuery(file, OutsidePolicy::Clamp);
    const GridSpec& g = file->header().levels[0].grid;
    q.irradianceWorld(g.node(20, 20, 20) + Vec3d(0.05, 0.05, 0.05), Vec3f(0, 1, 0));  // inside one leaf
    EXPECT_EQ(file->loadedLeaves(), 9u);
    q.irradianceWorld(g.node(20, 31, 7) + Vec3d(0.05, 0.05, 0.05), Vec3f(0, 1, 0));  // across leaf faces in y and z
    EXPECT_EQ(file->loadedLeaves(), 9u + 9u * 4u);
    EXPECT_GE(file->residentBytes(), topology + 45u * (512u * 12u - 64u));  // the values of the leaves read, less their file reference
    EXPECT_TRUE(file->header().levels[0].data.empty());
}

TEST(QueryStream, SameBitsOnBilevelAndAdaptiveLevels) {
    test::TempDir dir;
    writeVolume(test::randomLevelsVolume(LayoutKind::Bilevel, 2, BasisDesc::sh2(), 1, -0.5f, 1.5f), dir.file("b.vdb"));
    writeVolume(test::randomLevelsVolume(LayoutKind::Adaptive, 3, BasisDesc::sh2(), 2, -0.5f, 1.5f), dir.file("a.vdb"));
    for (const char* name : {"b.vdb", "a.vdb"})
        for (OutsidePolicy outside : {OutsidePolicy::Clamp, OutsidePolicy::Throw}) expectSameBits(dir.file(name), outside, true);
    Volume far = test::randomLevelsVolume(LayoutKind::Adaptive, 3, BasisDesc::sh2(), 3, -0.5f, 1.5f);
    for (VolumeLevel& l : far.levels) l.grid.origin += Vec3d(-3.0e6, 1.0e5, 2.5e6);
    writeVolume(far, dir.file("far.vdb"));
    expectSameBits(dir.file("far.vdb"), OutsidePolicy::Clamp, true);
    Volume depth = test::randomLevelsVolume(LayoutKind::Adaptive, 3, BasisDesc::sh2(), 4, -0.5f, 1.5f);
    Rng rng(8);
    for (VolumeLevel& l : depth.levels) {
        l.depth.resize(l.storedNodes() * depth::kFloatsPerNode);
        for (float& f : l.depth) f = float(int(rng.uniform() * 256.0f) % 256) / 255.0f;
    }
    writeVolume(depth, dir.file("depth.vdb"));
    expectSameBits(dir.file("depth.vdb"), OutsidePolicy::Clamp, true);
    expectSameBits(dir.file("depth.vdb"), OutsidePolicy::Clamp, false);
}

// A bake with --cull-solids: level 0 is sparse and cells with a culled corner read 0.
TEST(QueryStream, SameBitsOnACulledBake) {
    test::TempDir dir;
    const std::string vdb = dir.file("culled.vdb");
    std::string log;
    ASSERT_EQ(test::runCommand(std::string(VDBLIGHT_CLI_PATH) + " bake -o " + vdb +
                                   " --resolution 12 --rays 16 --bounces 1 --layout bilevel --cull-solids --quiet 2>&1",
                               &log),
              0)
        << log;
    ASSERT_EQ(metaString(readVolume(vdb).meta, "culling"), "solid-regions");
    expectSameBits(vdb, OutsidePolicy::Clamp, true);
}

// Real SH of every order the presets bake (sh:1 .. sh:4; sh:4 is the default's) on one level,
// and adaptive levels of sh:1 and sh:4, with depth moments weighted and not.
TEST(QueryStream, SameBitsOnShOfAnyOrder) {
    test::TempDir dir;
    for (int order = 1; order <= 4; ++order) {
        const BasisDesc basis = makeBasis("sh:" + std::to_string(order))->desc();
        Volume uniform = test::randomUniformVolume(basis, 11, 7, 9, 0.3, uint64_t(order));
        test::randomDepth(uniform, uint64_t(order));
        const std::string u = dir.file("u" + std::to_string(order) + ".vdb");
        writeVolume(uniform, u);
        expectSameBits(u, OutsidePolicy::Clamp, true);
        if (order != 1 && order != 4) continue;  // the levels of the smallest and the default's order
        expectSameBits(u, OutsidePolicy::Throw, false);
        Volume levels = test::randomLevelsVolume(LayoutKind::Adaptive, 3, basis, uint32_t(order), -0.5f, 1.5f);
        test::randomDepth(levels, uint64_t(order) + 10);
        const std::string l = dir.file("l" + std::to_string(order) + ".vdb");
        writeVolume(levels, l);
        expectSameBits(l, OutsidePolicy::Clamp, true);
        expectSameBits(l, OutsidePolicy::Clamp, false);
    }
    // A flat axis (one node along y): ChannelLookup never descends there.
    Volume flat = test::randomUniformVolume(makeBasis("sh:4")->desc(), 6, 1, 5, 0.5, 3);
    writeVolume(flat, dir.file("flat.vdb"), WriteOptions{true, true});
    expectSameBits(dir.file("flat.vdb"), OutsidePolicy::Clamp, true);
}

// The default bake's kind: sh:4, depth moments and per-light visibility (--direct occlusion:
// exact direct light times interpolated visibility), near and far from the origin; and the
// sh2 volumes of --direct occlusion.
Volume withLights(Volume v, uint64_t seed) {
    v.direct.mode = DirectMode::Occlusion;
    DirectLight point;
    point.kind = DirectLight::Kind::Point;
    point.position = v.levels[0].grid.origin + Vec3d(0.7, 2.5, 0.4);
    point.value = Rgb(3.0f, 2.5f, 2.0f);
    v.direct.lights = {point, squareLight(v.levels[0].grid.origin + Vec3d(1.0, 3.0, 1.0), Vec3d(0, -1, 0), 0.5,
                                          Rgb(5.0f, 5.0f, 4.0f))};
    Rng rng(seed);
    v.levels[0].lightVisibility.resize(v.levels[0].grid.nodeCount() * v.direct.lights.size());
    for (float& f : v.levels[0].lightVisibility) f = rng.uniform() < 0.3f ? 1.0f : rng.uniform();
    return v;
}

TEST(QueryStream, SameBitsOnTheDefaultKindWithLightVisibility) {
    test::TempDir dir;
    Volume v = withLights(test::randomUniformVolume(makeBasis("sh:4")->desc(), 12, 8, 10, 0.25, 4), 5);
    test::randomDepth(v, 6);
    writeVolume(v, dir.file("default.vdb"));
    for (OutsidePolicy outside : {OutsidePolicy::Clamp, OutsidePolicy::Throw}) expectSameBits(dir.file("default.vdb"), outside, true);
    expectSameBits(dir.file("default.vdb"), OutsidePolicy::Clamp, false);
    for (VolumeLevel& l : v.levels) l.grid.origin += Vec3d(2.0e6, 3.0e4, -5.0e5);
    for (DirectLight& light : v.direct.lights) light.translate(Vec3d(2.0e6, 3.0e4, -5.0e5));
    writeVolume(v, dir.file("far.vdb"));
    expectSameBits(dir.file("far.vdb"), OutsidePolicy::Clamp, true);
    writeVolume(withLights(test::randomShVolume(9, 6, 7, 0.3, 8), 9), dir.file("sh2.vdb"), WriteOptions{true, true});
    expectSameBits(dir.file("sh2.vdb"), OutsidePolicy::Clamp, true);
}

TEST(QueryStream, DefaultKindReadsOnlyTheLeavesItTouchesAndReleasesThem) {
    test::TempDir dir;
    Volume v = withLights(test::randomUniformVolume(makeBasis("sh:4")->desc(), 32, 32, 32, 0.1, 2), 3);
    test::randomDepth(v, 4);
    writeVolume(v, dir.file("big.vdb"));
    auto file = std::make_shared<StreamedVolume>(dir.file("big.vdb"));
    constexpr uint64_t kGrids = 25 + 4 + 2;  // coefficients, depth moments, two lights' visibility
    EXPECT_EQ(file->totalLeaves(), kGrids * 64u);
    const IrradianceQuery q = makeStreamingQuery(file, OutsidePolicy::Clamp);
    const GridSpec& g = file->header().levels[0].grid;
    const Vec3d x = g.node(20, 20, 20) + Vec3d(0.05, 0.05, 0.05);  // inside one leaf of every grid
    const Rgb first = q.irradianceWorld(x, Vec3f(0, 1, 0));
    EXPECT_EQ(file->loadedLeaves(), kGrids);
    const uint64_t loaded = file->residentBytes();
    file->releaseLeaves();
    EXPECT_EQ(file->loadedLeaves(), 0u);
    EXPECT_LT(file->residentBytes(), loaded);
    EXPECT_TRUE(sameBits(q.irradianceWorld(x, Vec3f(0, 1, 0)), first));
    EXPECT_EQ(file->loadedLeaves(), kGrids);
}

TEST(QueryStream, RefusesKindsItDoesNotRead) {
    test::TempDir dir;
    Volume bins = test::randomLevelsVolume(LayoutKind::Adaptive, 2, bins::basis(bins::parseBasisSpec("bins:2")), 1, 0.0f, 1.0f);
    writeVolume(bins, dir.file("bins.vdb"));
    auto other = std::make_shared<StreamedVolume>(dir.file("bins.vdb"));
    EXPECT_NE(streamingSupported(*other).find("basis"), std::string::npos) << streamingSupported(*other);
    EXPECT_THROW(makeStreamingQuery(other, OutsidePolicy::Clamp), FormatError);
    // Culled sh:N levels: ChannelLookup refuses them in memory, so streaming does too.
    Volume culled = test::randomLevelsVolume(LayoutKind::Adaptive, 2, makeBasis("sh:3")->desc(), 1, 0.0f, 1.0f);
    culled.meta["culling"] = std::string("solid-regions");
    writeVolume(culled, dir.file("culled.vdb"));
    auto culledFile = std::make_shared<StreamedVolume>(dir.file("culled.vdb"));
    EXPECT_NE(streamingSupported(*culledFile).find("culled 'sh:3'"), std::string::npos) << streamingSupported(*culledFile);
    EXPECT_THROW(StreamedVolume(dir.file("missing.vdb")), IoError);
    test::writeTextFile(dir.file("junk.vdb"), "not a vdb file");
    EXPECT_THROW(StreamedVolume(dir.file("junk.vdb")), FormatError);
}

}  // namespace
}  // namespace vdblight
