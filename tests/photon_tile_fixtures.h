// What the tests of photon tiles share (photon_tiles_test.cpp, photon_tiles_depth_test.cpp): a
// small photon bake with several batches, its tiles baked one by one, a file's bytes.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_util.h"
#include "vdblight/bake/bake.h"

namespace vdblight::test {

inline std::string bytesOf(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A closed grey room lit by an emissive ceiling patch: photons bounce, so every face of the
/// grid sees many batches' crossings.
inline Scene photonRoom() {
    return makeFurnaceBox({0, 0, 0}, {1, 0.8f, 0.9f}, {1.0f, 0.8f, 0.6f}, {0.6f, 0.6f, 0.6f});
}

/// 40 000 photons on 6 x 5 x 5 nodes: batches of 4096 photons (the minimum), 10 batches.
inline BakeRequest photonRequest() {
    BakeRequest r;
    r.method = "photons";
    r.params.set("photons", 40000);
    r.resolution = 6;
    r.seed = 5;
    r.threads = 2;
    r.tileParameters = "--method=photons\n--photons=40000\n--resolution=6\n--seed=5\n";
    return r;
}

/// Tiles 0 .. count - 1 of `r` baked into dir/<prefix><i>.vdb (tile i on 1 + i % 2 threads).
inline std::vector<std::string> bakePhotonTiles(const Scene& scene, BakeRequest r, const TempDir& dir, int count,
                                                const std::string& prefix) {
    std::vector<std::string> paths;
    for (int t = 0; t < count; ++t) {
        r.tiles = count;
        r.tile = t;
        r.threads = 1 + t % 2;
        paths.push_back(dir.file(prefix + std::to_string(t) + ".vdb"));
        BakeReport report;
        bakeToFile(scene, r, paths.back(), nullptr, &report);
        EXPECT_TRUE(report.photonSums);
        EXPECT_FALSE(report.skipped);
    }
    return paths;
}

}  // namespace vdblight::test
