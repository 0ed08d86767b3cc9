// Baking multi-level volumes: level 0 of a bilevel bake has the uniform bake's bits and the
// lookup equals the uniform one outside refined cells; same bits for 1 and 2 threads;
// baked seams are continuous; files round-trip and inconsistent files are refused.
#include <gtest/gtest.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstring>
#include <random>

#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "query/query_levels.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"

using namespace vdblight;

namespace {

struct Fixture {
    Scene scene = loadScene(defaultScenePath());
    Tracer tracer{scene};
    GridSpec grid0;
    Fixture() {
        GridPlacement p;
        p.resolution = 5;
        grid0 = placeUniformGrid(scene.bounds(), p, 1);
    }
    LevelLayout layout(LayoutKind kind, int levels = 3) const {
        LevelsPlacement p;
        p.kind = kind;
        p.refine = 3;
        p.levels = levels;
        return placeLevels(grid0, scene.positions, scene.indices, p, 1);
    }
    GatherOptions options(int threads) const {
        GatherOptions o;
        o.raysPerNode = 16;
        o.threads = threads;
        o.transport.maxBounces = 2;
        return o;
    }
};

const Fixture& fixture() {
    static const Fixture f;
    return f;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace

TEST(BakeLevels, BilevelEqualsUniformWhereNotRefined) {
    const Fixture& f = fixture();
    const Volume uniform = bakeShGather(f.scene, f.tracer, f.grid0, f.options(2));
    const Volume bilevel = bakeShGatherLevels(f.scene, f.tracer, f.layout(LayoutKind::Bilevel), f.options(2));
    ASSERT_EQ(bilevel.levels.size(), 2u);
    EXPECT_TRUE(sameBits(uniform.levels[0].data, bilevel.levels[0].data));
    const IrradianceQuery qu(uniform), qb(bilevel);
    const ShLevelsLookup levels(bilevel, OutsidePolicy::Clamp);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Bounds b = qu.bounds();
    int coarse = 0, fine = 0;
    for (int i = 0; i < 4000; ++i) {
        const Vec3f x(float(b.lo.x + u(rng) * (b.hi.x - b.lo.x)), float(b.lo.y + u(rng) * (b.hi.y - b.lo.y)),
                      float(b.lo.z + u(rng) * (b.hi.z - b.lo.z)));
        const Vec3f n = normalize(Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
        if (levels.levelAt(x) != 0) {
            ++fine;
            continue;
        }
        ++coarse;
        const Rgb a = qu.irradiance(x, n), c = qb.irradiance(x, n);
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(a[ch], c[ch]) << "point " << i;
    }
    EXPECT_GT(coarse, 100);
    EXPECT_GT(fine, 100);
}

TEST(BakeLevels, SameBitsForOneAndTwoThreads) {
    const Fixture& f = fixture();
    const LevelLayout layout = f.layout(LayoutKind::Adaptive);
    const Volume one = bakeShGatherLevels(f.scene, f.tracer, layout, f.options(1));
    const Volume two = bakeShGatherLevels(f.scene, f.tracer, layout, f.options(2));
    ASSERT_EQ(one.levels.size(), 3u);
    for (std::size_t l = 0; l < 3; ++l) EXPECT_TRUE(sameBits(one.levels[l].data, two.levels[l].data)) << "level " << l;
}

TEST(BakeLevels, FilesRoundTripAndInconsistentFilesAreRefused) {
    const Fixture& f = fixture();
    LevelsBakeStats stats;
    const Volume v = bakeShGatherLevels(f.scene, f.tracer, f.layout(LayoutKind::Adaptive), f.options(0), nullptr, &stats);
    EXPECT_GT(stats.seamNodes, 0u);
    test::TempDir dir;
    const std::string path = dir.file("levels.vdb");
    writeVolume(v, path);
    const Volume back = readVolume(path);
    ASSERT_EQ(back.levels.size(), v.levels.size());
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        EXPECT_TRUE(sameBits(back.levels[l].data, v.levels[l].data)) << "level " << l;
        EXPECT_EQ(back.levels[l].activeNodes, v.levels[l].activeNodes);
        EXPECT_EQ(back.levels[l].refinedCells, v.levels[l].refinedCells);
    }
    EXPECT_STREQ(IrradianceQuery(back).kind(), "sh2-levels");

    // Rewrite the file with one grid dropped or moved: readVolume names the problem.
    auto rewrite = [&](const std::string& out, const std::string& drop, const std::string& move) {
        openvdb::io::File in(path);
        in.open();
        openvdb::GridPtrVecPtr grids = in.getGrids();
        openvdb::MetaMap::Ptr meta = in.getMetadata();
        in.close();
        openvdb::GridPtrVec kept;
        for (const auto& g : *grids) {
            if (g->getName() == drop) continue;
            if (g->getName() == move) g->transform().postTranslate(openvdb::Vec3d(0.001, 0, 0));
            kept.push_back(g);
        }
        openvdb::io::File(out).write(kept, *meta);
    };
    auto expectRefused = [&](const std::string& file, const std::string& text) {
        try {
            readVolume(file);
            ADD_FAILURE() << "accepted " << file;
        } catch (const FormatError& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    rewrite(dir.file("nomask.vdb"), "refined_L1", "");
    expectRefused(dir.file("nomask.vdb"), "refined_L1");
    rewrite(dir.file("moved.vdb"), "", "sh_l1m0_L2");
    expectRefused(dir.file("moved.vdb"), "transform");
    rewrite(dir.file("movedmask.vdb"), "", "refined_L0");
    expectRefused(dir.file("movedmask.vdb"), "transform");
}
