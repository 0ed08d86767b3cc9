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

// Each case: the command line's options and what a library caller sets in a BakeRequest for
// them. Small grids and ray counts keep the bakes short; every pass and the presets run.
const Case kCases[] = {
    // The default bake (--quality default: node budget, 1024 rays, one probe pass, depth
    // moments, --direct occlusion, SH order 4) with fewer rays, so that the test stays short.
    {"default", "--rays 16", [](BakeRequest& r) { r.params.set("rays", 16); }},
    {"preview", "--quality preview", [](BakeRequest& r) { r.quality = "preview"; }},
    {"fast", "--quality fast --resolution 4 --rays 16",
     [](BakeRequest& r) {
         r.quality = "fast";
         r.resolution = 4;
         r.params.set("rays", 16);
     }},
    {"high", "--quality high --resolution 3 --rays 24",
     [](BakeRequest& r) {
         r.quality = "high";
         r.resolution = 3;
         r.params.set("rays", 24);
     }},
    {"error-targeted", "--target-error 0.03 --resolution 5 --min-rays 8 --max-rays 32",
     [](BakeRequest& r) {
         r.params.set("target-error", 0.03);
         r.resolution = 5;
         r.params.set("min-rays", 8);
         r.params.set("max-rays", 32);
     }},
    {"layout adaptive", "--layout adaptive --levels 2 --refine 2 --resolution 5 --rays 16",
     [](BakeRequest& r) {
         r.layout = "adaptive";
         r.params.set("levels", 2);
         r.params.set("refine", 2);
         r.resolution = 5;
         r.params.set("rays", 16);
     }},
    {"sampling antialiased", "--sampling antialiased --resolution 5 --rays 16",
     [](BakeRequest& r) {
         r.sampling = "antialiased";
         r.resolution = 5;
         r.params.set("rays", 16);
     }},
    {"basis bins:3", "--basis bins:3 --resolution 5 --rays 18",
     [](BakeRequest& r) {
         r.basis = "bins:3";
         r.resolution = 5;
         r.params.set("rays", 18);
     }},
    {"basis sh:3 (the generic gather of a registry basis)", "--basis sh:3 --resolution 5 --rays 18",
     [](BakeRequest& r) {
         r.basis = "sh:3";
         r.resolution = 5;
         r.params.set("rays", 18);
     }},
    {"method photons, compact", "--method photons --photons 20000 --resolution 6 --compact",
     [](BakeRequest& r) {
         r.method = "photons";
         r.params.set("photons", 20000);
         r.resolution = 6;
         r.params.set("compact", true);
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

/// A request that selects `pass`.
BakeRequest requestFor(const Pass& pass) {
    BakeRequest r;
    const std::string n = pass.name();
    if (n == "adaptive") r.params.set("target-error", 0.1);
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
            if (o.kind() != PassOption::Kind::Number) continue;
            // Just outside the range: above a finite maximum, else below the minimum.
            BakeRequest r = base;
            const double outside = std::isfinite(o.max) && o.max < 1e12 ? o.max + 1 : o.minExclusive ? o.min : o.min - 1;
            r.params.set(o.name, outside);
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
    EXPECT_EQ(refusal([](BakeRequest& r) { r.params.set("fit", "least-squares"); }),
              "--fit needs --sampling antialiased");
    EXPECT_EQ(refusal([](BakeRequest& r) { r.params.set("compact", true); }),
              "--compact applies to --method photons only");
    EXPECT_NE(refusal([](BakeRequest& r) {
                  r.method = "photons";
                  r.params.set("sh-window", true);
              }).find("--sh-window applies"),
              std::string::npos);
    // Every pass takes depth moments, the photon pass in tiles too (each tile bakes a run of nodes').
    EXPECT_EQ(refusal([](BakeRequest& r) {
                  r.method = "photons";
                  r.params.set("depth-moments", true);
                  r.tiles = 2;
                  r.tile = 0;
              }),
              "accepted");
    EXPECT_NE(refusal([](BakeRequest& r) {
                  r.sampling = "antialiased";
                  r.params.set("probe-passes", 2);
              }).find("--probe-passes works"),
              std::string::npos);
    EXPECT_NE(refusal([](BakeRequest& r) {
                  r.sampling = "antialiased";
                  r.params.set("domain", "nowhere");
              }).find("--domain must be all or interior, got 'nowhere'"),
              std::string::npos);
    EXPECT_NE(refusal([](BakeRequest& r) { r.pass = "wavelets"; }).find("unknown pass 'wavelets'"), std::string::npos);
    EXPECT_EQ(refusal([](BakeRequest&) {}), "accepted");
}

TEST(BakeVolume, OptionsSetFromTextAsTheCommandLineGivesThem) {
    for (const Pass* pass : passRegistry())
        for (const PassOption& o : pass->options()) {
            SCOPED_TRACE(pass->name() + " --" + o.name);
            BakeRequest r;
            if (o.flag) {
                r.params.setText(o.name, "true");
                EXPECT_TRUE(r.params.get<bool>(o.name));
                EXPECT_THROW(r.params.setText(o.name, "maybe"), ValueError);
            } else if (!o.choices.empty()) {
                r.params.setText(o.name, o.choices.back());
                EXPECT_EQ(r.params.get<std::string>(o.name), o.choices.back());
            } else {
                r.params.setText(o.name, "2");
                EXPECT_EQ(r.params.get<double>(o.name), 2.0);
                try {
                    r.params.setText(o.name, "2x");
                    ADD_FAILURE() << "'2x' accepted";
                } catch (const ValueError& e) {
                    EXPECT_NE(std::string(e.what()).find("--" + o.name), std::string::npos) << e.what();
                }
            }
        }
}

TEST(BakeVolume, PassParametersKnowTheDeclarationsNamesKindsAndDefaults) {
    BakeRequest r;
    // Unknown names and values of another kind are refused, naming the option.
    EXPECT_THROW(r.params.set("rayz", 64), ValueError);
    EXPECT_THROW(r.params.get<int>("rayz"), ValueError);
    EXPECT_THROW(r.params.find<int>("rayz"), ValueError);
    EXPECT_THROW(r.params.set("rays", "many"), ValueError);
    EXPECT_THROW(r.params.set("domain", 3), ValueError);
    EXPECT_THROW(r.params.set("compact", 1.0), ValueError);
    EXPECT_THROW(r.params.set("rays", 2.5), ValueError);  // a whole number
    EXPECT_THROW(r.params.get<std::string>("rays"), ValueError);
    EXPECT_THROW(BakeRequest().params.set("rays", -4).get<uint32_t>("rays"), ValueError);  // no wrap-around
    // Not given: the declared default, where the declaration has one of its own...
    EXPECT_EQ(r.params.get<std::string>("domain"), "interior");
    EXPECT_EQ(r.params.get<std::string>("fit"), "projection");
    EXPECT_EQ(r.params.get<int>("refine"), 3);
    EXPECT_EQ(r.params.get<double>("refine-distance"), 0.0);
    EXPECT_EQ(r.params.get<uint32_t>("max-rays"), 2048u);
    EXPECT_FALSE(r.params.get<bool>("compact"));
    EXPECT_EQ(r.params.find<int>("refine"), std::nullopt);
    // ...and the presets' where it depends on them (resolveBakeRequest fills it in).
    EXPECT_THROW(r.params.get<uint32_t>("rays"), ValueError);
    EXPECT_EQ(resolveBakeRequest(r).params.get<uint32_t>("rays"), 1024u);
    // Given: the value, of the type asked for.
    r.params.set("rays", 64).set("domain", "all").set("compact", true);
    EXPECT_EQ(r.params.get<uint32_t>("rays"), 64u);
    EXPECT_EQ(r.params.find<double>("rays"), std::optional<double>(64.0));
    EXPECT_EQ(r.params.get<std::string>("domain"), "all");
    EXPECT_TRUE(r.params.get<bool>("compact"));
    r.params.unset("rays");
    EXPECT_FALSE(r.params.has("rays"));
    r.params.set("domain", "");  // no word is not given, as `--domain ""` on the command line
    EXPECT_FALSE(r.params.has("domain"));
    // One name, one meaning: every pass that declares an option gives it the same kind and
    // default, so that the default get answers is every such pass's.
    for (const PassOptionEntry& e : passOptionTable())
        for (const Pass* pass : passRegistry())
            for (const PassOption& o : pass->options()) {
                if (o.name != e.option.name) continue;
                SCOPED_TRACE(pass->name() + " --" + o.name);
                EXPECT_EQ(o.kind(), e.option.kind());
                EXPECT_EQ(o.integer, e.option.integer);
                EXPECT_EQ(o.defaultValue, e.option.defaultValue);
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
