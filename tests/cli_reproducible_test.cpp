// Reproducible files end to end (issue 17): every pass gives byte-identical .vdb files for
// one and two threads, `info` shows the content hash, --no-reproducible keeps the run's time.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {
using test::runCli;

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Pass {
    const char* name;
    const char* args;
};

// Small bakes of every pass (and the options that change what a pass does).
const Pass kPasses[] = {
    {"point gather", "--resolution 6 --rays 32"},
    // The default bake's passes (issue 15): --direct occlusion (light list + visibility), one
    // probe-to-probe pass, depth moments; only the node budget and rays are made small.
    {"default quality", "--resolution 6 --rays 32 --quality default"},
    {"default quality, error-targeted, two probe passes",
     "--resolution 5 --target-error 0.03 --probe-passes 2 --min-rays 8 --max-rays 32"},
    {"adaptive layout", "--layout adaptive --levels 2 --refine 2 --resolution 5 --rays 16"},
    {"antialiased", "--sampling antialiased --resolution 5 --rays 16"},
    {"back-face invalidation", "--invalidate-backface 0.1 --resolution 5 --rays 16"},
    {"error-targeted", "--target-error 0.2 --min-rays 8 --max-rays 32 --resolution 5"},
    {"photons", "--method photons --photons 20000 --resolution 6"},
    {"compact photons", "--method photons --compact --photons 20000 --resolution 6"},
    {"bins", "--basis bins:3 --resolution 5 --rays 18"},
    {"bilevel bins, half floats", "--basis bins:2 --layout bilevel --resolution 4 --rays 8 --half"},
};

TEST(CliReproducible, OneAndTwoThreadsGiveIdenticalFilesForEveryPass) {
    test::TempDir dir;
    for (const Pass& p : kPasses) {
        SCOPED_TRACE(p.name);
        const std::string a = dir.file("t1.vdb"), b = dir.file("t2.vdb");
        const test::CliRun ra = runCli(std::string("bake -q -o ") + a + " --seed 5 --threads 1 " + p.args);
        const test::CliRun rb = runCli(std::string("bake -q -o ") + b + " --seed 5 --threads 2 " + p.args);
        ASSERT_EQ(ra.status, 0) << ra.output;
        ASSERT_EQ(rb.status, 0) << rb.output;
        const std::string ba = fileBytes(a), bb = fileBytes(b);
        ASSERT_GT(ba.size(), 1000u);
        EXPECT_TRUE(ba == bb) << "files differ (sizes " << ba.size() << ", " << bb.size() << ")";
        if (std::string(p.name).rfind("default quality", 0) == 0) {  // what the default adds is in the file
            const Volume v = readVolume(a);
            EXPECT_TRUE(v.hasDepth());
            EXPECT_TRUE(v.direct.hasVisibility());
            EXPECT_EQ(std::get<int64_t>(v.meta.at("probe_passes")), std::string(p.name) == "default quality" ? 1 : 2);
            EXPECT_EQ(v.basis.kind, std::string(p.name) == "default quality" ? "sh:4" : "sh2");  // an error target: sh2
        }
        const ContentHash h = fileContentHash(a);
        EXPECT_TRUE(h.uuidFromContent);
        const test::CliRun info = runCli("info " + a);
        EXPECT_NE(info.output.find("content hash: sha256 " + h.sha256), std::string::npos) << info.output;
    }
}

TEST(CliReproducible, NoReproducibleKeepsTheRunsTimeAndThreads) {
    test::TempDir dir;
    const std::string a = dir.file("a.vdb"), b = dir.file("b.vdb");
    ASSERT_EQ(runCli("bake -q -o " + a + " --resolution 4 --rays 8 --threads 2").status, 0);
    ASSERT_EQ(runCli("bake -q -o " + b + " --resolution 4 --rays 8 --threads 2 --no-reproducible").status, 0);
    const Volume va = readVolume(a), vb = readVolume(b);
    EXPECT_EQ(va.meta.count("bake_seconds"), 0u);
    EXPECT_EQ(va.meta.count("threads"), 0u);
    EXPECT_EQ(vb.meta.count("bake_seconds"), 1u);
    EXPECT_EQ(metaNumber(vb.meta, "threads", 0), 2);
    EXPECT_EQ(va.levels[0].data, vb.levels[0].data);
    // info --json is a JSON document (stdout alone) that states the hash, the grids and the
    // metadata as the file holds them.
    std::string out;
    ASSERT_EQ(test::runCommand(test::cliPath() + " info --json " + a + " 2>/dev/null", &out), 0);
    const nlohmann::json info = nlohmann::json::parse(out);
    EXPECT_EQ(info["content_sha256"], fileContentHash(a).sha256) << out;
    EXPECT_EQ(info["uuid_from_content"], true) << out;
    EXPECT_EQ(info["basis"], va.basis.kind) << out;
    const GridSpec& g = va.levels[0].grid;
    EXPECT_EQ(info["levels"][0]["dims"], nlohmann::json::array({g.nx, g.ny, g.nz})) << out;
    EXPECT_EQ(info["levels"][0]["spacing"], g.spacing) << out;  // every digit: it reads back as the same double
    EXPECT_EQ(info["levels"][0]["nodes"], va.levels[0].storedNodes()) << out;
    EXPECT_EQ(info["metadata"].size(), va.meta.size()) << out;
    EXPECT_EQ(info["metadata"]["probe_passes"], std::get<int64_t>(va.meta.at("probe_passes"))) << out;
}

}  // namespace
}  // namespace vdblight
