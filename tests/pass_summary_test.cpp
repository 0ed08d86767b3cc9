// The summary `vdblight bake` prints is the pass's (Pass::summary, issue 30 item 2), and the
// command line's pass options are the passes' declarations (passOptionTable): a pass shapes
// its summary through the Pass interface, and every option a pass declares is offered once,
// marked with every pass that takes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "vdblight/bake/bake.h"
#include "vdblight/scene/scene.h"

namespace vdblight {
namespace {

/// A pass that bakes nothing and only says its rays and contents in its own words; the rest
/// of the summary is the base's.
class WordsPass : public Pass {
public:
    std::string name() const override { return "words"; }
    std::string description() const override { return "a pass of words"; }
    std::vector<PassOption> options() const override { return {}; }
    std::size_t bytesPerNode(const BakeRequest&) const override { return 0; }
    std::string untileable(const BakeRequest&) const override { return {}; }
    Volume run(const BakeContext&, const BakeRequest&, const GridSpec&, BakeReport&) const override { return {}; }
    std::string summaryRays(const BakeSummaryInput&) const override { return "a few"; }
    std::string summaryStored(const BakeSummaryInput&) const override { return "(words only)"; }
};

TEST(PassSummary, TheSummaryIsWrittenByThePassThatBaked) {
    const Scene scene = loadScene(defaultScenePath(), SceneLoadOptions{});
    BakeRequest request;
    request.resolution = 3;
    request.rays = 8;
    request.probePasses = 0;
    BakeReport report;
    const Volume volume = bakeVolume(scene, request, nullptr, &report);
    ASSERT_EQ(report.pass->name(), "gather");

    const BakeSummaryInput in{scene, "(test)", "out.vdb", request, report, volume};
    const std::string gathered = bakeSummary(in);
    EXPECT_NE(gathered.find("with 8 rays per node"), std::string::npos) << gathered;
    EXPECT_NE(gathered.find(". Wrote out.vdb (basis sh:4"), std::string::npos) << gathered;

    // The same report told by another pass: its parts replace the gather's, the rest stays.
    const WordsPass words;
    BakeReport told = report;
    told.pass = &words;
    const std::string said = bakeSummary({scene, "(test)", "out.vdb", request, told, volume});
    EXPECT_NE(said.find("with a few rays per node"), std::string::npos) << said;
    EXPECT_NE(said.find(". Wrote out.vdb (words only).\n"), std::string::npos) << said;
    EXPECT_EQ(said.find("8 rays per node"), std::string::npos) << said;
    EXPECT_NE(said.find("Baked 27 nodes (3 x 3 x 3"), std::string::npos) << said;
}

TEST(PassSummary, ASkippedTileSaysSoWhateverThePass) {
    const Scene scene = loadScene(defaultScenePath(), SceneLoadOptions{});
    BakeRequest request;
    request.tiles = 4;
    request.tile = 2;
    BakeReport report;
    report.skipped = true;
    const std::string said = bakeSummary({scene, "", "t2.vdb", request, report, Volume{}});
    EXPECT_EQ(said, "Tile 2 of 4 is already baked with the same scene and parameters (t2.vdb): skipped.\n");
}

TEST(PassSummary, EveryDeclaredOptionIsOfferedOnceWithThePassesThatTakeIt) {
    const std::vector<PassOptionEntry> table = passOptionTable();
    std::set<std::string> names;
    for (const PassOptionEntry& e : table) EXPECT_TRUE(names.insert(e.option.name).second) << e.option.name;
    for (const Pass* pass : passRegistry())
        for (const PassOption& o : pass->options()) {
            const auto entry = std::find_if(table.begin(), table.end(),
                                            [&](const PassOptionEntry& e) { return e.option.name == o.name; });
            ASSERT_NE(entry, table.end()) << o.name;
            EXPECT_NE(std::find(entry->passes.begin(), entry->passes.end(), pass->name()), entry->passes.end())
                << o.name << " of " << pass->name();
            EXPECT_NE(entry->help.find(pass->name()), std::string::npos) << entry->help;
        }
    const auto rays = std::find_if(table.begin(), table.end(), [](const PassOptionEntry& e) { return e.option.name == "rays"; });
    ASSERT_NE(rays, table.end());
    EXPECT_GT(rays->passes.size(), 1u);
    EXPECT_NE(rays->help.find(" [passes gather, "), std::string::npos) << rays->help;
}

}  // namespace
}  // namespace vdblight
