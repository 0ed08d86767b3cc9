// Tests of the volume module: Volume checks and the .vdb reader/writer (docs/format.md).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <iterator>
#include <random>
#include <thread>

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

#include "test_util.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

namespace fs = std::filesystem;

/// An SH volume of nx x ny x nz nodes with random values, about a tenth of them exact zeros
/// (and one node entirely zero), so that "zero" is never mistaken for "not stored".
Volume makeVolume(int nx, int ny, int nz, uint32_t seed = 1) {
    Volume v;
    v.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid.origin = Vec3d(-1.25, 0.5, 3.0);
    level.grid.spacing = 0.375;
    level.grid.nx = nx, level.grid.ny = ny, level.grid.nz = nz;
    level.data.resize(level.grid.nodeCount() * std::size_t(v.basis.channelCount()) * 3);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-2.0f, 10.0f);
    for (float& x : level.data) x = (rng() % 10 == 0) ? 0.0f : value(rng);
    std::fill_n(level.data.begin(), v.basis.channelCount() * 3, 0.0f);  // node 0
    v.levels.push_back(std::move(level));
    return v;
}

openvdb::GridPtrVecPtr readAllGrids(const std::string& path, openvdb::MetaMap::Ptr* fileMeta = nullptr) {
    openvdb::initialize();
    openvdb::io::File file(path);
    file.open(false);
    if (fileMeta) *fileMeta = file.getMetadata();
    return file.getGrids();
}

std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    return names;
}

TEST(Volume, Sh2ChannelNames) {
    const std::vector<std::string> expected = {"sh_l0m0",     "sh_l1m_neg1", "sh_l1m0", "sh_l1m1", "sh_l2m_neg2",
                                               "sh_l2m_neg1", "sh_l2m0",     "sh_l2m1", "sh_l2m2"};
    EXPECT_EQ(BasisDesc::sh2().channelNames, expected);
    EXPECT_EQ(BasisDesc::sh2().kind, "sh2");
}

TEST(Volume, ValidateRejectsInconsistentVolumes) {
    EXPECT_NO_THROW(makeVolume(2, 2, 2).validate());
    Volume v = makeVolume(2, 2, 2);
    v.levels[0].data.pop_back();
    EXPECT_THROW(v.validate(), FormatError);
    v = makeVolume(2, 2, 2);
    v.levels[0].grid.spacing = 0;
    EXPECT_THROW(v.validate(), FormatError);
    v = makeVolume(2, 2, 2);
    v.basis.channelNames[1] = "sh.l1";
    EXPECT_THROW(v.validate(), FormatError);
    v = makeVolume(2, 2, 2);
    v.levels.clear();
    EXPECT_THROW(v.validate(), FormatError);
}

TEST(Volume, MetaAccessorsConvert) {
    Metadata m{{"i", int64_t(3)}, {"d", 2.5}, {"s", std::string("text")}};
    EXPECT_EQ(metaNumber(m, "i", 0), 3.0);
    EXPECT_EQ(metaNumber(m, "d", 0), 2.5);
    EXPECT_EQ(metaNumber(m, "s", -1), -1.0);
    EXPECT_EQ(metaNumber(m, "missing", 7), 7.0);
    EXPECT_EQ(metaString(m, "s"), "text");
    EXPECT_EQ(metaString(m, "i"), "3");
    EXPECT_EQ(metaString(m, "d"), "2.5");
    EXPECT_EQ(metaString(m, "missing", "x"), "x");
}

TEST(VdbIo, RoundTripIsBitIdentical) {
    test::TempDir dir;
    const Volume v = makeVolume(3, 4, 5);
    writeVolume(v, dir.file("v.vdb"));
    const Volume r = readVolume(dir.file("v.vdb"));
    EXPECT_EQ(r.basis.kind, "sh2");
    EXPECT_EQ(r.basis.channelNames, v.basis.channelNames);
    ASSERT_EQ(r.levels.size(), 1u);
    const GridSpec& g = r.levels[0].grid;
    EXPECT_EQ(g.origin, v.levels[0].grid.origin);
    EXPECT_EQ(g.spacing, v.levels[0].grid.spacing);
    EXPECT_EQ(g.nx, 3);
    EXPECT_EQ(g.ny, 4);
    EXPECT_EQ(g.nz, 5);
    ASSERT_EQ(r.levels[0].data.size(), v.levels[0].data.size());
    EXPECT_EQ(0, std::memcmp(r.levels[0].data.data(), v.levels[0].data.data(), v.levels[0].data.size() * sizeof(float)));
}

// `-o /dev/null` and named pipes: the writer reads its own file back (the content UUID,
// content_hash.h), so the whole file is made in the temporary directory and then copied into
// the pipe, which stays a pipe (atomic_file.h); the reader gets the file writeVolume makes.
TEST(VdbIo, WritingIntoAFifoSendsTheFileAndKeepsTheFifo) {
    test::TempDir dir;
    const Volume v = makeVolume(3, 4, 5);
    WriteOptions reproducible;
    reproducible.reproducible = true;
    writeVolume(v, dir.file("v.vdb"), reproducible);
    const std::string fifo = dir.file("pipe");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] {
        std::ifstream in(fifo, std::ios::binary);
        received.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    });
    writeVolume(v, fifo, reproducible);
    reader.join();
    std::ifstream file(dir.file("v.vdb"), std::ios::binary);
    const std::string expected((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    EXPECT_FALSE(expected.empty());
    EXPECT_TRUE(received == expected) << received.size() << " bytes received, " << expected.size() << " expected";
    struct stat st;
    ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced by a regular file";
    std::vector<std::string> names = listDir(dir.path());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"pipe", "v.vdb"}));
}

TEST(VdbIo, ZeroNodesStayActive) {
    test::TempDir dir;
    Volume v = makeVolume(3, 4, 5);
    std::fill(v.levels[0].data.begin(), v.levels[0].data.end(), 0.0f);
    writeVolume(v, dir.file("zero.vdb"));
    const auto grids = readAllGrids(dir.file("zero.vdb"));
    ASSERT_EQ(grids->size(), 9u);
    for (const auto& grid : *grids) EXPECT_EQ(grid->activeVoxelCount(), 60u) << grid->getName();
    EXPECT_EQ(readVolume(dir.file("zero.vdb")).levels[0].data, v.levels[0].data);
}

TEST(VdbIo, MetadataRoundTrip) {
    test::TempDir dir;
    Volume v = makeVolume(2, 2, 2);
    v.meta["scene"] = std::string("cornell box, v2");
    v.meta["rays_per_node"] = int64_t(1) << 40;
    v.meta["negative"] = int64_t(-7);
    v.meta["time_seconds"] = 0.1;
    v.meta["units"] = std::string("radiance W/(m^2 sr)");
    v.meta["level_of_detail"] = int64_t(2);  // looks like, but is not, a structural key
    v.meta["levels_note"] = std::string("x");
    writeVolume(v, dir.file("m.vdb"));
    EXPECT_EQ(readVolume(dir.file("m.vdb")).meta, v.meta);

    openvdb::MetaMap::Ptr fileMeta;
    readAllGrids(dir.file("m.vdb"), &fileMeta);
    EXPECT_EQ(fileMeta->metaValue<int64_t>("vdblight:format_version"), kFormatVersion);
    EXPECT_EQ(fileMeta->metaValue<std::string>("vdblight:basis"), "sh2");
    EXPECT_EQ(fileMeta->metaValue<std::string>("vdblight:channels"),
              "sh_l0m0,sh_l1m_neg1,sh_l1m0,sh_l1m1,sh_l2m_neg2,sh_l2m_neg1,sh_l2m0,sh_l2m1,sh_l2m2");
    EXPECT_EQ(fileMeta->metaValue<int64_t>("vdblight:levels"), 1);
    EXPECT_EQ(fileMeta->metaValue<openvdb::Vec3i>("vdblight:level0_dims"), openvdb::Vec3i(2, 2, 2));
    EXPECT_EQ(fileMeta->metaValue<double>("vdblight:level0_spacing"), 0.375);
    EXPECT_EQ(fileMeta->metaValue<openvdb::Vec3d>("vdblight:level0_origin"), openvdb::Vec3d(-1.25, 0.5, 3.0));
    EXPECT_EQ(fileMeta->metaValue<double>("vdblight:time_seconds"), 0.1);
}

TEST(VdbIo, InvalidVolumesAndReservedKeysAreRejected) {
    test::TempDir dir;
    Volume v = makeVolume(2, 2, 2);
    v.meta["basis"] = std::string("other");
    EXPECT_THROW(writeVolume(v, dir.file("r.vdb")), ValueError);
    v = makeVolume(2, 2, 2);
    v.meta["level0_origin"] = 1.0;
    EXPECT_THROW(writeVolume(v, dir.file("r.vdb")), ValueError);
    v = makeVolume(2, 2, 2);
    v.meta["level12_dims"] = 1.0;
    EXPECT_THROW(writeVolume(v, dir.file("r.vdb")), ValueError);
    v = makeVolume(2, 2, 2);
    v.levels[0].data.resize(5);
    EXPECT_THROW(writeVolume(v, dir.file("r.vdb")), ValueError);
    v = makeVolume(2, 2, 2);
    v.levels[0].data[7] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(writeVolume(v, dir.file("r.vdb")), ValueError);
    v = makeVolume(2, 2, 2);
    v.levels[0].data[7] = 1e5f;  // fine as float, overflows a half
    EXPECT_NO_THROW(writeVolume(v, dir.file("r.vdb")));
    EXPECT_THROW(writeVolume(v, dir.file("r_half.vdb"), WriteOptions{true}), ValueError);
    fs::remove(dir.file("r.vdb"));
    EXPECT_TRUE(listDir(dir.path()).empty());
}

TEST(VdbIo, VoxelCentresAreNodePositions) {
    test::TempDir dir;
    const Volume v = makeVolume(3, 4, 5);
    writeVolume(v, dir.file("v.vdb"));
    const auto grids = readAllGrids(dir.file("v.vdb"));
    ASSERT_EQ(grids->size(), 9u);
    const GridSpec& g = v.levels[0].grid;
    for (const auto& base : *grids) {
        auto grid = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base);
        ASSERT_TRUE(grid) << base->getName() << " is " << base->valueType();
        EXPECT_EQ(grid->getVectorType(), openvdb::VEC_INVARIANT);
        EXPECT_EQ(grid->getGridClass(), openvdb::GRID_UNKNOWN);
        EXPECT_EQ(grid->activeVoxelCount(), g.nodeCount());
        const int channel = int(grid->metaValue<int64_t>("vdblight:channel"));
        EXPECT_EQ(grid->getName(), v.basis.channelNames[std::size_t(channel)]);
        EXPECT_EQ(grid->metaValue<int64_t>("vdblight:level"), 0);
        auto acc = grid->getConstAccessor();
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) {
                    const openvdb::Vec3d w = grid->transform().indexToWorld(openvdb::Coord(i, j, k));
                    const Vec3d p = g.node(i, j, k);
                    EXPECT_NEAR(w.x(), p.x, 1e-12);
                    EXPECT_NEAR(w.y(), p.y, 1e-12);
                    EXPECT_NEAR(w.z(), p.z, 1e-12);
                    const openvdb::Vec3d idx = grid->transform().worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
                    EXPECT_NEAR((idx - openvdb::Vec3d(i, j, k)).length(), 0.0, 1e-9);
                    ASSERT_TRUE(acc.isValueOn(openvdb::Coord(i, j, k)));
                    const float* d = v.levels[0].nodeData(g.index(i, j, k), 9) + channel * 3;
                    EXPECT_EQ(acc.getValue(openvdb::Coord(i, j, k)), openvdb::Vec3s(d[0], d[1], d[2]));
                }
    }
}

TEST(VdbIo, HalfFloatHalvesTheFile) {
    test::TempDir dir;
    Volume v = makeVolume(16, 16, 16, 7);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> value(0.1f, 10.0f);
    for (float& x : v.levels[0].data) x = value(rng);
    v.levels[0].data[5] = 0.0f;
    writeVolume(v, dir.file("full.vdb"));
    writeVolume(v, dir.file("half.vdb"), WriteOptions{true});
    const double ratio = double(fs::file_size(dir.file("half.vdb"))) / double(fs::file_size(dir.file("full.vdb")));
    EXPECT_LT(ratio, 0.7);  // compression gains less on halves than on floats
    EXPECT_GT(ratio, 0.4);
    const Volume r = readVolume(dir.file("half.vdb"));
    ASSERT_EQ(r.levels[0].data.size(), v.levels[0].data.size());
    EXPECT_EQ(r.levels[0].data[5], 0.0f);
    for (std::size_t n = 0; n < v.levels[0].data.size(); ++n) {
        const float a = v.levels[0].data[n], b = r.levels[0].data[n];
        ASSERT_LE(std::abs(a - b), std::abs(a) * 0x1p-11f) << "at " << n << ": " << a << " vs " << b;
    }
}

TEST(VdbIo, TwoLevelsRoundTrip) {
    // A consistent two-level structure (docs/format.md, "Levels"): K = 3, level-0 cell
    // (0, 0, 0) refined, level 1 holding exactly that cell's 4^3 child corners.
    test::TempDir dir;
    Volume v = makeVolume(2, 3, 2);
    v.levels[0].refinedCells = {0};
    Volume fine = makeVolume(4, 7, 4, 5);
    VolumeLevel level1;
    level1.grid = fine.levels[0].grid;
    level1.grid.spacing = 0.125;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) level1.activeNodes.push_back(level1.grid.index(i, j, k));
    std::sort(level1.activeNodes.begin(), level1.activeNodes.end());
    level1.data.assign(fine.levels[0].data.begin(), fine.levels[0].data.begin() + 64 * 27);
    v.levels.push_back(level1);
    writeVolume(v, dir.file("two.vdb"));
    const Volume r = readVolume(dir.file("two.vdb"));
    ASSERT_EQ(r.levels.size(), 2u);
    EXPECT_EQ(r.levels[1].grid.spacing, 0.125);
    EXPECT_EQ(r.levels[1].data, v.levels[1].data);
    EXPECT_EQ(r.levels[1].activeNodes, v.levels[1].activeNodes);
    EXPECT_EQ(r.levels[0].refinedCells, v.levels[0].refinedCells);
    EXPECT_EQ(r.levels[0].data, v.levels[0].data);
    const FileInfo info = inspectVolumeFile(dir.file("two.vdb"));
    ASSERT_EQ(info.grids.size(), 19u);
    EXPECT_EQ(info.grids[0].name, "sh_l0m0");
    EXPECT_EQ(info.grids[9].name, "refined_L0");
    EXPECT_EQ(info.grids[9].activeVoxels, 1u);
    EXPECT_EQ(info.grids[10].name, "sh_l0m0_L1");
    int fineGrids = 0;
    for (const GridInfo& g : info.grids) {
        if (g.level == 1) {
            ++fineGrids;
            EXPECT_EQ(g.name.substr(g.name.size() - 3), "_L1");
            EXPECT_EQ(g.activeVoxels, 64u);
            EXPECT_DOUBLE_EQ(g.voxelSize, 0.125);
        }
    }
    EXPECT_EQ(fineGrids, 9);

    // Two unrelated levels (no refinement structure) are refused before writing.
    Volume bad = makeVolume(2, 3, 2);
    bad.levels.push_back(makeVolume(9, 8, 3, 5).levels[0]);
    EXPECT_THROW(writeVolume(bad, dir.file("bad.vdb")), ValueError);
    EXPECT_FALSE(std::filesystem::exists(dir.file("bad.vdb")));
}

TEST(VdbIo, OverwritesAnExistingFile) {
    test::TempDir dir;
    writeVolume(makeVolume(2, 2, 2, 1), dir.file("v.vdb"));
    const Volume second = makeVolume(3, 2, 2, 2);
    writeVolume(second, dir.file("v.vdb"));
    EXPECT_EQ(readVolume(dir.file("v.vdb")).levels[0].data, second.levels[0].data);
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"v.vdb"});
}

TEST(VdbIo, NonexistentDirectoryIsAnIoError) {
    test::TempDir dir;
    const std::string path = dir.file("no/such/dir/v.vdb");
    EXPECT_THROW(writeVolume(makeVolume(2, 2, 2), path), IoError);
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(listDir(dir.path()).empty());
}

TEST(VdbIo, FailedWriteLeavesNoTemporaryFile) {
    test::TempDir dir;
    fs::create_directory(dir.path() / "taken.vdb");  // rename onto a directory fails
    try {
        writeVolume(makeVolume(2, 2, 2), dir.file("taken.vdb"));
        FAIL() << "expected IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot write '" + dir.file("taken.vdb") + "'"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"taken.vdb"});
    EXPECT_TRUE(fs::is_empty(dir.path() / "taken.vdb"));
}

TEST(VdbIo, MissingFileIsAnIoError) {
    test::TempDir dir;
    EXPECT_THROW(readVolume(dir.file("missing.vdb")), IoError);
    EXPECT_THROW(inspectVolumeFile(dir.file("missing.vdb")), IoError);
}

TEST(VdbIo, TruncatedFileIsRejected) {
    test::TempDir dir;
    writeVolume(makeVolume(6, 5, 4), dir.file("v.vdb"));
    std::ifstream in(dir.file("v.vdb"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::size_t> cuts = {0, 4, 100, bytes.size() / 2, bytes.size() - 1};
    for (std::size_t n = 1; n < 64; ++n) cuts.push_back(bytes.size() * n / 64);
    for (std::size_t keep : cuts) {
        std::ofstream(dir.file("cut.vdb"), std::ios::binary).write(bytes.data(), std::streamsize(keep));
        try {
            readVolume(dir.file("cut.vdb"));
            ADD_FAILURE() << "a file cut to " << keep << " bytes was accepted";
        } catch (const FormatError&) {
        } catch (const IoError&) {
        }
    }
}

TEST(VdbIo, ForeignVdbIsAFormatError) {
    test::TempDir dir;
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    openvdb::io::File(dir.file("foreign.vdb")).write({grid});
    try {
        readVolume(dir.file("foreign.vdb"));
        FAIL() << "expected FormatError";
    } catch (const FormatError& e) {
        EXPECT_NE(std::string(e.what()).find("not a vdblight volume"), std::string::npos) << e.what();
    }
    EXPECT_THROW(inspectVolumeFile(dir.file("foreign.vdb")), FormatError);
    test::writeTextFile(dir.file("text.vdb"), "not a vdb at all\n");
    EXPECT_THROW(readVolume(dir.file("text.vdb")), FormatError);
}

/// Rewrites `path` with its file metadata changed by `edit` (grids unchanged).
template <typename Edit>
void rewriteFileMetadata(const std::string& path, Edit edit) {
    openvdb::MetaMap::Ptr meta;
    auto grids = readAllGrids(path, &meta);
    edit(*meta);
    openvdb::io::File(path).write(*grids, *meta);
}

TEST(VdbIo, NewerOrInconsistentFilesAreFormatErrors) {
    test::TempDir dir;
    const std::string path = dir.file("v.vdb");
    writeVolume(makeVolume(3, 4, 5), path);
    rewriteFileMetadata(path, [](openvdb::MetaMap& m) {
        m.removeMeta("vdblight:format_version");
        m.insertMeta("vdblight:format_version", openvdb::Int64Metadata(kFormatVersion + 1));
    });
    EXPECT_THROW(readVolume(path), FormatError);

    writeVolume(makeVolume(3, 4, 5), path);
    rewriteFileMetadata(path, [](openvdb::MetaMap& m) {
        m.removeMeta("vdblight:level0_dims");
        m.insertMeta("vdblight:level0_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(3, 4, 6)));
    });
    EXPECT_THROW(readVolume(path), FormatError);

    writeVolume(makeVolume(3, 4, 5), path);
    rewriteFileMetadata(path, [](openvdb::MetaMap& m) {
        m.removeMeta("vdblight:channels");
        m.insertMeta("vdblight:channels", openvdb::StringMetadata("sh_l0m0,sh_l9m9"));
    });
    EXPECT_THROW(readVolume(path), FormatError);
}

TEST(VdbIo, InspectListsNineGrids) {
    test::TempDir dir;
    writeVolume(makeVolume(3, 4, 5), dir.file("v.vdb"));
    const FileInfo info = inspectVolumeFile(dir.file("v.vdb"));
    EXPECT_EQ(info.fileBytes, fs::file_size(dir.file("v.vdb")));
    ASSERT_EQ(info.grids.size(), 9u);
    for (std::size_t c = 0; c < 9; ++c) EXPECT_EQ(info.grids[c].name, BasisDesc::sh2().channelNames[c]);
    for (const GridInfo& g : info.grids) {
        EXPECT_EQ(g.valueType, "vec3s");
        EXPECT_EQ(g.activeVoxels, 60u);
        EXPECT_GT(g.memoryBytes, 0u);
        EXPECT_EQ(g.level, 0);
        EXPECT_DOUBLE_EQ(g.voxelSize, 0.375);
    }
}

/// Writes a small known volume to $VDBLIGHT_WRITE_SAMPLE (for checking the cross-reader
/// scripts by hand): 4 x 3 x 2 nodes, sh_l0m0 at node (0, 0, 0) = (1.5, 0.75, 0.25).
}  // namespace
}  // namespace vdblight
