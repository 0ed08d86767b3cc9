// `vdblight --help` and `vdblight bake --help` say what the code does (issue 29): the bake's
// description and every preset's help come from the library's resolution of the presets
// (describeQuality, resolveBakeRequest), and a preview bake does what its help says. A help
// text written by hand that drifts from the presets fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "cli_util.h"
#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

using namespace vdblight;
using namespace vdblight::test;

namespace {
BakeRequest resolved(const std::string& quality, const std::string& method = "gather") {
    BakeRequest r;
    r.quality = quality;
    r.method = method;
    return resolveBakeRequest(r);
}

/// "V1 with --quality preview, V2 with fast, V3 with default, V4 with high", or "V" if all agree:
/// the form of the presets' defaults in --help, built here from resolveBakeRequest.
template <typename Field>
std::string perPreset(Field field, const std::string& method = "gather") {
    std::vector<std::string> v;
    for (const std::string& q : qualityNames()) v.push_back(field(resolved(q, method)));
    if (v[0] == v[1] && v[1] == v[2] && v[2] == v[3]) return v[0];
    return v[0] + " with --quality preview, " + v[1] + " with fast, " + v[2] + " with default, " + v[3] + " with high";
}
}  // namespace

TEST(CliHelp, EachPresetIsDescribedFromWhatItResolvesTo) {
    ASSERT_EQ(qualityNames(), (std::vector<std::string>{"preview", "fast", "default", "high"}));
    for (const std::string& q : qualityNames()) {
        const BakeRequest r = resolved(q);
        const std::string text = describeQuality(q);
        SCOPED_TRACE(q + ": " + text);
        EXPECT_NE(text.find(std::to_string(r.params.get<uint32_t>("rays")) + " rays per node"), std::string::npos);
        EXPECT_NE(text.find("basis " + r.basis + ","), std::string::npos);
        EXPECT_NE(text.find(r.params.get<bool>("depth-moments") ? ", depth moments" : "no depth moments"),
                  std::string::npos);
        if (r.nodes) {
            EXPECT_NE(text.find("about " + std::to_string(*r.nodes) + " nodes"), std::string::npos);
        }
        const int passes = r.params.find<int>("probe-passes").value_or(0);
        EXPECT_EQ(text.find(std::to_string(passes) + " probe-to-probe pass") != std::string::npos, passes > 0);
        EXPECT_NE(
            text.find(std::to_string(resolved(q, "photons").params.get<uint64_t>("photons") / 1000000) + " M photons"),
            std::string::npos);
    }
    EXPECT_THROW(describeQuality("ultra"), ValueError);
}

TEST(CliHelp, TopLevelAndBakeHelpShowThePresetsAndTheirDefaults) {
    const CliRun top = runCli("--help");
    ASSERT_EQ(top.status, 0) << top.output;
    EXPECT_NE(top.output.find("by default " + describeQuality("default")), std::string::npos) << top.output;
    EXPECT_EQ(top.output.find("SH order-2 irradiance volume"), std::string::npos) << "the old, stale description";

    const CliRun bake = runCli("bake --help");
    ASSERT_EQ(bake.status, 0) << bake.output;
    for (const std::string& q : qualityNames())
        EXPECT_NE(bake.output.find(q + ": " + describeQuality(q)), std::string::npos) << q << "\n" << bake.output;
    // The passes' options whose defaults follow the preset.
    const std::string rays =
        perPreset([](const BakeRequest& r) { return std::to_string(r.params.get<uint32_t>("rays")); });
    const std::string passes =
        perPreset([](const BakeRequest& r) { return std::to_string(r.params.get<int>("probe-passes")); });
    const std::string photons =
        perPreset([](const BakeRequest& r) { return std::to_string(r.params.get<uint64_t>("photons")); }, "photons");
    const std::string depth =
        perPreset([](const BakeRequest& r) { return std::string(r.params.get<bool>("depth-moments") ? "on" : "off"); });
    EXPECT_NE(bake.output.find("--rays NUMBER=" + rays + " for the uniform SH point gather"), std::string::npos) << rays;
    EXPECT_NE(bake.output.find("--probe-passes NUMBER=" + passes), std::string::npos) << passes;
    EXPECT_NE(bake.output.find("--photons NUMBER=" + photons), std::string::npos) << photons;
    EXPECT_NE(bake.output.find("--method photons): " + depth), std::string::npos) << depth;
    // No option claims a preset samples to an error target: none does.
    EXPECT_EQ(resolved("high").params.find<double>("target-error"), std::nullopt);
    EXPECT_EQ(bake.output.find("0.03 with high"), std::string::npos);
}

TEST(CliHelp, APreviewBakeDoesWhatItsHelpSays) {
    TempDir dir;
    const BakeRequest r = resolved("preview");
    const CliRun run = runCli("bake --quality preview --threads 2 -o " + (dir.path() / "p.vdb").string());
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("with " + std::to_string(r.params.get<uint32_t>("rays")) +
                              " rays per node (+ 1 probe-to-probe pass)"),
              std::string::npos)
        << run.output;
    ASSERT_TRUE(r.nodes.has_value());  // a node budget (issue 32)
    const std::size_t baked = run.output.find("Baked ");
    ASSERT_NE(baked, std::string::npos) << run.output;
    const double nodes = std::stod(run.output.substr(baked + 6));
    EXPECT_GT(nodes, 0.5 * double(*r.nodes)) << run.output;
    // The budget's rule (node_budget.h): at least 16 nodes on the longest axis, 16^3 in a cube.
    const double most = std::max(2.0 * double(*r.nodes), std::pow(double(kBudgetMinNodesOnLongestAxis), 3));
    EXPECT_LE(nodes, most) << run.output;
    const CliRun info = runCli("info " + (dir.path() / "p.vdb").string());
    ASSERT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("basis: " + r.basis + " "), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("node_filter_passes = " + std::to_string(r.params.get<int>("node-filter"))),
              std::string::npos)
        << info.output;
}
