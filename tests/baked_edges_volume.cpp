// bakedEdgesVolume (baked_edges_volume.h): a small scene baked with --direct occlusion's edges.
#include "baked_edges_volume.h"

#include "random_volumes.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight::test {

Volume bakedEdgesVolume() {
    Scene s;
    Material grey;
    grey.albedo = {0.5f, 0.5f, 0.5f};
    const uint32_t m = addMaterial(s, grey);
    const Vec3f roof[4] = {{-0.6f, 1.4f, -0.3f}, {0.2f, 1.4f, -0.7f}, {0.7f, 1.4f, 0.2f}, {-0.1f, 1.4f, 0.6f}};
    addTriangle(s, roof[0], roof[1], roof[2], m);
    addTriangle(s, roof[0], roof[2], roof[3], m);
    const Vec3f bar[4] = {{-1.6f, 2.1f, -1.2f}, {1.6f, 2.1f, -1.1f}, {1.6f, 2.1f, -1.03f}, {-1.6f, 2.1f, -1.13f}};
    addTriangle(s, bar[0], bar[1], bar[2], m);
    addTriangle(s, bar[0], bar[2], bar[3], m);
    Material lamp;
    lamp.emission = {6.0f, 6.0f, 5.0f};
    const uint32_t e = addMaterial(s, lamp);
    const Vec3f quad[4] = {{-0.2f, 2.8f, -0.2f}, {0.2f, 2.8f, -0.2f}, {0.2f, 2.8f, 0.2f}, {-0.2f, 2.8f, 0.2f}};
    addTriangle(s, quad[0], quad[1], quad[2], e);  // counter-clockwise seen from below: it faces down
    addTriangle(s, quad[0], quad[2], quad[3], e);
    s.directionalLights.push_back({Vec3f(normalize(Vec3d(0.3, -1.0, 0.2))), Rgb(3, 3, 3)});
    s.pointLights.push_back({Vec3f(0.4f, 3.0f, -0.3f), Rgb(9, 8, 7)});
    Volume v = randomUniformVolume(makeBasis("sh:4")->desc(), 12, 5, 12, 0.3, 33);
    v.levels[0].grid.origin = Vec3d(-1.65, 0.0, -1.65);
    randomDepth(v, 6);
    const Tracer tracer(s);
    DirectOptions o;
    o.mode = DirectMode::Occlusion;
    o.shadowEdges = true;
    bakeLightVisibility(s, tracer, planDirectLight(s, tracer, v.levels[0].grid, o), o, v);
    return v;
}

}  // namespace vdblight::test
