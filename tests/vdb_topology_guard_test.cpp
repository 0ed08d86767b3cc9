// The .vdb reader against crafted tree topology counts (tests/fuzz/fuzz_vdb's timeout inside
// OpenVDB 10's io::Archive::readGrid; docs/measurements/robustness.md): a root tile or child
// count that the grid's bytes cannot hold is refused with FormatError naming the grid and the
// count before OpenVDB loops over it (vdb_topology_guard.h), and valid files of every kind
// (vdblight's, and OpenVDB's own with every compression, half floats, root tiles, instances)
// still pass. No timing assertion: without the guard the largest counts keep OpenVDB busy for
// minutes, which shows as a CTest timeout.
#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_util.h"
#include "tiny_volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/volume.h"

namespace vdblight {
namespace {

/// Finds a grid's tree topology with OpenVDB's own readers, in io::Archive::readGrid's order
/// (descriptor; at the grid: compression flags, metadata, transform; then the topology), so
/// that the crafted bytes do not depend on the guard's own parse.
class TopologyLocator : public openvdb::io::Archive {
public:
    /// Byte offset of grid `name`'s buffer count, the first word of its topology.
    std::streamoff find(const std::string& path, const std::string& name) {
        std::ifstream is(path, std::ios::binary);
        readHeader(is);
        auto streamMeta = std::make_shared<openvdb::io::StreamMetadata>();  // as io::File::open does
        openvdb::io::setStreamMetadataPtr(is, streamMeta, /*transfer=*/false);
        setFormatVersion(is);
        setLibraryVersion(is);
        setDataCompression(is);
        openvdb::MetaMap().readMeta(is);
        const int32_t count = readGridCount(is);
        for (int32_t n = 0; n < count; ++n) {
            openvdb::io::GridDescriptor gd;
            openvdb::GridBase::Ptr grid = gd.read(is);
            if (gd.uniqueName() == name) {
                gd.seekToGrid(is);
                readGridCompression(is);
                grid->readMeta(is);
                grid->readTransform(is);
                return is.tellg();
            }
            gd.seekToEnd(is);
        }
        ADD_FAILURE() << "no grid " << name << " in " << path;
        return 0;
    }
};

/// `bytes` with the root tile count and child count of the grid whose topology starts at
/// `topology` (values of `valueBytes` bytes) replaced, and the header UUID replaced by a random
/// one (version 4): a file written by another program, which the damage check (docs/format.md,
/// "Damaged files") lets through to OpenVDB.
std::string withRootCounts(std::string bytes, std::streamoff topology, std::size_t valueBytes, uint32_t tiles,
                           uint32_t children) {
    const std::size_t counts = std::size_t(topology) + sizeof(int32_t) + valueBytes;  // buffer count, background
    std::memcpy(&bytes[counts], &tiles, sizeof tiles);
    std::memcpy(&bytes[counts + 4], &children, sizeof children);
    bytes.replace(21, 36, "0badc0de-0000-4000-8000-000000000000");
    return bytes;
}

/// Every way in: readVolume (`vdblight info`, `export`), delayed loading (`query` of a large
/// file) and the grid listing must refuse `path` naming the grid and the count.
void expectRefused(const std::string& path, const std::string& expected) {
    for (int call = 0; call < 3; ++call) {
        try {
            if (call == 0) {
                readVolume(path);
            } else if (call == 1) {
                StreamedVolume streamed(path);
            } else {
                inspectVolumeFile(path);
            }
            ADD_FAILURE() << "call " << call << " accepted a crafted topology count";
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << "call " << call << ": " << e.what();
        }
    }
}

TEST(VdbTopologyGuard, ImpossibleRootCountsInAVdblightFileAreRefusedBeforeOpenVdbReadsThem) {
    test::TempDir dir;
    const std::string good = dir.file("good.vdb");
    writeVolume(test::tinySh2Volume(), good);
    const std::string bytes = test::readTextFile(good);
    const std::streamoff topology = TopologyLocator().find(good, "sh_l0m0");
    ASSERT_NO_THROW(readVolume(good));
    const std::string path = dir.file("crafted.vdb");
    // The largest tile count keeps OpenVDB 10 reading an exhausted stream for minutes; one of
    // 2^20 (25 MB of tiles in a file of kilobytes) is as impossible. The real counts are 0 and 1.
    for (const uint32_t tiles : {0xffffffffu, 1u << 20}) {
        test::writeTextFile(path, withRootCounts(bytes, topology, sizeof(openvdb::Vec3s), tiles, 1));
        expectRefused(path, "grid 'sh_l0m0' declares " + std::to_string(tiles) + " root tiles");
    }
    for (const uint32_t children : {0xffffffffu, 2u}) {  // each child takes at least 8 KB
        test::writeTextFile(path, withRootCounts(bytes, topology, sizeof(openvdb::Vec3s), 0, children));
        expectRefused(path, "grid 'sh_l0m0' declares " + std::to_string(children) + " root child nodes");
    }
}

/// An OpenVDB file that vdblight's grid listing opens (it carries vdblight:format_version),
/// holding a grid of every value type, root tiles, several root children and an instance.
void writeOpenVdbFile(const std::string& path, uint32_t compression, bool half) {
    auto floats = openvdb::FloatGrid::create(0.5f);
    floats->setName("floats");
    floats->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    floats->tree().setValue(openvdb::Coord(9000, -9000, 0), 2.0f);  // another root child
    floats->tree().addTile(3, openvdb::Coord(40960, 0, 0), 3.0f, true);  // root tiles
    floats->tree().addTile(3, openvdb::Coord(-40960, 0, 0), 4.0f, false);
    auto vectors = openvdb::Vec3SGrid::create();
    vectors->setName("vectors");
    vectors->tree().setValue(openvdb::Coord(0), openvdb::Vec3s(1, 2, 3));
    vectors->tree().addTile(3, openvdb::Coord(0, 4096, 0), openvdb::Vec3s(4, 5, 6), true);
    auto bools = openvdb::BoolGrid::create();
    bools->setName("bools");
    bools->tree().setValue(openvdb::Coord(5), true);
    bools->tree().addTile(3, openvdb::Coord(4096, 4096, 4096), true, true);
    auto masks = openvdb::MaskGrid::create();
    masks->setName("masks");
    masks->tree().setValueOn(openvdb::Coord(-5));
    auto int64s = openvdb::Int64Grid::create();
    int64s->setName("int64s");
    int64s->tree().setValue(openvdb::Coord(7), 7);
    auto doubles = openvdb::DoubleGrid::create();
    doubles->setName("doubles");
    doubles->tree().addTile(3, openvdb::Coord(0), 1.0, true);
    auto instance = openvdb::FloatGrid::create(floats->treePtr());  // shares the tree: stores none
    instance->setName("instance");
    for (openvdb::GridBase::Ptr g : openvdb::GridPtrVec{floats, vectors, doubles, instance}) g->setSaveFloatAsHalf(half);
    openvdb::MetaMap meta;
    meta.insertMeta("vdblight:format_version", openvdb::Int64Metadata(1));
    openvdb::io::File file(path);
    file.setCompression(compression);
    file.write({floats, vectors, bools, masks, int64s, doubles, instance}, meta);
}

TEST(VdbTopologyGuard, OpenVdbFilesOfEveryKindPass) {
    openvdb::initialize();
    test::TempDir dir;
    const std::string path = dir.file("openvdb.vdb");
    using namespace openvdb::io;
    for (const uint32_t compression : {uint32_t(COMPRESS_NONE), uint32_t(COMPRESS_ZIP), uint32_t(COMPRESS_ACTIVE_MASK),
                                       uint32_t(COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK)})
        for (const bool half : {false, true}) {
            SCOPED_TRACE("compression " + std::to_string(compression) + (half ? ", half floats" : ""));
            writeOpenVdbFile(path, compression, half);
            FileInfo info;
            ASSERT_NO_THROW(info = inspectVolumeFile(path));
            EXPECT_EQ(info.grids.size(), 7u);
            // The crafted count in the same file is refused (the locator finds this layout too).
            const std::string crafted = dir.file("crafted.vdb");
            test::writeTextFile(crafted, withRootCounts(test::readTextFile(path), TopologyLocator().find(path, "floats"),
                                                        sizeof(float), 0xffffffffu, 2));
            try {
                inspectVolumeFile(crafted);
                ADD_FAILURE() << "a crafted tile count was accepted";
            } catch (const FormatError& e) {
                EXPECT_NE(std::string(e.what()).find("grid 'floats' declares 4294967295 root tiles"), std::string::npos)
                    << e.what();
            }
        }
}

TEST(VdbTopologyGuard, VdblightFilesOfEveryKindStillRead) {
    // The fuzz seeds: every volume kind vdblight writes (levels, half floats, bins, moments,
    // vectors, compact, validity; tests/fuzz/make_vdb_corpus.sh).
    const std::filesystem::path seeds = std::filesystem::path(VDBLIGHT_SOURCE_DIR) / "tests/fuzz/corpus/fuzz_vdb";
    int read = 0;
    for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
        const std::string path = entry.path().string();
        if (entry.path().filename().string().rfind("regression-", 0) == 0) continue;  // crafted inputs
        SCOPED_TRACE(path);
        EXPECT_NO_THROW(readVolume(path));
        EXPECT_NO_THROW(inspectVolumeFile(path));
        ++read;
    }
    EXPECT_GE(read, 10);
    for (const char* name : {"sh2_uniform.vdb", "sh2_half.vdb", "sh2_levels_adaptive.vdb"}) {
        SCOPED_TRACE(name);
        EXPECT_NO_THROW(StreamedVolume streamed((seeds / name).string()));  // delayed loading
    }
}

}  // namespace
}  // namespace vdblight
