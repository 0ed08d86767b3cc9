// Solid culling (solid_cull.h): on a room with a closed block and on the Cornell box, the
// culled nodes are exactly the nodes whose every cell lies inside a solid by a brute-force
// count against the exact geometry (all triangles, exact box test, analytic inside test);
// free-space queries never read a culled node; a culled bake equals the unculled bake bit
// for bit in free space; an open box culls nothing; files round-trip and inconsistent
// culled files are refused.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>

#include "refinement_box.h"
#include "test_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "query/query_levels.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/volume/vdb_io.h"

#include "support/scene_generators.h"

using namespace vdblight;

namespace {

/// A closed solid described exactly: a convex prism (footprint polygon in x-z, counter-
/// clockwise or clockwise, and a y range) whose interior is the open set.
struct Prism {
    std::vector<std::pair<double, double>> xz;
    double y0 = 0, y1 = 0;
    bool inside(const Vec3d& p) const {
        if (!(p.y > y0 && p.y < y1)) return false;
        int sign = 0;
        for (std::size_t i = 0; i < xz.size(); ++i) {
            const auto& a = xz[i];
            const auto& b = xz[(i + 1) % xz.size()];
            const double c = (b.first - a.first) * (p.z - a.second) - (b.second - a.second) * (p.x - a.first);
            if (c == 0) return false;
            const int s = c > 0 ? 1 : -1;
            if (sign != 0 && s != sign) return false;
            sign = s;
        }
        return true;
    }
};

struct TestScene {
    Scene scene;
    std::vector<Prism> solids;
};

Prism boxPrism(const Vec3d& lo, const Vec3d& hi) {
    Prism p;
    p.xz = {{lo.x, lo.z}, {hi.x, lo.z}, {hi.x, hi.z}, {lo.x, hi.z}};
    p.y0 = lo.y, p.y1 = hi.y;
    return p;
}

/// Room [0,1]^3 (faces in) with a closed block (faces out) and a point light; with
/// `openTop` the block has no top face (an open box: no enclosure).
TestScene roomWithBlock(bool openTop) {
    TestScene t;
    t.scene.name = openTop ? "room_open_box" : "room_block";
    Material m;
    m.albedo = {0.6f, 0.6f, 0.6f};
    addMaterial(t.scene, m);
    appendBox(t.scene, {0, 0, 0}, {1, 1, 1}, /*inward=*/true, 0);
    const Vec3f lo(0.23f, 0.17f, 0.31f), hi(0.71f, 0.62f, 0.77f);
    appendBox(t.scene, lo, hi, /*inward=*/false, 0);
    if (openTop) {  // remove the block's +y face (the two triangles whose vertices all have y = hi.y)
        Scene& s = t.scene;
        for (std::size_t tri = s.triangleCount(); tri-- > 12;) {
            bool top = true;
            for (int k = 0; k < 3; ++k) top = top && s.vertex(tri, k).y == hi.y;
            if (!top) continue;
            s.indices.erase(s.indices.begin() + std::ptrdiff_t(3 * tri), s.indices.begin() + std::ptrdiff_t(3 * tri + 3));
            s.materialIds.erase(s.materialIds.begin() + std::ptrdiff_t(tri));
        }
    } else {
        t.solids.push_back(boxPrism(Vec3d(lo), Vec3d(hi)));
    }
    t.scene.pointLights.push_back({{0.5f, 0.9f, 0.5f}, {1.0f, 1.0f, 1.0f}});
    return t;
}

/// The Cornell box of data/: its two blocks are convex prisms standing on the floor (y = 0).
TestScene cornell() {
    TestScene t;
    t.scene = loadScene(defaultScenePath());
    Prism s;
    s.xz = {{0.13, 0.065}, {0.29, 0.114}, {0.24, 0.272}, {0.082, 0.225}};
    s.y0 = 0, s.y1 = 0.165;
    Prism tall;
    tall.xz = {{0.423, 0.247}, {0.472, 0.406}, {0.314, 0.456}, {0.265, 0.296}};
    tall.y0 = 0, tall.y1 = 0.33;
    t.solids = {s, tall};
    return t;
}

LevelLayout place(const TestScene& t, LayoutKind kind, int resolution, int levels = 3) {
    GridPlacement gp;
    gp.resolution = resolution;
    const GridSpec g0 = placeUniformGrid(t.scene.bounds(), gp, 1);
    LevelsPlacement p;
    p.kind = kind;
    p.refine = 3;
    p.levels = levels;
    p.keepFinestGeometry = true;
    return placeLevels(g0, t.scene.positions, t.scene.indices, p, 1);
}

bool refined(const LevelTopology& l, uint64_t cell) {
    return std::binary_search(l.refinedCells.begin(), l.refinedCells.end(), cell);
}

/// Brute force, independent of solid_cull.cpp: a cell exists (level 0, or its parent is
/// refined); it is exactly solid when it is not refined, no triangle overlaps its test box
/// (the refinement test box: pushed out by half a level-0 spacing on the node-box border)
/// and its centre lies inside an exact solid. Returns, per level, the nodes all of whose
/// existing cells are exactly solid.
std::vector<std::vector<uint64_t>> bruteForceCulled(const TestScene& t, const LevelLayout& layout) {
    const auto& levels = layout.levels;
    const int K = layout.refine;
    const double margin = 0.5 * levels[0].grid.spacing;
    const Scene& s = t.scene;
    std::vector<std::vector<uint64_t>> out(levels.size());
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const GridSpec& g = levels[l].grid;
        const auto exists = [&](int i, int j, int k) {
            if (i < 0 || j < 0 || k < 0 || i > g.nx - 2 || j > g.ny - 2 || k > g.nz - 2) return false;
            return l == 0 || refined(levels[l - 1], levels[l - 1].grid.index(i / K, j / K, k / K));
        };
        const auto solid = [&](int i, int j, int k) {
            if (refined(levels[l], g.index(i, j, k))) return false;
            Bounds box;
            box.lo = g.node(i, j, k);
            box.hi = box.lo + Vec3d(g.spacing, g.spacing, g.spacing);
            test::extendOnNodeBoxBorder(box, g, i, j, k, margin);
            for (std::size_t tri = 0; tri < s.triangleCount(); ++tri)
                if (triangleOverlapsBox(Vec3d(s.vertex(tri, 0)), Vec3d(s.vertex(tri, 1)), Vec3d(s.vertex(tri, 2)), box))
                    return false;
            const Vec3d c = g.node(i, j, k) + Vec3d(0.5, 0.5, 0.5) * g.spacing;
            for (const Prism& p : t.solids)
                if (p.inside(c)) return true;
            return false;
        };
        std::map<uint64_t, bool> memo;
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) {
                    bool any = false, all = true;
                    for (int c = 0; c < 8 && all; ++c) {
                        const int ci = i - (c & 1), cj = j - ((c >> 1) & 1), ck = k - (c >> 2);
                        if (!exists(ci, cj, ck)) continue;
                        any = true;
                        const uint64_t cell = g.index(ci, cj, ck);
                        auto it = memo.find(cell);
                        if (it == memo.end()) it = memo.emplace(cell, solid(ci, cj, ck)).first;
                        all = it->second;
                    }
                    if (any && all) out[l].push_back(g.index(i, j, k));
                }
    }
    return out;
}

/// Every culled node of the culled layout is absent from it, and the full layout had it.
std::vector<std::vector<uint64_t>> removedNodes(const LevelLayout& full, const LevelLayout& culled) {
    std::vector<std::vector<uint64_t>> out(full.levels.size());
    for (std::size_t l = 0; l < full.levels.size(); ++l) {
        const LevelTopology& a = full.levels[l];
        const LevelTopology& b = culled.levels[l];
        for (uint64_t n = 0; n < a.grid.nodeCount(); ++n) {
            const bool inA = !a.sparse() || std::binary_search(a.activeNodes.begin(), a.activeNodes.end(), n);
            const bool inB = !b.sparse() || std::binary_search(b.activeNodes.begin(), b.activeNodes.end(), n);
            if (inA && !inB) out[l].push_back(n);
            EXPECT_FALSE(inB && !inA) << "culling added node " << n << " to level " << l;
        }
    }
    return out;
}

Volume zeroVolume(const LevelLayout& layout) {
    Volume v;
    v.basis = BasisDesc::sh2();
    v.levels = volumeLevels(layout.levels);
    for (VolumeLevel& l : v.levels) {
        l.data.assign(l.storedNodes() * 27, 0.0f);
        for (std::size_t n = 0; n < l.storedNodes(); ++n) l.data[n * 27] = 1.0f;  // L00 = 1
    }
    if (layout.culledNodes > 0) v.meta["culling"] = std::string("solid-regions");
    return v;
}

bool insideAnySolid(const TestScene& t, const Vec3d& p) {
    for (const Prism& s : t.solids)
        if (s.inside(p)) return true;
    return false;
}

void checkAgainstBruteForce(const TestScene& t, LayoutKind kind, int resolution, uint64_t* culledOut) {
    const Tracer tracer(t.scene);
    const LevelLayout full = place(t, kind, resolution);
    LevelLayout culled = full;
    SolidCullStats stats;
    const uint64_t n = cullSolidNodes(culled, tracer, SolidCullOptions(), &stats);
    EXPECT_EQ(n, stats.nodesCulled);
    EXPECT_EQ(culled.totalNodes() + n, full.totalNodes());
    const auto removed = removedNodes(full, culled);
    const auto brute = bruteForceCulled(t, full);
    uint64_t total = 0;
    for (std::size_t l = 0; l < full.levels.size(); ++l) {
        EXPECT_EQ(removed[l].size(), brute[l].size()) << "level " << l;
        EXPECT_TRUE(removed[l] == brute[l]) << "level " << l << ": culled nodes differ from the brute-force set";
        EXPECT_EQ(stats.culledPerLevel[l], removed[l].size());
        total += removed[l].size();
    }
    EXPECT_EQ(total, n);
    *culledOut = n;

    // A culled volume is valid, and free-space queries never read a culled node.
    const Volume v = zeroVolume(culled);
    ASSERT_NO_THROW(v.validate());
    const ShLevelsLookup fast(v, OutsidePolicy::Clamp);
    const Bounds box = full.levels[0].grid.nodeBounds();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int freePoints = 0, culledCells = 0;
    for (int s = 0; s < 4000; ++s) {
        const Vec3d p(box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                      box.lo.z + u(rng) * (box.hi.z - box.lo.z));
        const bool inSolid = insideAnySolid(t, p);
        const bool flagged = fast.inCulledCell(Vec3f(p));
        if (inSolid) {
            culledCells += flagged;
            continue;
        }
        ++freePoints;
        EXPECT_FALSE(flagged) << "free-space point in a culled cell";
        EXPECT_NO_THROW(referenceLevelsLookup(v, p, Vec3d(0, 1, 0)));  // throws if it reads an inactive node
        // Every kept node holds radiance L00 = 1: E = pi Y00 everywhere a query reads only kept nodes.
        EXPECT_NEAR(fast.irradiance(Vec3f(p), Vec3f(0, 1, 0)).x, float(M_PI * 0.28209479177387814), 1e-5f);
    }
    EXPECT_GT(freePoints, 1000);
    if (n > 0) {
        EXPECT_GT(culledCells, 0) << "no point deep inside a solid was flagged";
    }
}

}  // namespace

TEST(SolidCull, RoomWithClosedBlockMatchesBruteForce) {
    const TestScene t = roomWithBlock(false);
    uint64_t bilevel = 0, adaptive = 0;
    checkAgainstBruteForce(t, LayoutKind::Bilevel, 12, &bilevel);
    checkAgainstBruteForce(t, LayoutKind::Adaptive, 6, &adaptive);
    EXPECT_GT(bilevel, 0u);
    EXPECT_GT(adaptive, 0u);
}

TEST(SolidCull, CornellBlocksMatchBruteForce) {
    const TestScene t = cornell();
    uint64_t bilevel = 0, adaptive = 0;
    checkAgainstBruteForce(t, LayoutKind::Bilevel, 16, &bilevel);
    checkAgainstBruteForce(t, LayoutKind::Adaptive, 8, &adaptive);
    EXPECT_GT(bilevel, 0u);
    EXPECT_GT(adaptive, 0u);
}

TEST(SolidCull, OpenBoxCullsNothing) {
    const TestScene t = roomWithBlock(true);
    ASSERT_EQ(t.scene.triangleCount(), 22u);
    const Tracer tracer(t.scene);
    for (LayoutKind kind : {LayoutKind::Bilevel, LayoutKind::Adaptive}) {
        LevelLayout layout = place(t, kind, 12);
        const uint64_t before = layout.totalNodes();
        EXPECT_EQ(cullSolidNodes(layout, tracer), 0u);
        EXPECT_EQ(layout.totalNodes(), before);
        EXPECT_FALSE(layout.levels[0].sparse());
    }
}

TEST(SolidCull, CulledBakeEqualsUnculledBakeInFreeSpace) {
    const TestScene t = roomWithBlock(false);
    const Tracer tracer(t.scene);
    const LevelLayout full = place(t, LayoutKind::Bilevel, 10);
    LevelLayout culled = full;
    ASSERT_GT(cullSolidNodes(culled, tracer), 0u);
    GatherOptions o;
    o.raysPerNode = 16;
    o.transport.maxBounces = 1;
    const Volume a = bakeShGatherLevels(t.scene, tracer, full, o);
    const Volume b = bakeShGatherLevels(t.scene, tracer, culled, o);
    EXPECT_EQ(metaString(b.meta, "culling"), "solid-regions");
    EXPECT_EQ(metaNumber(b.meta, "nodes_culled", 0), double(culled.culledNodes));
    const ShLevelsLookup la(a, OutsidePolicy::Clamp), lb(b, OutsidePolicy::Clamp);
    const Bounds box = full.levels[0].grid.nodeBounds();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int compared = 0;
    for (int s = 0; s < 3000; ++s) {
        const Vec3d p(box.lo.x + u(rng) * (box.hi.x - box.lo.x), box.lo.y + u(rng) * (box.hi.y - box.lo.y),
                      box.lo.z + u(rng) * (box.hi.z - box.lo.z));
        if (insideAnySolid(t, p)) continue;
        const Vec3f n = normalize(Vec3f(float(u(rng) - 0.5), float(u(rng) - 0.5), float(u(rng) - 0.5)));
        const Rgb ea = la.irradiance(Vec3f(p), n), eb = lb.irradiance(Vec3f(p), n);
        ASSERT_EQ(std::memcmp(&ea, &eb, sizeof(Rgb)), 0) << "at " << p.x << ", " << p.y << ", " << p.z;
        ++compared;
    }
    EXPECT_GT(compared, 1000);

    // Round trip through a file, and the reader's refusals.
    test::TempDir dir;
    writeVolume(b, dir.file("culled.vdb"));
    const Volume r = readVolume(dir.file("culled.vdb"));
    ASSERT_EQ(r.levels.size(), b.levels.size());
    for (std::size_t l = 0; l < r.levels.size(); ++l) {
        EXPECT_EQ(r.levels[l].activeNodes, b.levels[l].activeNodes);
        EXPECT_EQ(r.levels[l].data, b.levels[l].data);
    }
    Volume noMark = b;
    noMark.meta.erase("culling");
    EXPECT_THROW(noMark.validate(), FormatError);  // sparse level 0 without the culling mark
    Volume holed = b;  // remove a corner of a refined cell
    VolumeLevel& l0 = holed.levels[0];
    const uint64_t corner = l0.refinedCells.front();
    const auto at = std::lower_bound(l0.activeNodes.begin(), l0.activeNodes.end(), corner);
    ASSERT_TRUE(at != l0.activeNodes.end() && *at == corner);
    const std::size_t pos = std::size_t(at - l0.activeNodes.begin());
    l0.activeNodes.erase(at);
    l0.data.erase(l0.data.begin() + std::ptrdiff_t(pos * 27), l0.data.begin() + std::ptrdiff_t(pos * 27 + 27));
    EXPECT_THROW(holed.validate(), FormatError);
}

TEST(SolidCull, NeedsFinestGeometry) {
    const TestScene t = roomWithBlock(false);
    const Tracer tracer(t.scene);
    GridPlacement gp;
    gp.resolution = 6;
    LevelsPlacement p;
    p.kind = LayoutKind::Bilevel;
    LevelLayout layout = placeLevels(placeUniformGrid(t.scene.bounds(), gp, 1), t.scene.positions, t.scene.indices, p, 1);
    EXPECT_THROW(cullSolidNodes(layout, tracer), ValueError);
    SolidCullOptions bad;
    bad.backfaceFraction = 0;
    LevelLayout ok = place(t, LayoutKind::Bilevel, 6);
    EXPECT_THROW(cullSolidNodes(ok, tracer, bad), ValueError);
}
