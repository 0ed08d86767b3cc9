// check-scene: faces whose back side is seen from open space (K&L section 7, reversed normals).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"
#include "vdblight/bake/scene_check.h"
#include "vdblight/trace/trace.h"

#include "support/leak_scenes.h"
#include "support/scene_generators.h"

using namespace vdblight;

namespace {

void flip(Scene& s, uint32_t tri) { std::swap(s.indices[3 * tri + 1], s.indices[3 * tri + 2]); }

std::set<uint32_t> listed(const Scene& s, int threads = 0) {
    const Tracer tracer(s);
    SceneCheckOptions o;
    o.resolution = 16;
    o.raysPerPoint = 64;
    o.threads = threads;
    std::set<uint32_t> out;
    for (const BackfacingTriangle& t : findBackfacingTriangles(s, tracer, o).backfacing) out.insert(t.triangle);
    return out;
}

/// Room [-1,1]^3 (front faces in) with a closed solid block (front faces out).
Scene roomWithBlock() {
    Scene s;
    addMaterial(s, Material{});
    appendBox(s, {-1, -1, -1}, {1, 1, 1}, /*inward=*/true, 0);
    appendBox(s, {-0.35f, -0.6f, -0.2f}, {0.45f, 0.3f, 0.5f}, /*inward=*/false, 0);
    return s;
}

}  // namespace

TEST(SceneCheck, ClosedRoomWithBlockListsExactlyTheFlippedFaces) {
    Scene s = roomWithBlock();
    ASSERT_EQ(s.triangleCount(), 24u);
    EXPECT_TRUE(listed(s).empty());
    // Both triangles of one room wall, one of another, and one triangle of the block.
    const std::set<uint32_t> flipped = {2, 3, 8, 17};
    for (uint32_t t : flipped) flip(s, t);
    EXPECT_EQ(listed(s), flipped);
}

TEST(SceneCheck, ThinWallSceneListsExactlyTheFlippedFaces) {
    Scene s = makeThinWallScene().scene;
    EXPECT_TRUE(listed(s).empty());
    // Triangles 0-11 are the room, 12-47 the three solids of the wall (12 each: around the
    // door, beyond it, the lintel), 48-49 the light panel. Flipped: room walls, both big
    // faces of the wall, the door's jamb and the lintel's underside, and the panel. (Faces
    // outside the room, e.g. the solids' ends that reach 0.01 into its walls, or the lintel's
    // ends against the other solids, are seen from no open space and are not candidates.)
    const std::set<uint32_t> flipped = {0, 5, 11, 14, 20, 23, 32, 35, 40, 48};
    for (uint32_t t : flipped) flip(s, t);
    EXPECT_EQ(listed(s), flipped);
}

TEST(SceneCheck, OpenTownAndBedScenesListNothing) {
    // A one-sided ground under a sky with closed blocks, and a room with thin bars: probes
    // inside the blocks or bars see only back-faces and are not open space.
    EXPECT_TRUE(listed(makeTownScene().scene).empty());
    EXPECT_TRUE(listed(makeBarsScene().scene).empty());
}

TEST(SceneCheck, SameCountsForAnyThreadCountAndRefusesBadOptions) {
    Scene s = roomWithBlock();
    flip(s, 5);
    const Tracer tracer(s);
    SceneCheckOptions o;
    o.resolution = 12;
    o.raysPerPoint = 32;
    o.threads = 1;
    const SceneCheckResult a = findBackfacingTriangles(s, tracer, o);
    o.threads = 2;
    const SceneCheckResult b = findBackfacingTriangles(s, tracer, o);
    ASSERT_EQ(a.backfacing.size(), 1u);
    ASSERT_EQ(b.backfacing.size(), 1u);
    EXPECT_EQ(a.backfacing[0].triangle, 5u);
    EXPECT_EQ(a.backfacing[0].hits, b.backfacing[0].hits);
    EXPECT_EQ(a.openProbes, b.openProbes);
    // Probes inside the solid block are not open space (it sees only back-faces).
    EXPECT_LT(a.openProbes, a.probes);
    o.maxBackfaceFraction = 1.0;
    EXPECT_THROW(findBackfacingTriangles(s, tracer, o), ValueError);
    o.maxBackfaceFraction = 0.25;
    o.raysPerPoint = 0;
    EXPECT_THROW(findBackfacingTriangles(s, tracer, o), ValueError);
}

TEST(SceneCheck, FlippedRoomHasNoOpenSpace) {
    Scene s;
    addMaterial(s, Material{});
    appendBox(s, {-1, -1, -1}, {1, 1, 1}, /*inward=*/false, 0);
    const Tracer tracer(s);
    SceneCheckOptions o;
    o.resolution = 8;
    o.raysPerPoint = 32;
    const SceneCheckResult r = findBackfacingTriangles(s, tracer, o);
    EXPECT_EQ(r.openProbes, 0u);
    EXPECT_TRUE(r.backfacing.empty());
}
