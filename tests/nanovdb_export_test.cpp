// export --format nanovdb (export_nanovdb.h) and the PNanoVDB lookup of
// shaders/vdblight_nanovdb.h, compiled as C (nanovdb_lookup_c.c):
// - the lookup equals IrradianceQuery to 1e-5 relative at 10 000 random points and normals,
//   for uniform and multi-level volumes, with and without depth moments;
// - the light visibility it interpolates equals the visibility query's irradiance multiplies
//   the lights by, with the shadow edges and strips of a bake (docs/shadow_visibility.md) as
//   without; the occlusion lookup's own, located in double, is within float location's reach;
// - the file holds every channel (in the blind data of one vdblight_nodes grid per level, whose
//   values index it), the numbers and the metadata text;
// - nanovdb_validate and nanovdb_print (libnanovdb-tools) accept the files;
// - an empty volume is refused in one line, leaving no file.
#include <cstdio>
#include <cstring>
#include <functional>
#include <gtest/gtest.h>

#include <nanovdb/util/IO.h>

#include "baked_edges_volume.h"
#include "cli_util.h"
#include "expect_throw.h"
#include "nanovdb_lookup_c.h"
#include "random_volumes.h"
#include "test_util.h"
#include "basis/shadow_edges.h"
#include "vdblight/basis/basis.h"
#include "query/channel_lookup.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/query/query.h"
#include "query/query_direct.h"
#include "vdblight/volume/vdb_io.h"
#include "nanovdb_grid_words.h"

namespace vdblight {
namespace {
using test::readTextFile;
using test::TempDir;

/// The file's grid buffers back to back (nanovdb_grid_words.h), each grid ending aligned.
std::vector<uint64_t> loadGrids(const std::string& file) {
    std::vector<std::size_t> gridBytes;
    std::vector<uint64_t> words = test::nanoGridWords(file, &gridBytes);
    for (const std::size_t bytes : gridBytes) EXPECT_EQ(bytes % 32, 0u) << "a grid that does not end aligned shifts the next one";
    return words;
}

BasisDesc shBasis(int order) { return makeBasis("sh:" + std::to_string(order))->desc(); }

/// Random points in the node box grown by 5 % (the outside is clamped) and unit normals.
struct Probe {
    Vec3f x, n;
};
std::vector<Probe> randomProbes(const Bounds& box, int count, uint64_t seed) {
    Rng rng(seed);
    const Vec3d lo = box.lo - (box.hi - box.lo) * 0.05, size = (box.hi - box.lo) * 1.1;
    std::vector<Probe> out{std::size_t(count)};
    for (Probe& p : out) {
        p.x = Vec3f(Vec3d(lo.x + size.x * rng.uniform(), lo.y + size.y * rng.uniform(), lo.z + size.z * rng.uniform()));
        p.n = uniformSphere(rng.uniform(), rng.uniform());
    }
    return out;
}

/// The C lookup against IrradianceQuery at 10 000 probes: every colour within 1e-5 of the
/// query's value relative to max(|E|, 1 % of the RMS irradiance) (E of random coefficients
/// passes through 0; the floor keeps those points from dividing by nothing).
/// `edit` may change the file's words first (e.g. to make it look like an older file).
void expectLookupEqualsQuery(const Volume& volume, const std::string& what, double tolerance = 1e-5,
                             const std::function<void(const std::string&, std::vector<uint64_t>&)>& edit = {}) {
    TempDir dir;
    const std::string file = dir.file("v.nvdb");
    exportNanoVdb(volume, file);
    std::vector<uint64_t> words = loadGrids(file);
    if (edit) edit(file, words);
    const uint32_t* buf = reinterpret_cast<const uint32_t*>(words.data());
    const IrradianceQuery query(volume);
    const std::vector<Probe> probes = randomProbes(query.bounds(), 10000, 7);
    std::vector<Rgb> expected;
    double squares = 0;
    for (const Probe& p : probes) {
        expected.push_back(query.irradiance(p.x, p.n));
        for (int c = 0; c < 3; ++c) squares += double(expected.back()[c]) * expected.back()[c];
    }
    const double floor = 0.01 * std::sqrt(squares / (3.0 * probes.size()));
    double worst = 0;
    std::size_t worstAt = 0;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const float x[3] = {probes[i].x.x, probes[i].x.y, probes[i].x.z}, n[3] = {probes[i].n.x, probes[i].n.y, probes[i].n.z};
        float e[3];
        ASSERT_EQ(vdblightNanoIrradiance(buf, x, n, e), 1) << what << ": the lookup does not read the volume";
        for (int c = 0; c < 3; ++c) {
            const double rel = std::fabs(double(e[c]) - expected[i][c]) / std::max(std::fabs(double(expected[i][c])), floor);
            if (rel > worst) worst = rel, worstAt = i;
        }
    }
    const Probe& w = probes[worstAt];
    EXPECT_LE(worst, tolerance) << what << ": worst at (" << w.x.x << ", " << w.x.y << ", " << w.x.z << ") normal ("
                           << w.n.x << ", " << w.n.y << ", " << w.n.z << ")";
    std::printf("[ %s ] query kind %s, worst relative difference %.3g over %zu points\n", what.c_str(), query.kind(),
                worst, probes.size());
}

Volume uniformSh(int order, bool depth) {
    Volume v = test::randomUniformVolume(shBasis(order), 7, 5, 6, 0.3, 21);
    if (depth) test::randomDepth(v, 5);
    return v;
}

Volume levelsSh(LayoutKind kind, int levels, const BasisDesc& basis, bool depth) {
    Volume v = test::randomLevelsVolume(kind, levels, basis, 3, -0.5f, 1.5f);
    applySeamConstraints(v);  // as a bake leaves it
    if (depth) test::randomDepth(v, 9);
    return v;
}

TEST(NanoVdbLookup, EqualsQueryOnUniformVolumes) {
    expectLookupEqualsQuery(uniformSh(4, true), "uniform sh:4 with depth moments (the default bake's kind)");
    expectLookupEqualsQuery(uniformSh(4, false), "uniform sh:4");
    expectLookupEqualsQuery(uniformSh(2, true), "uniform sh:2 with depth moments");
    expectLookupEqualsQuery(test::randomShVolume(6, 4, 5, 0.25, 8), "uniform sh2");
    expectLookupEqualsQuery(test::randomUniformVolume(shBasis(3), 6, 5, 1, 0.4, 2), "uniform sh:3, one node along z");
}

TEST(NanoVdbLookup, EqualsQueryOnMultiLevelVolumes) {
    expectLookupEqualsQuery(levelsSh(LayoutKind::Adaptive, 3, shBasis(4), true), "adaptive, 3 levels, sh:4, depth moments");
    expectLookupEqualsQuery(levelsSh(LayoutKind::Adaptive, 3, shBasis(4), false), "adaptive, 3 levels, sh:4");
    expectLookupEqualsQuery(levelsSh(LayoutKind::Bilevel, 2, BasisDesc::sh2(), true), "bilevel sh2, depth moments");
}

/// A uniform sh:4 volume with depth moments baked with --direct occlusion: a listed light of
/// every kind (polygon, point, spot, directional, a tetrahedral mesh), random visibility.
Volume occlusionVolume() {
    Volume v = uniformSh(4, true);
    v.direct.mode = DirectMode::Occlusion;
    v.direct.lights.push_back(squareLight({0.3, 1.4, 1.9}, {0, -1, 0}, 0.2, Rgb{3, 2, 1}));
    // Its corners on floats, as a bake's are (a polygon light is the scene's float mesh): the
    // file stores them as floats, so that query and the shader see the same polygon.
    for (Vec3d& p : v.direct.lights.back().loops[0]) p = Vec3d(Vec3f(p));
    DirectLight point;  // positions on floats too, as a bake's (its scene's Vec3f)
    point.position = Vec3d(Vec3f(0.1f, 0.9f, 1.5f));
    point.value = Rgb{1, 1, 1};
    v.direct.lights.push_back(point);
    DirectLight spot = point;
    spot.kind = DirectLight::Kind::Spot;
    spot.position = Vec3d(Vec3f(0.6f, 1.5f, 2.0f));
    spot.direction = normalize(Vec3d(-0.3, -1, -0.2));
    spot.innerCone = 0.3, spot.outerCone = 0.7;
    v.direct.lights.push_back(spot);
    DirectLight sun;
    sun.kind = DirectLight::Kind::Directional;
    sun.direction = normalize(Vec3d(0.2, -1, 0.4));
    sun.value = Rgb{0.5f, 0.6f, 0.7f};
    v.direct.lights.push_back(sun);
    DirectLight bulb;  // a tetrahedron, each face counter-clockwise seen from outside
    bulb.kind = DirectLight::Kind::Mesh;
    bulb.value = Rgb{2, 2, 2};
    // Its corners on floats, as a bake's mesh lights are (they come from the scene's float mesh).
    const Vec3d c{0.9, 1.0, 1.6};
    const auto corner = [&](double dx, double dy, double dz) { return Vec3d(Vec3f(c + Vec3d(dx, dy, dz))); };
    const Vec3d a = corner(0.05, 0.05, 0.05), b = corner(0.05, -0.05, -0.05), d = corner(-0.05, 0.05, -0.05),
                e = corner(-0.05, -0.05, 0.05);
    bulb.loops = {{a, b, d}, {a, e, b}, {a, d, e}, {b, e, d}};
    v.direct.lights.push_back(bulb);
    Rng rng(4);
    v.levels[0].lightVisibility.resize(v.levels[0].grid.nodeCount() * v.direct.lights.size());
    for (float& f : v.levels[0].lightVisibility) f = rng.uniform();
    return v;
}

/// The visibility query multiplies each listed light of v by at x (the cell its irradiance
/// blends, located in float), read through IrradianceQuery itself: with the coefficients zero
/// and the lights replaced by suns of unit irradiance in one colour each, three at a time, the
/// irradiance facing them is exactly their visibility (1 times it, plus zeros).
std::vector<float> queriedVisibility(const Volume& v, const std::vector<Vec3f>& points) {
    const std::size_t lights = v.direct.lights.size();
    std::vector<float> out(points.size() * lights);
    DirectLight sun;
    sun.kind = DirectLight::Kind::Directional;
    sun.direction = Vec3d(0, -1, 0);  // along an axis: its float cosine facing it is exactly 1
    const Vec3f facing(-sun.direction);
    for (std::size_t first = 0; first < lights; first += 3) {
        Volume probe = v;
        std::fill(probe.levels[0].data.begin(), probe.levels[0].data.end(), 0.0f);
        for (std::size_t i = 0; i < lights; ++i) {
            probe.direct.lights[i] = sun;
            probe.direct.lights[i].value = Rgb(0, 0, 0);
            if (i >= first && i < first + 3) probe.direct.lights[i].value[int(i - first)] = 1.0f;
        }
        const IrradianceQuery query(probe);
        for (std::size_t p = 0; p < points.size(); ++p) {
            const Rgb e = query.irradiance(points[p], facing);
            for (std::size_t i = first; i < std::min(lights, first + 3); ++i) out[p * lights + i] = e[int(i - first)];
        }
    }
    return out;
}

/// The C lookup's visibility of each listed light against query's at `count` random points:
/// the worst |difference| from the visibility query's irradiance uses (`fromQuery`), and from
/// OcclusionLookup::visibility (`fromDoubleLocation`: its own reference, which locates the
/// point in double where query's irradiance and the shader locate it in float).
struct VisibilityDifference {
    double fromQuery = 0, fromDoubleLocation = 0;
};
VisibilityDifference worstVisibilityDifference(const Volume& v, const uint32_t* buf, int count) {
    Volume baked = v;  // the SH part alone
    baked.direct = {};
    baked.levels[0].lightVisibility.clear();
    baked.levels[0].lightShadowEdges.clear();
    const OcclusionLookup occlusion(std::make_unique<ChannelLookup>(baked, OutsidePolicy::Clamp), v);
    const std::size_t lights = v.direct.lights.size();
    std::vector<Vec3f> points;
    for (const Probe& p : randomProbes(IrradianceQuery(v).bounds(), count, 3)) points.push_back(p.x);
    const std::vector<float> queried = queriedVisibility(v, points);
    std::vector<float> expected(lights);
    VisibilityDifference worst;
    for (std::size_t p = 0; p < points.size(); ++p) {
        occlusion.visibility(Vec3d(points[p]), expected.data());
        const float x[3] = {points[p].x, points[p].y, points[p].z};
        for (std::size_t i = 0; i < lights; ++i) {
            const float mine = vdblightNanoLightVisibility(buf, x, int(i));
            worst.fromDoubleLocation = std::max(worst.fromDoubleLocation, double(std::fabs(mine - expected[i])));
            worst.fromQuery = std::max(worst.fromQuery, double(std::fabs(mine - queried[p * lights + i])));
        }
    }
    return worst;
}

TEST(NanoVdbLookup, AddsTheListedLightsTimesTheirVisibility) {
    const Volume v = occlusionVolume();
    Volume baked = v;  // the SH part alone
    baked.direct = {};
    baked.levels[0].lightVisibility.clear();
    expectLookupEqualsQuery(baked, "uniform sh:4 with depth moments: the SH part of an occlusion volume");
    // Every kind of light runs in float in the shader and, with its operations, sums and normal,
    // in query (fast_exact_lights.cpp), the lights' sum added to the SH part once in both: the
    // same bits for the same float lights, as a bake's. Where a polygon is clipped to a sliver of
    // the hemisphere its edge terms cancel and a last-bit difference grows to ~1e-4 of the light.
    // Measured: 1.0e-4 before the sums and normal were shared; 1.04e-5, 6.7e-6, 3.0e-6 as the
    // polygon, the mesh and the sum were shared; 0 now, GCC Release and clang ASan alike. The
    // tolerance leaves a last bit to a compiler that contracts differently.
    expectLookupEqualsQuery(v, "uniform sh:4 with depth moments and 5 listed lights (--direct occlusion)", 1e-6);
    TempDir dir;
    exportNanoVdb(v, dir.file("o.nvdb"));
    const std::vector<uint64_t> words = loadGrids(dir.file("o.nvdb"));
    const uint32_t* buf = reinterpret_cast<const uint32_t*>(words.data());
    const VisibilityDifference worst = worstVisibilityDifference(v, buf, 2000);
    std::printf("[ 5 listed lights ] visibility: worst |difference| from query's %.3g, from the visibility located in "
                "double %.3g\n", worst.fromQuery, worst.fromDoubleLocation);
    // The visibility query's irradiance uses: the same float cell and weights (measured 0).
    EXPECT_LE(worst.fromQuery, 1e-6);
    // OcclusionLookup::visibility locates the point in double, the shader in float; the depth
    // weights' steep Chebyshev bound (sigma 0.02 cells) amplifies that rounding (measured 5.0e-6).
    EXPECT_LE(worst.fromDoubleLocation, 2e-5);
}

/// With the shadow edges of a bake (nearest edges and strips) the lookup's visibility is
/// query's edge model (shadow_edges.h), not the trilinear blend of the visibility: the same
/// tolerances as without edges.
TEST(NanoVdbLookup, KeepsTheShadowEdgesAndStripsOfABake) {
    const Volume v = test::bakedEdgesVolume();
    const std::vector<float>& edges = v.levels[0].lightShadowEdges;
    ASSERT_EQ(v.direct.lights.size(), 3u);
    ASSERT_EQ(edges.size(), v.levels[0].grid.nodeCount() * 3 * shadow_edge::kFloatsPerLight);
    int strips = 0, penumbrae = 0, hard = 0;
    for (std::size_t p = 0; p < edges.size(); p += shadow_edge::kFloatsPerLight) {
        const bool inRange = std::fabs(edges[p + shadow_edge::kDistance]) < shadow_edge::kRange;
        strips += edges[p + shadow_edge::kFar] > 0.0f;
        penumbrae += inRange && edges[p + shadow_edge::kWidth] > 0.0f && edges[p + shadow_edge::kWidth] < shadow_edge::kNoEdge;
        hard += inRange && edges[p + shadow_edge::kWidth] == 0.0f;
    }
    std::printf("[ baked edges ] %zu nodes x 3 lights: %d with a strip, %d edges with a penumbra, %d hard edges\n",
                v.levels[0].grid.nodeCount(), strips, penumbrae, hard);
    ASSERT_GT(strips, 0) << "the fixture must have strips";
    ASSERT_GT(penumbrae, 0);
    ASSERT_GT(hard, 0);

    TempDir dir;
    exportNanoVdb(v, dir.file("e.nvdb"));
    const std::vector<uint64_t> words = loadGrids(dir.file("e.nvdb"));
    const uint32_t* buf = reinterpret_cast<const uint32_t*>(words.data());
    {  // the arrays after the 3 visibility arrays: 3 x (distances, widths), then 3 strips of 4 floats
        const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(dir.file("e.nvdb"));
        const std::size_t nodes = v.levels[0].grid.nodeCount();
        const nanovdb::GridBlindMetaData& blind = handles[1].template grid<uint32_t>()->blindMetaData(0);
        ASSERT_EQ(blind.mElementCount, nodes * ((25 + 4) * 3 + 3 + 3 * 2 + 3 * 4));
        const float* channels = blind.template getBlindData<float>();
        const std::size_t node = v.levels[0].grid.index(5, 2, 7), edgesAt = nodes * (29 * 3 + 3);
        const float* edge = edges.data() + (node * 3 + 2) * shadow_edge::kFloatsPerLight;  // light 2's
        EXPECT_EQ(channels[edgesAt + 4 * nodes + node], edge[shadow_edge::kDistance]);
        EXPECT_EQ(channels[edgesAt + 5 * nodes + node], edge[shadow_edge::kWidth]);
        EXPECT_EQ(channels[edgesAt + 6 * nodes + (2 * nodes + node) * 4 + 1], edge[shadow_edge::kDirectionY]);
        EXPECT_EQ(channels[edgesAt + 6 * nodes + (2 * nodes + node) * 4 + 3], edge[shadow_edge::kFar]);
        const auto* meta = handles[0].template grid<float>();
        EXPECT_EQ(meta->tree().getValue(nanovdb::Coord(nanovdb_meta::kShadowEdges, 0, 0)), 2.0f);
        const std::string text = meta->blindMetaData(0).template getBlindData<char>();
        EXPECT_NE(text.find("\nshadow_edges=2\nlight_arrays=light_visibility_0,light_visibility_1,light_visibility_2,"
                            "light_edge_distance_0,light_edge_width_0,light_edge_distance_1,light_edge_width_1,"
                            "light_edge_distance_2,light_edge_width_2,light_edge_strip_0,light_edge_strip_1,light_edge_strip_2\n"),
                  std::string::npos)
            << text;
    }
    Volume oneEdge = v;  // without the strips, and without any edge: other answers
    for (std::size_t p = 0; p < edges.size(); p += shadow_edge::kFloatsPerLight) oneEdge.levels[0].lightShadowEdges[p + shadow_edge::kFar] = 0.0f;
    Volume noEdges = v;
    noEdges.levels[0].lightShadowEdges.clear();
    const VisibilityDifference worst = worstVisibilityDifference(v, buf, 10000);
    exportNanoVdb(oneEdge, dir.file("one.nvdb"));
    const std::vector<uint64_t> oneWords = loadGrids(dir.file("one.nvdb"));
    const VisibilityDifference worstOne = worstVisibilityDifference(oneEdge, reinterpret_cast<const uint32_t*>(oneWords.data()), 10000);
    const auto oneHandles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(dir.file("one.nvdb"));
    EXPECT_EQ(oneHandles[0].template grid<float>()->tree().getValue(nanovdb::Coord(nanovdb_meta::kShadowEdges, 0, 0)), 1.0f);
    EXPECT_EQ(oneHandles[1].template grid<uint32_t>()->blindMetaData(0).mElementCount,
              v.levels[0].grid.nodeCount() * ((25 + 4) * 3 + 3 + 3 * 2))
        << "without strips the file has no strip arrays";
    const double stripsMatter = worstVisibilityDifference(oneEdge, buf, 10000).fromQuery,
                 edgesMatter = worstVisibilityDifference(noEdges, buf, 10000).fromQuery;
    std::printf("[ baked edges ] visibility: worst |difference| from query's %.3g with strips, %.3g with one edge (from "
                "the visibility located in double: %.3g, %.3g); the strips change it by up to %.3g, the edges by %.3g\n",
                worst.fromQuery, worstOne.fromQuery, worst.fromDoubleLocation, worstOne.fromDoubleLocation, stripsMatter,
                edgesMatter);
    // The visibility query's irradiance uses: the same float cell and weights, so bit for bit
    // outside strip cells (measured 0 with one edge); in a strip's cells the corner offsets
    // from the exact frame, rounded to ~1e-7 cell where query's are in double, times the
    // ramp's slope of up to 16 per cell: measured 7.8e-7. Tolerance: twice that, rounded up.
    EXPECT_LE(worst.fromQuery, 2e-6);
    EXPECT_LE(worstOne.fromQuery, 2e-6);
    // OcclusionLookup::visibility locates x in double, query's irradiance and the shader in
    // float: (x - origin) / spacing rounded to ~1e-6 cell, amplified by the depth weights'
    // Chebyshev bound and by the edge's ramp, whose slope is up to 16 per cell (a hard edge:
    // shadow_edge::kMinWidth) on a blended distance of up to 3 cells. Measured 9.1e-5 here;
    // with every width raised to 1 cell 1.3e-5, without the depth moments 1.5e-5.
    EXPECT_LE(worst.fromDoubleLocation, 2e-4);
    EXPECT_LE(worstOne.fromDoubleLocation, 2e-4);
    EXPECT_GT(stripsMatter, 0.1) << "the fixture's strips must change the answer somewhere";
    EXPECT_GT(edgesMatter, 0.1);
    // Irradiance: query's shared cell has the shader's float weights (the SH part is bit for bit)
    // and its lights' float operations and sum (fast_exact_lights.cpp): measured 0 here without
    // the edges, GCC and clang alike (4.7e-6 while the shader added the lights to the SH part one
    // by one; 9.7e-6 while query's point light was in double: at normals that graze it, its
    // n . w rounded to 1e-7 against an irradiance down to the 1 % floor). In a strip's cells the
    // corner offsets, which query measures in double, come from the file's exact frame
    // (nanovdb_meta::kFrame): measured 2.3e-6 (8.0e-6 before the frame, 3.3e-6 before the sum),
    // where the grid's float map (origin -1.65 and spacing 0.3 are not floats) gave 3.8e-5, its
    // rounding times the ramp's slope of up to 16 per cell. With strips, CI's ASan build (clang
    // 14, -O1) measured 2.8e-5 where GCC's Release build measured 2.3e-6: its tolerance is
    // twice clang's.
    expectLookupEqualsQuery(noEdges, "the same volume without its shadow edges", 1e-6);
    expectLookupEqualsQuery(v, "baked sh:4 volume with depth moments, 3 listed lights, shadow edges and strips", 5.5e-5);
    // A file written before the frame (kFrame 0) still reads, through the grid's float map.
    // (The value's byte offset is found in the file's own, aligned grid: NanoVDB's types are
    // 32-byte aligned, the words only 16.)
    const auto withoutFrame = [](const std::string& file, std::vector<uint64_t>& words) {
        const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(file);
        const nanovdb::Coord at(nanovdb_meta::kFrame, 0, 0);
        const auto* leaf = handles[0].template grid<float>()->tree().root().probeLeaf(at);
        ASSERT_NE(leaf, nullptr);
        const float* value = &leaf->data()->mValues[nanovdb::NanoLeaf<float>::CoordToOffset(at)];
        const float zero = 0.0f;  // vdblight_meta is the first grid: the same offset in the words
        const std::ptrdiff_t offset = reinterpret_cast<const char*>(value) - reinterpret_cast<const char*>(handles[0].data());
        std::memcpy(reinterpret_cast<char*>(words.data()) + offset, &zero, sizeof zero);
    };
    expectLookupEqualsQuery(v, "the same, its file without the exact frame (older files)", 1e-4, withoutFrame);
}

/// vdblight_meta and one vdblight_nodes grid (the node's index in its channel arrays, which ride
/// in its blind data, channel-major); the numbers and text of vdblight_meta.
TEST(NanoVdbExport, WritesEveryChannelAndTheMetadata) {
    const Volume v = occlusionVolume();
    TempDir dir;
    const NanoVdbSummary s = exportNanoVdb(v, dir.file("o.nvdb"));
    EXPECT_EQ(s.grids, (std::vector<std::string>{"vdblight_meta", "vdblight_nodes"}));
    EXPECT_EQ(s.activeNodes, v.levels[0].grid.nodeCount());

    const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(dir.file("o.nvdb"));
    ASSERT_EQ(handles.size(), 2u);
    const auto* grid = handles[1].template grid<uint32_t>();
    ASSERT_NE(grid, nullptr);
    const std::size_t nodes = v.levels[0].grid.nodeCount();
    EXPECT_EQ(grid->activeVoxelCount(), nodes);
    EXPECT_NEAR(grid->voxelSize()[0], v.levels[0].grid.spacing, 1e-12);
    ASSERT_EQ(grid->blindDataCount(), 1u);
    const nanovdb::GridBlindMetaData& blind = grid->blindMetaData(0);
    EXPECT_EQ(std::string(blind.mName), "vdblight_channels");
    // 25 SH + 4 depth arrays of N RGB triples, then 5 visibility arrays of N values.
    ASSERT_EQ(blind.mElementCount, nodes * ((25 + 4) * 3 + 5));
    const float* channels = blind.template getBlindData<float>();
    // Node (2, 3, 4): its index, channel 5's green, depth_mean_neg's y, light 3's visibility.
    const std::size_t node = v.levels[0].grid.index(2, 3, 4);
    const uint32_t at = grid->tree().getValue(nanovdb::Coord(2, 3, 4));
    EXPECT_EQ(at, node);
    EXPECT_EQ(channels[(5 * nodes + at) * 3 + 1], v.levels[0].data[(node * 25 + 5) * 3 + 1]);
    EXPECT_EQ(channels[((25 + 1) * nodes + at) * 3 + 1], v.levels[0].nodeDepth(node)[3 + 1]);
    EXPECT_EQ(channels[29 * nodes * 3 + 3 * nodes + at], v.levels[0].lightVisibility[node * 5 + 3]);
    // The grid's transform puts voxel (2, 3, 4) at the node.
    const nanovdb::Vec3d world = grid->indexToWorld(nanovdb::Vec3d(2, 3, 4));
    const Vec3d pos = v.levels[0].grid.node(2, 3, 4);
    EXPECT_NEAR(world[0], pos.x, 1e-12);
    EXPECT_NEAR(world[2], pos.z, 1e-12);

    const auto* meta = handles[0].template grid<float>();
    ASSERT_NE(meta, nullptr);
    const auto value = [&](int i) { return meta->tree().getValue(nanovdb::Coord(i, 0, 0)); };
    EXPECT_EQ(value(nanovdb_meta::kShOrder), 4.0f);
    EXPECT_EQ(value(nanovdb_meta::kChannels), 25.0f);
    EXPECT_EQ(value(nanovdb_meta::kLevels), 1.0f);
    EXPECT_EQ(value(nanovdb_meta::kDepth), 1.0f);
    EXPECT_EQ(value(nanovdb_meta::kDirectMode), 2.0f);
    EXPECT_EQ(value(nanovdb_meta::kVisibility), 5.0f);
    // The spot's record: kind 1, its position, the cosines of its cones.
    const int spot = nanovdb_meta::kFieldCount + 2 * nanovdb_meta::kLightFloats;
    EXPECT_EQ(value(spot), 1.0f);
    EXPECT_EQ(value(spot + 5), 0.6f);
    EXPECT_EQ(value(spot + 12), float(std::cos(0.7)));
    EXPECT_EQ(value(nanovdb_meta::kDimsX), 7.0f);
    EXPECT_EQ(value(nanovdb_meta::kDimsZ), 6.0f);
    // Level 0's exact frame: the origin as two floats, the spacing as s1 + s2 + s3 with s1 and
    // s2 of at most 12 significant bits (a node index below 4096 times either is exact in float).
    const int frame = int(value(nanovdb_meta::kFrame));
    ASSERT_GE(frame, nanovdb_meta::kFieldCount + 5 * nanovdb_meta::kLightFloats);
    const GridSpec& lattice = v.levels[0].grid;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(double(value(frame + a)) + value(frame + 3 + a), lattice.origin[a], 1e-14);
    const auto significantBits = [](float f) {
        int exponent, n = 0;
        for (double m = std::fabs(std::frexp(double(f), &exponent)); m != 0; m = m * 2 - std::floor(m * 2)) ++n;
        return n;
    };
    EXPECT_LE(significantBits(value(frame + 6)), 12);
    EXPECT_LE(significantBits(value(frame + 7)), 12);
    EXPECT_NEAR(double(value(frame + 6)) + value(frame + 7) + value(frame + 8), lattice.spacing, 1e-15);
    EXPECT_EQ(value(frame + 9), float(1.0 / lattice.spacing));
    ASSERT_EQ(meta->blindDataCount(), 1u);
    const std::string text = meta->blindMetaData(0).template getBlindData<char>();
    EXPECT_NE(text.find("basis=sh:4\n"), std::string::npos) << text;
    EXPECT_NE(text.find("direct=occlusion\n"), std::string::npos) << text;
    EXPECT_NE(text.find("direct_light_0=" + formatDirectLight(v.direct.lights[0]) + "\n"), std::string::npos) << text;
    EXPECT_NE(text.find("direct_light_4=" + formatDirectLight(v.direct.lights[4]) + "\n"), std::string::npos) << text;
}

TEST(NanoVdbExport, LevelsHaveTheirGridsAndRefinedMasks) {
    const Volume v = levelsSh(LayoutKind::Adaptive, 3, shBasis(2), true);
    TempDir dir;
    const NanoVdbSummary s = exportNanoVdb(v, dir.file("l.nvdb"));
    EXPECT_EQ(s.grids, (std::vector<std::string>{"vdblight_meta", "vdblight_nodes", "refined_L0", "vdblight_nodes_L1",
                                                 "refined_L1", "vdblight_nodes_L2"}));
    const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(dir.file("l.nvdb"));
    EXPECT_EQ(handles[2].gridMetaData()->gridType(), nanovdb::GridType::Float);
    EXPECT_EQ(handles[2].gridMetaData()->activeVoxelCount(), v.levels[0].refinedCells.size());
    EXPECT_EQ(handles[3].gridMetaData()->gridType(), nanovdb::GridType::UInt32);
    EXPECT_EQ(handles[3].gridMetaData()->activeVoxelCount(), v.levels[1].activeNodes.size());
    // 9 SH + 4 depth arrays per level, no visibility.
    EXPECT_EQ(handles[3].template grid<uint32_t>()->blindMetaData(0).mElementCount, v.levels[1].activeNodes.size() * 13 * 3);
}

/// nanovdb_validate and nanovdb_print (libnanovdb-tools) accept a uniform, a multi-level export
/// and one with shadow edges and strips.
TEST(NanoVdbExport, NanoVdbToolsAcceptTheFiles) {
    TempDir dir;
    exportNanoVdb(occlusionVolume(), dir.file("u.nvdb"));
    exportNanoVdb(levelsSh(LayoutKind::Adaptive, 3, shBasis(4), true), dir.file("l.nvdb"));
    exportNanoVdb(test::bakedEdgesVolume(), dir.file("e.nvdb"));
    for (const char* name : {"u.nvdb", "l.nvdb", "e.nvdb"}) {
        const std::string file = dir.file(name);
        const std::string out = dir.file("out.txt");
        EXPECT_EQ(std::system(("nanovdb_validate -v " + file + " > " + out + " 2>&1").c_str()), 0) << readTextFile(out);
        const std::string report = readTextFile(out);  // "Grid named "...": passed" per grid
        EXPECT_EQ(report.find("failed"), std::string::npos) << report;
        EXPECT_NE(report.find("\"vdblight_meta\": passed"), std::string::npos) << report;
        EXPECT_EQ(std::system(("nanovdb_print -l " + file + " > " + out + " 2>&1").c_str()), 0) << readTextFile(out);
        EXPECT_NE(readTextFile(out).find("vdblight_nodes"), std::string::npos) << readTextFile(out);
    }
}

TEST(NanoVdbExport, RefusesAnEmptyVolumeWithoutWritingAFile) {
    TempDir dir;
    Volume empty;
    empty.basis = shBasis(4);
    test::expectThrowWith<ValueError>([&] { exportNanoVdb(empty, dir.file("e.nvdb")); },
                                      "cannot export an empty volume to NanoVDB");
    EXPECT_EQ(test::filesIn(dir.path()), 0u);
}

/// The command: one line, one file; a file that cannot be written: one line, nothing left.
TEST(NanoVdbExportCli, WritesOneFileOrFailsInOneLine) {
    TempDir dir;
    writeVolume(levelsSh(LayoutKind::Adaptive, 3, shBasis(4), true), dir.file("v.vdb"));
    const test::CliRun run = test::runCli("export " + dir.file("v.vdb") + " -o " + dir.file("v.nvdb") + " --format nanovdb");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_EQ(test::countLines(run.output), 1) << run.output;
    EXPECT_NE(run.output.find("Wrote 6 NanoVDB grids"), std::string::npos) << run.output;
    // vdblight_meta, 3 x vdblight_nodes (25 channels + 4 depth arrays in each), refined_L0, refined_L1
    const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(dir.file("v.nvdb"));
    EXPECT_EQ(handles.size(), 6u);
    test::expectCleanFailure(dir, "export " + dir.file("v.vdb") + " -o " + dir.file("missing/v.nvdb") + " --format nanovdb",
                             "missing/v.nvdb");
}

}  // namespace
}  // namespace vdblight
