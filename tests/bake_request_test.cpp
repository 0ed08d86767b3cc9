// How a bake request resolves (bake/bake.h: resolveBakeRequest, checkBakeRequest): the pass its
// options select, the --quality presets' values as the command line documents them, and the
// point gather's memory estimate per node. (The bakes themselves: bake_volume_test.)
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"

namespace vdblight {
namespace {

/// What a --quality preset resolves to on the uniform point gather (bake_request.cpp,
/// qualityPreset): its rays, nodes and passes of the node filter, one probe pass through the
/// surface cache, depth moments, SH order 4, the guide and the blend (issue 32, session 22),
/// and whether it takes the extra cache paths, pass 0's two rounds and the probe pass's.
struct PointGatherPreset {
    uint32_t rays;
    uint64_t nodes;
    int nodeFilter;
    bool extraCachePaths, firstPassByError, probePassByError;
};
void expectPointGatherPreset(const BakeRequest& d, const PointGatherPreset& e, const std::string& what) {
    EXPECT_EQ(d.params.get<uint32_t>("rays"), e.rays) << what;
    EXPECT_EQ(d.params.get<int>("probe-passes"), 1) << what;
    EXPECT_EQ(*d.nodes, e.nodes) << what;
    EXPECT_TRUE(d.params.get<bool>("depth-moments")) << what;
    EXPECT_EQ(d.basis, "sh:4") << what;
    EXPECT_EQ(d.pass, "gather") << what;
    EXPECT_EQ(d.params.get<std::string>("probe-cache"), "surface") << what;
    EXPECT_EQ(d.params.get<int>("node-filter"), e.nodeFilter) << what;
    EXPECT_TRUE(d.params.get<bool>("guide-probe-directions")) << what;  // pass 0's map (direction_guide.h)
    EXPECT_TRUE(d.params.get<bool>("blend-first-pass")) << what;        // pass 0 blended in (first_pass_blend.h)
    EXPECT_EQ(d.params.get<bool>("extra-cache-paths"), e.extraCachePaths) << what;
    EXPECT_EQ(d.params.get<bool>("first-pass-by-error"), e.firstPassByError) << what;  // first_pass_by_error.h
    EXPECT_EQ(d.params.get<bool>("probe-pass-by-error"), e.probePassByError) << what;  // issue 32, session 26
}
TEST(BakeRequest, SelectsThePassTheOptionsName) {
    const auto selected = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return checkBakeRequest(r).name();
    };
    EXPECT_EQ(selected([](BakeRequest&) {}), "gather");
    EXPECT_EQ(selected([](BakeRequest& r) { r.quality = "high"; }), "gather");
    EXPECT_EQ(selected([](BakeRequest& r) { r.quality = "high"; r.params.set("target-error", 0.03); }), "adaptive");
    EXPECT_EQ(selected([](BakeRequest& r) { r.sampling = "antialiased"; }), "antialiased");
    EXPECT_EQ(selected([](BakeRequest& r) { r.layout = "bilevel"; }), "levels");
    EXPECT_EQ(selected([](BakeRequest& r) { r.basis = "moment:2"; r.layout = "adaptive"; }), "bins");
    EXPECT_EQ(selected([](BakeRequest& r) { r.method = "photons"; }), "photons");
}

/// Issue 32, session 25: three light samples at each probe-pass path's end in `fast`, the default
/// and `high` (tiled too: a tile's probe pass is the single bake's); one in the preview, where the
/// probe pass does not run, and where given.
TEST(BakeRequest, ProbeLightSamplesComeFromThePreset) {
    const auto samples = [](const std::function<void(BakeRequest&)>& edit) {
        BakeRequest r;
        edit(r);
        return resolveBakeRequest(r).params.get<uint32_t>("probe-light-samples");
    };
    EXPECT_EQ(samples([](BakeRequest&) {}), 3u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.tiles = 2; }), 3u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.quality = "fast"; }), 3u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.quality = "high"; }), 3u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.quality = "preview"; }), 1u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.params.set("probe-passes", 0.0); }), 1u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.method = "photons"; }), 1u);
    EXPECT_EQ(samples([](BakeRequest& r) { r.params.set("probe-light-samples", 5.0); }), 5u);
    EXPECT_EQ(samples([](BakeRequest& r) {
                  r.quality = "preview";
                  r.params.set("probe-light-samples", 2.0);
              }),
              2u);
    EXPECT_NE(describeQuality("default").find("3 light samples at each probe-pass path's end"), std::string::npos);
    EXPECT_EQ(describeQuality("preview").find("light samples"), std::string::npos);
}

TEST(BakeRequest, PresetsResolveAsTheCommandLineDocumentsThem) {
    BakeRequest r;
    // Issue 32, session 22: the preview's guide and blend, which pay on the default's budget and
    // tile (stage_carry.h), in a tiled bake too; not its other two levers.
    expectPointGatherPreset(resolveBakeRequest(r), {1024, 16384, 0, false, false, false}, "default");
    r.tiles = 2;
    expectPointGatherPreset(resolveBakeRequest(r), {1024, 16384, 0, false, false, false}, "default, tiled");
    r.tiles.reset();
    // Issue 32: the preview is the default's method on fewer nodes and rays, filtered across
    // nodes, with the cache fed where pass 0 is noisiest and pass 0's rays by its error.
    r.quality = "preview";
    BakeRequest d = resolveBakeRequest(r);
    expectPointGatherPreset(d, {64, 8192, 1, true, true, false}, "preview");
    EXPECT_EQ(d.params.get<uint32_t>("extra-cache-paths-per-node"), 256u);
    r.tiles = 2;  // a tile's stage 1 reads pass 0's map and values from stage 0, not every node's errors
    expectPointGatherPreset(resolveBakeRequest(r), {64, 8192, 1, false, false, false}, "preview, tiled");
    r.tiles.reset();
    r.params.set("target-error", 0.05);  // the adaptive pass has no node filter
    EXPECT_EQ(resolveBakeRequest(r).params.get<int>("node-filter"), 0);
    r.params.unset("target-error");
    // Issue 32 item 1: the default's grid and probe pass at 224 rays, filtered across nodes,
    // pass 0's and the probe pass's rays by their error (session 26) and 128 extra cache paths
    // per noisy node where the bake is not tiled (session 24: half the preview's per node, on
    // twice its nodes).
    r.quality = "fast";
    d = resolveBakeRequest(r);
    expectPointGatherPreset(d, {224, 16384, 1, true, true, true}, "fast");
    EXPECT_EQ(d.params.get<uint32_t>("extra-cache-paths-per-node"), 128u);
    r.params.set("extra-cache-paths-per-node", 64.0);  // given, it is kept
    EXPECT_EQ(resolveBakeRequest(r).params.get<uint32_t>("extra-cache-paths-per-node"), 64u);
    r.params.unset("extra-cache-paths-per-node");
    r.tiles = 2;  // tiled: the filter is the merge's, the two rounds and the extra paths are left out
    expectPointGatherPreset(resolveBakeRequest(r), {224, 16384, 1, false, false, false}, "fast, tiled");
    r.tiles.reset();
    r.quality = "high";
    d = resolveBakeRequest(r);
    expectPointGatherPreset(d, {2048, 16384, 0, false, false, false}, "high");  // as the default (issue 32, session 22)
    EXPECT_FALSE(d.params.has("target-error"));
    r.params.set("target-error", 0.03);  // an error target: the adaptive pass, SH order 2, its own ray caps
    d = resolveBakeRequest(r);
    EXPECT_EQ(d.pass, "adaptive");
    EXPECT_EQ(d.basis, "sh2");
    EXPECT_EQ(d.params.get<uint32_t>("min-rays"), 64u);
    EXPECT_EQ(d.params.get<uint32_t>("max-rays"), 2048u);
    EXPECT_EQ(d.params.get<int>("probe-passes"), 1);
    r.params.unset("target-error");
    r.quality = "default";
    r.sampling = "antialiased";  // presets apply to the uniform SH point gather only
    d = resolveBakeRequest(r);
    EXPECT_EQ(d.params.get<uint32_t>("rays"), 256u);
    EXPECT_EQ(d.params.get<int>("probe-passes"), 0);
    EXPECT_FALSE(d.nodes.has_value());
    EXPECT_EQ(d.basis, "sh2");
}

// No --basis: SH order 4 only where the default's point gather runs with a fixed budget; every
// option that needs SH order 2 (or another pass) keeps it, and an explicit basis wins.
TEST(BakeRequest, TheDefaultBasisIsShFourOnlyForThePointGather) {
    const auto basisOf = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return resolveBakeRequest(r).basis;
    };
    EXPECT_EQ(basisOf([](BakeRequest&) {}), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.params.set("rays", 64); r.resolution = 8; }), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.params.set("target-error", 0.05); }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.params.set("sh-window", true); }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.layout = "bilevel"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.sampling = "antialiased"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.method = "photons"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.params.set("invalidate-backface", 0.1); }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.quality = "preview"; }), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.basis = "sh2"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.basis = "sh:3"; }), "sh:3");
    // An explicit sh2 keeps the preset's rays: only the basis is the caller's.
    BakeRequest r;
    r.basis = "sh2";
    EXPECT_EQ(resolveBakeRequest(r).params.get<uint32_t>("rays"), 1024u);
    EXPECT_EQ(&checkBakeRequest(r), &checkBakeRequest(BakeRequest{}));
}

// The probe pass reads the surface bins by default where the bake runs exactly one probe pass
// in the point gather (the presets'); elsewhere the nodes, and an explicit choice wins.
TEST(BakeRequest, TheDefaultProbeCacheIsTheSurfaceBinsWithOneProbePass) {
    const auto cacheOf = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return resolveBakeRequest(r).params.get<std::string>("probe-cache");
    };
    EXPECT_EQ(cacheOf([](BakeRequest&) {}), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "high"; }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.basis = "sh2"; r.params.set("rays", 64); }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "preview"; }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "preview"; r.params.set("probe-passes", 0); }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.params.set("probe-passes", 2); }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.params.set("target-error", 0.05); }), "nodes");  // the adaptive pass
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.method = "photons"; }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.params.set("probe-cache", "nodes"); }), "nodes");
    BakeRequest r;
    EXPECT_NO_THROW(checkBakeRequest(r));
    r.quality = "preview";
    EXPECT_NO_THROW(checkBakeRequest(r));
    r.params.set("probe-passes", 0);
    r.params.set("probe-cache", "surface");  // asked for, without a probe pass
    EXPECT_THROW(checkBakeRequest(r), ValueError);
}

// Photon volumes take the default's grid (on 16 nodes their interpolation dominated the error,
// issue 15 item 5); preview and an explicit grid keep theirs.
TEST(BakeRequest, PhotonsTakeTheDefaultGridUnlessTold) {
    BakeRequest r;
    r.method = "photons";
    BakeRequest d = resolveBakeRequest(r);
    EXPECT_EQ(d.pass, "photons");
    ASSERT_TRUE(d.nodes.has_value());
    EXPECT_EQ(*d.nodes, 16384u);
    EXPECT_EQ(d.params.get<int>("probe-passes"), 0);  // the gather's presets stay the gather's
    EXPECT_TRUE(d.params.get<bool>("depth-moments"));  // but its depth moments apply (docs/methods.md)
    EXPECT_EQ(d.params.get<uint64_t>("photons"), 4'000'000u);
    r.quality = "high";
    EXPECT_TRUE(resolveBakeRequest(r).params.get<bool>("depth-moments"));
    r.quality = "preview";
    EXPECT_FALSE(resolveBakeRequest(r).nodes.has_value());
    EXPECT_EQ(resolveBakeRequest(r).params.get<uint64_t>("photons"), 1'000'000u);
    EXPECT_FALSE(resolveBakeRequest(r).params.get<bool>("depth-moments"));
    r.quality = "default";
    r.resolution = 6;
    d = resolveBakeRequest(r);
    EXPECT_FALSE(d.nodes.has_value());
    EXPECT_EQ(*d.resolution, 6);
    EXPECT_TRUE(d.params.get<bool>("depth-moments"));
    r.params.set("depth-moments", false);  // --no-depth-moments
    EXPECT_FALSE(resolveBakeRequest(r).params.get<bool>("depth-moments"));
}

TEST(BakeRequest, TheMemoryEstimateCountsTheGuidesMapAndTheBlendsCopy) {
    // The default's point gather keeps, per node, its sh:4 values (75 floats) twice, the probe
    // pass's SH order-2 cache (27 floats), the surface bins' share, the guide's map (128 cells
    // of a float sum and a count: 1 KiB) and the blend's copy of pass 0's values (75 floats).
    BakeRequest r;
    const BakeRequest resolved = resolveBakeRequest(r);
    const Pass& gather = findPass(resolved.pass);
    ASSERT_EQ(resolved.pass, "gather");
    const std::size_t all = gather.bytesPerNode(resolved);
    r.params.set("guide-probe-directions", false);
    const std::size_t noGuide = gather.bytesPerNode(resolveBakeRequest(r));
    r.params.set("blend-first-pass", false);
    const std::size_t neither = gather.bytesPerNode(resolveBakeRequest(r));
    EXPECT_EQ(all - noGuide, 1024u);
    EXPECT_EQ(noGuide - neither, 75u * sizeof(float));
    EXPECT_GE(neither, (2 * 75 + 27) * sizeof(float));
}

}  // namespace
}  // namespace vdblight
