// The SH ringing case (docs/measurements/robustness.md, "SH ringing"): one point light, direct light only.
#pragma once

#include "vdblight/bake/each_pass.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight::test {

/// A point light of intensity 4 at (0, 0, 2) (irradiance 1 at the origin) and nothing else
/// reachable (a scene needs a triangle: a tiny black one far away), baked by the point gather
/// on 2 x 2 x 2 nodes at -0.5 and 0.5 with 16 rays and direct light only. Order-2 SH of a
/// single direction is most negative (-0.0396 of the peak) at cos = -8/15 to the light.
inline Volume bakeOnePointLight() {
    Scene s;
    s.name = "one_point_light";
    s.materials.resize(1);
    s.materials[0].albedo = Rgb(0, 0, 0);
    addTriangle(s, Vec3f(50, 50, 50), Vec3f(50.001f, 50, 50), Vec3f(50, 50.001f, 50), 0);
    s.pointLights.push_back({Vec3f(0, 0, 2), Rgb(4, 4, 4)});
    const Tracer tracer(s);
    GridSpec g;
    g.origin = Vec3d(-0.5, -0.5, -0.5);
    g.spacing = 1;
    g.nx = g.ny = g.nz = 2;
    GatherOptions o;
    o.raysPerNode = 16;
    o.transport.maxBounces = 0;
    return bakeShGather(s, tracer, g, o);
}

}  // namespace vdblight::test
