// The one entry point of a bake (bake_volume.h) and the Pass interface (pass.h): a bake
// through the library and one through `vdblight bake` give the same file, byte for byte; every
// registered pass refuses an option outside its declared range with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_util.h"
#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"

namespace vdblight {
namespace {

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Case {
    const char* name;
    const char* cliArgs;        ///< what the command line is given
    void (*fill)(BakeRequest&); ///< the same request, filled by hand as a library caller would
};

// Each case: the command line's options and the BakeRequest fields a library caller sets for
// them. Small grids and ray counts keep the bakes short; every pass and the presets run.
const Case kCases[] = {
    // The default bake (--quality default: node budget, 1024 rays, one probe pass, depth
    // moments, --direct occlusion, SH order 4) with fewer rays, so that the test stays short.
    {"default", "--rays 16", [](BakeRequest& r) { r.rays = 16; }},
    {"preview", "--quality preview", [](BakeRequest& r) { r.quality = "preview"; }},
    {"high", "--quality high --resolution 3 --rays 24",
     [](BakeRequest& r) {
         r.quality = "high";
         r.resolution = 3;
         r.rays = 24;
     }},
    {"error-targeted", "--target-error 0.03 --resolution 5 --min-rays 8 --max-rays 32",
     [](BakeRequest& r) {
         r.targetError = 0.03;
         r.resolution = 5;
         r.minRays = 8;
         r.maxRays = 32;
     }},
    {"layout adaptive", "--layout adaptive --levels 2 --refine 2 --resolution 5 --rays 16",
     [](BakeRequest& r) {
         r.layout = "adaptive";
         r.levels = 2;
         r.refine = 2;
         r.resolution = 5;
         r.rays = 16;
     }},
    {"sampling antialiased", "--sampling antialiased --resolution 5 --rays 16",
     [](BakeRequest& r) {
         r.sampling = "antialiased";
         r.resolution = 5;
         r.rays = 16;
     }},
    {"basis bins:3", "--basis bins:3 --resolution 5 --rays 18",
     [](BakeRequest& r) {
         r.basis = "bins:3";
         r.resolution = 5;
         r.rays = 18;
     }},
    {"basis sh:3 (the generic gather of a registry basis)", "--basis sh:3 --resolution 5 --rays 18",
     [](BakeRequest& r) {
         r.basis = "sh:3";
         r.resolution = 5;
         r.rays = 18;
     }},
    {"method photons, compact", "--method photons --photons 20000 --resolution 6 --compact",
     [](BakeRequest& r) {
         r.method = "photons";
         r.photons = 20000;
         r.resolution = 6;
         r.compact = true;
     }},
};

TEST(BakeVolume, LibraryAndCommandLineWriteIdenticalFiles) {
    test::TempDir dir;
    const std::string scenePath = defaultScenePath();
    const Scene scene = loadScene(scenePath, SceneLoadOptions{});
    for (const Case& c : kCases) {
        SCOPED_TRACE(c.name);
        const std::string viaCli = dir.file("cli.vdb"), viaLibrary = dir.file("library.vdb");
        const test::CliRun run =
            test::runCli("bake '" + scenePath + "' -q --seed 7 --threads 2 -o " + viaCli + " " + c.cliArgs);
        ASSERT_EQ(run.status, 0) << run.output;

        BakeRequest request;
        request.seed = 7;
        request.threads = 1;  // files are the same for any thread count
        request.sceneFile = scenePath;  // what the file says it was baked from, as the command line writes
        c.fill(request);
        BakeReport report;
        bakeToFile(scene, request, viaLibrary, nullptr, &report);
        ASSERT_NE(report.pass, nullptr);

        const std::string a = fileBytes(viaCli), b = fileBytes(viaLibrary);
        ASSERT_GT(a.size(), 1000u);
        EXPECT_TRUE(a == b) << "files differ (sizes " << a.size() << ", " << b.size() << ") for pass "
                            << report.pass->name();
    }
}

TEST(BakeVolume, SelectsThePassTheOptionsName) {
    const auto selected = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return checkBakeRequest(r).name();
    };
    EXPECT_EQ(selected([](BakeRequest&) {}), "gather");
    EXPECT_EQ(selected([](BakeRequest& r) { r.quality = "high"; }), "gather");
    EXPECT_EQ(selected([](BakeRequest& r) { r.quality = "high"; r.targetError = 0.03; }), "adaptive");
    EXPECT_EQ(selected([](BakeRequest& r) { r.sampling = "antialiased"; }), "antialiased");
    EXPECT_EQ(selected([](BakeRequest& r) { r.layout = "bilevel"; }), "levels");
    EXPECT_EQ(selected([](BakeRequest& r) { r.basis = "moment:2"; r.layout = "adaptive"; }), "bins");
    EXPECT_EQ(selected([](BakeRequest& r) { r.method = "photons"; }), "photons");
}

TEST(BakeVolume, PresetsResolveAsTheCommandLineDocumentsThem) {
    BakeRequest r;
    BakeRequest d = resolveBakeRequest(r);
    EXPECT_EQ(*d.rays, 1024u);
    EXPECT_EQ(*d.probePasses, 1);
    EXPECT_EQ(*d.nodes, 16384u);
    EXPECT_TRUE(*d.depthMoments);
    EXPECT_EQ(d.basis, "sh:4");
    EXPECT_EQ(d.pass, "gather");
    EXPECT_EQ(*d.nodeFilter, 0);
    EXPECT_FALSE(*d.guideProbeDirections);
    EXPECT_FALSE(*d.blendFirstPass);
    // Issue 32: the preview is the default's method on fewer nodes and rays, filtered across nodes.
    r.quality = "preview";
    d = resolveBakeRequest(r);
    EXPECT_EQ(*d.rays, 128u);
    EXPECT_EQ(*d.probePasses, 1);
    EXPECT_EQ(*d.nodes, 2048u);
    EXPECT_TRUE(*d.depthMoments);
    EXPECT_EQ(d.basis, "sh:4");
    EXPECT_EQ(d.probeCache, "surface");
    EXPECT_EQ(*d.nodeFilter, 1);
    EXPECT_EQ(d.pass, "gather");
    EXPECT_TRUE(*d.guideProbeDirections);  // its probe pass's directions from pass 0's map (direction_guide.h)
    EXPECT_TRUE(*d.blendFirstPass);        // and pass 0's values blended in (pass_blend.h)
    r.tiles = 2;  // a tile's probe pass runs in a stage of its own, without pass 0's
    EXPECT_FALSE(*resolveBakeRequest(r).guideProbeDirections);
    EXPECT_FALSE(*resolveBakeRequest(r).blendFirstPass);
    r.tiles.reset();
    r.targetError = 0.05;  // the adaptive pass has no node filter
    EXPECT_EQ(*resolveBakeRequest(r).nodeFilter, 0);
    r.targetError.reset();
    r.quality = "high";
    d = resolveBakeRequest(r);
    EXPECT_FALSE(d.targetError.has_value());
    EXPECT_EQ(*d.rays, 2048u);
    EXPECT_EQ(*d.probePasses, 1);
    EXPECT_EQ(*d.nodes, 16384u);
    EXPECT_TRUE(*d.depthMoments);
    EXPECT_EQ(d.basis, "sh:4");
    r.targetError = 0.03;  // an error target: the adaptive pass, SH order 2, its own ray caps
    d = resolveBakeRequest(r);
    EXPECT_EQ(d.pass, "adaptive");
    EXPECT_EQ(d.basis, "sh2");
    EXPECT_EQ(*d.minRays, 64u);
    EXPECT_EQ(*d.maxRays, 2048u);
    EXPECT_EQ(*d.probePasses, 1);
    r.targetError.reset();
    r.quality = "default";
    r.sampling = "antialiased";  // presets apply to the uniform SH point gather only
    d = resolveBakeRequest(r);
    EXPECT_EQ(*d.rays, 256u);
    EXPECT_EQ(*d.probePasses, 0);
    EXPECT_FALSE(d.nodes.has_value());
    EXPECT_EQ(d.basis, "sh2");
}

// No --basis: SH order 4 only where the default's point gather runs with a fixed budget; every
// option that needs SH order 2 (or another pass) keeps it, and an explicit basis wins.
TEST(BakeVolume, TheDefaultBasisIsShFourOnlyForThePointGather) {
    const auto basisOf = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return resolveBakeRequest(r).basis;
    };
    EXPECT_EQ(basisOf([](BakeRequest&) {}), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.rays = 64; r.resolution = 8; }), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.targetError = 0.05; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.shWindow = true; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.layout = "bilevel"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.sampling = "antialiased"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.method = "photons"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.invalidateBackface = 0.1; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.quality = "preview"; }), "sh:4");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.basis = "sh2"; }), "sh2");
    EXPECT_EQ(basisOf([](BakeRequest& r) { r.basis = "sh:3"; }), "sh:3");
    // An explicit sh2 keeps the preset's rays: only the basis is the caller's.
    BakeRequest r;
    r.basis = "sh2";
    EXPECT_EQ(*resolveBakeRequest(r).rays, 1024u);
    EXPECT_EQ(&checkBakeRequest(r), &checkBakeRequest(BakeRequest{}));
}

// The probe pass reads the surface bins by default where the bake runs exactly one probe pass
// in the point gather (the presets'); elsewhere the nodes, and an explicit choice wins.
TEST(BakeVolume, TheDefaultProbeCacheIsTheSurfaceBinsWithOneProbePass) {
    const auto cacheOf = [](void (*fill)(BakeRequest&)) {
        BakeRequest r;
        fill(r);
        return resolveBakeRequest(r).probeCache;
    };
    EXPECT_EQ(cacheOf([](BakeRequest&) {}), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "high"; }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.basis = "sh2"; r.rays = 64; }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "preview"; }), "surface");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.quality = "preview"; r.probePasses = 0; }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.probePasses = 2; }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.targetError = 0.05; }), "nodes");  // the adaptive pass
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.method = "photons"; }), "nodes");
    EXPECT_EQ(cacheOf([](BakeRequest& r) { r.probeCache = "nodes"; }), "nodes");
    BakeRequest r;
    EXPECT_NO_THROW(checkBakeRequest(r));
    r.quality = "preview";
    EXPECT_NO_THROW(checkBakeRequest(r));
    r.probePasses = 0;
    r.probeCache = "surface";  // asked for, without a probe pass
    EXPECT_THROW(checkBakeRequest(r), ValueError);
}

// Photon volumes take the default's grid (on 16 nodes their interpolation dominated the error,
// issue 15 item 5); preview and an explicit grid keep theirs.
TEST(BakeVolume, PhotonsTakeTheDefaultGridUnlessTold) {
    BakeRequest r;
    r.method = "photons";
    BakeRequest d = resolveBakeRequest(r);
    EXPECT_EQ(d.pass, "photons");
    ASSERT_TRUE(d.nodes.has_value());
    EXPECT_EQ(*d.nodes, 16384u);
    EXPECT_EQ(*d.probePasses, 0);  // the gather's presets stay the gather's
    EXPECT_TRUE(*d.depthMoments);  // but its depth moments apply (docs/methods.md)
    EXPECT_EQ(*d.photons, 4'000'000u);
    r.quality = "high";
    EXPECT_TRUE(*resolveBakeRequest(r).depthMoments);
    r.quality = "preview";
    EXPECT_FALSE(resolveBakeRequest(r).nodes.has_value());
    EXPECT_EQ(*resolveBakeRequest(r).photons, 1'000'000u);
    EXPECT_FALSE(*resolveBakeRequest(r).depthMoments);
    r.quality = "default";
    r.resolution = 6;
    d = resolveBakeRequest(r);
    EXPECT_FALSE(d.nodes.has_value());
    EXPECT_EQ(*d.resolution, 6);
    EXPECT_TRUE(*d.depthMoments);
    r.depthMoments = false;  // --no-depth-moments
    EXPECT_FALSE(*resolveBakeRequest(r).depthMoments);
}

/// A request that selects `pass`.
BakeRequest requestFor(const Pass& pass) {
    BakeRequest r;
    const std::string n = pass.name();
    if (n == "adaptive") r.targetError = 0.1;
    if (n == "antialiased") r.sampling = "antialiased";
    if (n == "levels") r.layout = "adaptive";
    if (n == "bins") r.basis = "bins:2";
    if (n == "photons") r.method = "photons";
    return r;
}

TEST(BakeVolume, EveryPassRefusesAnOptionOutsideItsRangeWithOneLine) {
    ASSERT_GE(passRegistry().size(), 6u);
    for (const Pass* pass : passRegistry()) {
        SCOPED_TRACE(pass->name());
        const BakeRequest base = requestFor(*pass);
        EXPECT_EQ(&checkBakeRequest(base), pass);
        EXPECT_NO_THROW(pass->validate(base));
        EXPECT_FALSE(pass->description().empty());
        int refused = 0;
        for (const PassOption& o : pass->options()) {
            SCOPED_TRACE(o.name);
            EXPECT_FALSE(o.help.empty());
            EXPECT_FALSE(o.defaultValue.empty());
            if (!o.number || !o.setNumber) continue;
            // Just outside the range: above a finite maximum, else below the minimum.
            BakeRequest r = base;
            const double outside = std::isfinite(o.max) && o.max < 1e12 ? o.max + 1 : o.minExclusive ? o.min : o.min - 1;
            o.setNumber(r, outside);
            const std::optional<double> stored = o.number(r);
            if (!stored || (*stored >= o.min && *stored <= o.max && !(o.minExclusive && *stored == o.min)))
                continue;  // a flag, or a value its field cannot hold
            try {
                pass->validate(r);
                ADD_FAILURE() << "--" << o.name << " " << outside << " was accepted";
            } catch (const ValueError& e) {
                const std::string message = e.what();
                EXPECT_EQ(message.find('\n'), std::string::npos) << message;
                EXPECT_NE(message.find("--" + o.name), std::string::npos) << message;
                ++refused;
            }
            EXPECT_THROW(checkBakeRequest(r), ValueError);
        }
        EXPECT_GT(refused, 0) << "no option of the pass was tried";
    }
}

TEST(BakeVolume, RefusesOptionsThePassDoesNotTake) {
    const auto refusal = [](void (*fill)(BakeRequest&)) -> std::string {
        BakeRequest r;
        fill(r);
        try {
            checkBakeRequest(r);
        } catch (const ValueError& e) {
            return e.what();
        }
        return "accepted";
    };
    EXPECT_EQ(refusal([](BakeRequest& r) { r.fit = "least-squares"; }), "--fit needs --sampling antialiased");
    EXPECT_EQ(refusal([](BakeRequest& r) { r.compact = true; }), "--compact applies to --method photons only");
    EXPECT_NE(refusal([](BakeRequest& r) { r.method = "photons"; r.shWindow = true; }).find("--sh-window applies"),
              std::string::npos);
    // Every pass takes depth moments, the photon pass in tiles too (each tile bakes a run of nodes').
    EXPECT_EQ(refusal([](BakeRequest& r) { r.method = "photons"; r.depthMoments = true; r.tiles = 2; r.tile = 0; }),
              "accepted");
    EXPECT_NE(refusal([](BakeRequest& r) { r.sampling = "antialiased"; r.probePasses = 2; }).find("--probe-passes works"),
              std::string::npos);
    EXPECT_NE(refusal([](BakeRequest& r) { r.sampling = "antialiased"; r.domain = "nowhere"; })
                  .find("--domain must be all or interior, got 'nowhere'"),
              std::string::npos);
    EXPECT_NE(refusal([](BakeRequest& r) { r.pass = "wavelets"; }).find("unknown pass 'wavelets'"), std::string::npos);
    EXPECT_EQ(refusal([](BakeRequest&) {}), "accepted");
}

TEST(BakeVolume, OptionsSetFromTextAsTheCommandLineGivesThem) {
    for (const Pass* pass : passRegistry())
        for (const PassOption& o : pass->options()) {
            SCOPED_TRACE(pass->name() + " --" + o.name);
            ASSERT_TRUE(o.setText);
            BakeRequest r;
            if (o.flag) {
                o.setText(r, "true");
                EXPECT_EQ(o.number(r), std::optional<double>(1.0));
                EXPECT_THROW(o.setText(r, "maybe"), ValueError);
            } else if (!o.choices.empty()) {
                o.setText(r, o.choices.back());
                EXPECT_EQ(o.word(r), std::optional<std::string>(o.choices.back()));
            } else {
                o.setText(r, "2");
                EXPECT_EQ(o.number(r), std::optional<double>(2.0));
                try {
                    o.setText(r, "2x");
                    ADD_FAILURE() << "'2x' accepted";
                } catch (const ValueError& e) {
                    EXPECT_NE(std::string(e.what()).find("--" + o.name), std::string::npos) << e.what();
                }
            }
        }
}

TEST(BakeVolume, RefusesAGridThatWouldNotFitBeforeBaking) {
    const Scene scene = loadScene(defaultScenePath(), SceneLoadOptions{});
    BakeRequest r;
    r.resolution = 200000;
    try {
        bakeVolume(scene, r);
        FAIL() << "accepted";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("nodes would need"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace vdblight
