// manifest.json keeps its meaning (issue 30: built as a JSON object instead of streamed text).
// tests/data/manifests/ holds the manifests the streamed writer made (vdblight before the
// change) for every layout, every container, depth moments exported and not, and the three
// direct-light modes; the same bakes and exports now must parse to equal JSON values (key
// order and number spelling may differ). A deliberate change of the manifest updates these
// files in the same commit (each is the manifest.json of the export below of the same name).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "test_util.h"

namespace vdblight {
namespace {

// Small bakes of the default scene (a Cornell box with one polygon luminaire): only their
// lattice, lights and kinds reach the manifest, not their values.
const std::map<std::string, std::string> kBakes = {
    {"sh4", "--resolution 4 --rays 8 --bounces 1 --basis sh:4 --no-depth-moments --direct baked --seed 1"},
    {"depth", "--resolution 4 --rays 8 --bounces 1 --basis sh:4 --depth-moments --direct runtime --seed 1"},
    // The pinned manifests predate the shadow edges (issue 32), which add textures and a
    // "direct.shadow_edges" object: the gpu_export_test row of the edges reads those.
    {"occlusion", "--resolution 4 --rays 8 --bounces 1 --no-depth-moments --direct occlusion --no-shadow-edges --seed 1"},
    {"bins", "--resolution 4 --rays 8 --bounces 1 --basis bins:2 --no-depth-moments --seed 1"},
    {"photons", "--method photons --photons 2000 --resolution 4 --no-depth-moments --seed 1"},
    {"compact", "--method photons --photons 2000 --resolution 4 --no-depth-moments --compact --seed 1"},
};

struct ExportCase {
    const char* name;  ///< tests/data/manifests/<name>.json
    const char* bake;
    const char* args;
};

const ExportCase kExports[] = {
    {"sh2_ktx2", "sh4", "--format ktx2 --layout sh2"},
    {"sh2_packed_ktx2", "sh4", "--format ktx2 --layout sh2-packed"},
    {"sh2_packed_dds_float", "sh4", "--format dds --layout sh2-packed --float"},
    {"sh2_packed_exr_atlas", "sh4", "--format exr-atlas --layout sh2-packed"},
    {"sh2_packed_raw", "sh4", "--format raw --layout sh2-packed"},
    {"sh1_ktx2", "sh4", "--format ktx2 --layout sh1"},
    {"sh2_32_ktx2", "sh4", "--format ktx2 --layout sh2-32"},
    {"sh1_16_dds", "sh4", "--format dds --layout sh1-16"},
    {"basis_sh4_ktx2", "sh4", "--format ktx2 --layout basis"},
    {"depth_sh2_packed_ktx2", "depth", "--format ktx2 --layout sh2-packed"},
    {"depth_not_exported_ktx2", "depth", "--format ktx2 --layout sh2-packed --resolution 7"},
    {"runtime_lights_raw", "depth", "--format raw --layout sh1"},
    {"occlusion_sh2_packed_ktx2", "occlusion", "--format ktx2 --layout sh2-packed"},
    {"bins_ktx2", "bins", "--format ktx2 --layout bins"},
    {"vectors_ktx2", "photons", "--format ktx2 --layout vectors"},
    {"compact_ktx2", "compact", "--format ktx2 --layout compact"},
};

nlohmann::json parseFile(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return nlohmann::json::parse(in);
}

TEST(ManifestJson, EveryLayoutParsesToTheValuesOfTheStreamedWriter) {
    test::TempDir dir;
    std::string log;
    for (const auto& [name, options] : kBakes)
        ASSERT_EQ(test::runCommand(test::cliPath() + " bake -q -o " + dir.file(name + ".vdb") + " " + options, &log), 0) << log;
    for (const ExportCase& c : kExports) {
        const std::string out = dir.file(std::string("x_") + c.name);
        ASSERT_EQ(test::runCommand(test::cliPath() + " export -q " + dir.file(std::string(c.bake) + ".vdb") + " -o " + out +
                                       " " + c.args, &log), 0) << c.name << ": " << log;
        const nlohmann::json before =
            parseFile(std::string(VDBLIGHT_SOURCE_DIR) + "/tests/data/manifests/" + c.name + ".json");
        const nlohmann::json now = parseFile(out + "/manifest.json");
        EXPECT_EQ(now, before) << c.name << ": differences (JSON Patch from the old manifest): "
                               << nlohmann::json::diff(before, now).dump();
    }
}

}  // namespace
}  // namespace vdblight
