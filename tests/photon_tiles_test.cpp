// Tiles of the photon pass (issue 17): a tile traces a run of the photon batches and writes
// the whole grid's exact sums (photon_sums.h); the merge of any number of tiles writes the
// single-process bake's bytes; bad sets of tiles are refused by name. Their depth moments:
// photon_tiles_depth_test.cpp.
#include <gtest/gtest.h>

#include <limits>

#include "grids.h"
#include "photon_tile_fixtures.h"
#include "test_util.h"
#include "vdblight/bake/bake.h"
#include "vdblight/core/errors.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight {
namespace {

using test::bakePhotonTiles;
using test::bytesOf;
using test::photonRequest;
using test::photonRoom;

TEST(PhotonTiles, MergesOfOneTwoThreeAndTenTilesAreTheSingleBake) {
    test::TempDir dir;
    const Scene scene = photonRoom();
    const BakeRequest r = photonRequest();
    BakeReport whole;
    const Volume volume = bakeToFile(scene, r, dir.file("whole.vdb"), nullptr, &whole);
    ASSERT_EQ(whole.photons->batches, 10u);
    const std::string expected = bytesOf(dir.file("whole.vdb"));
    ASSERT_GT(expected.size(), 1000u);
    for (int count : {1, 2, 3, 10}) {
        SCOPED_TRACE(count);
        std::vector<std::string> paths = bakePhotonTiles(scene, r, dir, count, "n" + std::to_string(count) + "_");
        std::reverse(paths.begin(), paths.end());  // any order
        const MergedTiles merged = mergeTiles(paths);
        const std::string out = dir.file("merged" + std::to_string(count) + ".vdb");
        writeVolume(merged.volume, out, merged.write);
        EXPECT_TRUE(bytesOf(out) == expected) << "merge of " << count << " photon tiles differs from the single bake";
        // The counts of every batch, summed: the single bake's metadata.
        EXPECT_EQ(merged.volume.meta.at("photon_segments"), volume.meta.at("photon_segments"));
        EXPECT_EQ(merged.volume.meta.at("photon_face_crossings"), volume.meta.at("photon_face_crossings"));
        EXPECT_EQ(merged.volume.meta.at("rays_intersect"), volume.meta.at("rays_intersect"));
    }
    // More tiles than batches: refused with the reason, before tracing.
    BakeRequest eleven = r;
    eleven.tiles = 11;
    eleven.tile = 0;
    try {
        bakeToFile(scene, eleven, dir.file("eleven.vdb"));
        ADD_FAILURE() << "11 tiles of 10 batches were baked";
    } catch (const ValueError& e) {
        EXPECT_NE(std::string(e.what()).find("photon batches"), std::string::npos) << e.what();
    }
}

TEST(PhotonTiles, CompactAndHalfFloatMergesAreTheSingleBake) {
    test::TempDir dir;
    const Scene scene = photonRoom();
    BakeRequest r = photonRequest();
    r.params.set("compact", true);
    r.tileParameters += "--compact=true\n";
    bakeToFile(scene, r, dir.file("whole.vdb"));
    const MergedTiles merged = mergeTiles(bakePhotonTiles(scene, r, dir, 3, "c"));
    EXPECT_TRUE(merged.write.halfFloat);
    writeVolume(merged.volume, dir.file("merged.vdb"), merged.write);
    EXPECT_TRUE(bytesOf(dir.file("merged.vdb")) == bytesOf(dir.file("whole.vdb")));
}

TEST(PhotonTiles, ATileHasTheSameBitsOnOneAndTwoThreads) {
    test::TempDir dir;
    const Scene scene = photonRoom();
    BakeRequest r = photonRequest();
    r.tiles = 3;
    r.tile = 1;
    r.threads = 1;
    bakeToFile(scene, r, dir.file("one.vdb"));
    r.threads = 2;
    bakeToFile(scene, r, dir.file("two.vdb"));
    EXPECT_TRUE(bytesOf(dir.file("one.vdb")) == bytesOf(dir.file("two.vdb")));
    // Baked again with the same parameters: skipped (resumable, as every tile).
    BakeReport again;
    bakeToFile(scene, r, dir.file("two.vdb"), nullptr, &again);
    EXPECT_TRUE(again.skipped);
}

TEST(PhotonTiles, MissingDuplicateAndMismatchedTilesAreRefusedByName) {
    test::TempDir dir;
    const Scene scene = photonRoom();
    const BakeRequest r = photonRequest();
    const std::vector<std::string> t = bakePhotonTiles(scene, r, dir, 3, "t");
    BakeRequest other = r;
    other.seed = 6;
    other.tileParameters = "--method=photons\n--photons=40000\n--resolution=6\n--seed=6\n";
    const std::vector<std::string> seed6 = bakePhotonTiles(scene, other, dir, 3, "s");
    auto refusal = [](const std::vector<std::string>& paths) -> std::string {
        try {
            mergeTiles(paths);
        } catch (const Error& e) {
            return e.what();
        }
        return "merged";
    };
    EXPECT_NE(refusal({t[0], t[2]}).find("tile 1 of 3 is missing"), std::string::npos) << refusal({t[0], t[2]});
    const std::string duplicate = refusal({t[0], t[1], t[2], t[1]});
    EXPECT_NE(duplicate.find("are both tile 1 of 3"), std::string::npos) << duplicate;
    const std::string mixed = refusal({t[0], seed6[1], t[2]});
    EXPECT_NE(mixed.find("different scenes or parameters"), std::string::npos) << mixed;
    EXPECT_NE(mixed.find(seed6[1]), std::string::npos) << mixed;
    // A tile of another count names both files.
    const std::vector<std::string> two = bakePhotonTiles(scene, r, dir, 2, "two");
    const std::string count = refusal({t[0], two[1], t[2]});
    EXPECT_NE(count.find("is a tile of 2"), std::string::npos) << count;
    EXPECT_NE(count.find(two[1]), std::string::npos) << count;
    // A photon tile is not a volume.
    EXPECT_THROW(readVolume(t[0]), FormatError);
}

/// Sums written as a tile and merged come back exactly: values beyond 64 bits and negative
/// ones (two's complement words), split over two tiles' runs of batches.
TEST(PhotonTiles, TileFilesHoldTheExact128BitSums) {
    test::TempDir dir;
    PhotonSums a;
    a.grid = test::makeGrid({-1, 2, 0.5}, 0.25, 3, 2, 4);
    a.exponent = -70;
    a.batches = 5;
    a.firstBatch = 0, a.endBatch = 2;
    const std::size_t n = a.grid.nodeCount() * iv::kFloatsPerNode;
    a.values.resize(n);
    PhotonSums b = a;
    b.firstBatch = 2, b.endBatch = 5;
    for (std::size_t i = 0; i < n; ++i) {
        const PhotonFixed big = PhotonFixed(int64_t(i * 2654435761u % 1000003)) << 70;  // above 2^64
        a.values[i] = (i % 3 == 0 ? -big : big) + PhotonFixed(i);
        b.values[i] = (i % 5 == 0 ? -1 : 1) * (PhotonFixed(int64_t(i) * 977) << 40) - PhotonFixed(7 * i);
    }
    Metadata meta;
    meta["photon_segments"] = int64_t(10);
    TileId id;
    id.count = 2, id.paramsHash = tileParamsHash("scene", "photons\n");
    id.index = 0;
    writePhotonTile(a, meta, id, dir.file("a.vdb"), {}, false);
    id.index = 1;
    meta["photon_segments"] = int64_t(32);
    writePhotonTile(b, meta, id, dir.file("b.vdb"), {}, false);
    PhotonSums sum = a;
    sum.firstBatch = 0, sum.endBatch = 5;
    for (std::size_t i = 0; i < n; ++i) sum.values[i] += b.values[i];
    const MergedTiles merged = mergeTiles({dir.file("b.vdb"), dir.file("a.vdb")});
    const Volume expected = photonVolume(sum, {});
    EXPECT_EQ(merged.volume.levels[0].data, expected.levels[0].data);
    EXPECT_EQ(std::get<int64_t>(merged.volume.meta.at("photon_segments")), 42);
    // Sums that would overflow 127 bits are refused (only a damaged or forged file has them).
    for (PhotonFixed& v : a.values) v = PhotonFixed(1) << 126;
    for (PhotonFixed& v : b.values) v = PhotonFixed(1) << 126;
    id.index = 0;
    writePhotonTile(a, meta, id, dir.file("a.vdb"), {}, false);
    id.index = 1;
    writePhotonTile(b, meta, id, dir.file("b.vdb"), {}, false);
    EXPECT_THROW(mergeTiles({dir.file("a.vdb"), dir.file("b.vdb")}), FormatError);
    // Sums of part of the batches are no volume.
    EXPECT_THROW(photonVolume(a, {}), ValueError);
}

TEST(PhotonTiles, FixedPointRoundsToNearestAndRefusesTheOutOfRange) {
    PhotonFixed v = 0;
    const double scale = 0x1p10;  // quantum 2^-10
    ASSERT_TRUE(toPhotonFixed(1.5f, 1.0, v));
    EXPECT_TRUE(v == 2);
    ASSERT_TRUE(toPhotonFixed(-1.5f, 1.0, v));
    EXPECT_TRUE(v == -2);
    ASSERT_TRUE(toPhotonFixed(2.25f, 1.0, v));
    EXPECT_TRUE(v == 2);
    ASSERT_TRUE(toPhotonFixed(-2.75f, 1.0, v));
    EXPECT_TRUE(v == -3);
    ASSERT_TRUE(toPhotonFixed(0.75f, scale, v));  // exactly representable: exact
    EXPECT_TRUE(v == 768);
    ASSERT_TRUE(toPhotonFixed(0x1p70f, 0x1p40, v));  // beyond 64 bits
    EXPECT_TRUE(v == PhotonFixed(1) << 110);
    ASSERT_TRUE(toPhotonFixed(-0x1.8p65f, 1.0, v));
    EXPECT_TRUE(v == -(PhotonFixed(3) << 64));
    // The fast integer paths against the compiler's conversion and a rounding reference.
    uint64_t state = 12345;
    for (int i = 0; i < 100000; ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const float f = std::ldexp(float(state >> 40) / float(1 << 24) + 0.5f, int(state % 140) - 40) *
                        (state & (1ull << 20) ? -1.0f : 1.0f);
        const double d = double(f) * scale;
        if (std::abs(d) > 0x1p118) {
            EXPECT_FALSE(toPhotonFixed(f, scale, v));
            continue;
        }
        ASSERT_TRUE(toPhotonFixed(f, scale, v)) << f;
        ASSERT_TRUE(v == PhotonFixed(std::round(d))) << f;  // nearest, ties away from zero
    }
    EXPECT_FALSE(toPhotonFixed(0x1p80f, 0x1p40, v));  // 2^120 quanta > the per-batch 2^118
    EXPECT_FALSE(toPhotonFixed(std::numeric_limits<float>::infinity(), 1.0, v));
    EXPECT_FALSE(toPhotonFixed(std::numeric_limits<float>::quiet_NaN(), 1.0, v));
    EXPECT_EQ(photonSumExponent(1.0), -80);
    EXPECT_EQ(photonSumExponent(3.0), -79);
    EXPECT_EQ(photonSumExponent(0.3), -82);
    EXPECT_THROW(photonSumExponent(0.0), ValueError);
    uint64_t first = 0, end = 0;
    photonTileBatches(10, 3, 2, first, end);
    EXPECT_EQ(first, 6u);
    EXPECT_EQ(end, 10u);
    EXPECT_THROW(photonTileBatches(10, 11, 0, first, end), ValueError);
}

}  // namespace
}  // namespace vdblight
