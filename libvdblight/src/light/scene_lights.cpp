// A scene's lights for `bake --direct` (scene_lights.h): emissive triangles grouped into
// polygon lights, punctual lights as they are, and visibility by shadow rays.

#include "vdblight/light/light.h"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>

#include "core/union_find.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {

// Shadow rays stop just short of the light, as the estimator's (radiance_estimator.cpp).
constexpr float kShadowEnd = 1.0f - 1e-4f;

using Key = std::array<float, 3>;
Key keyOf(const Vec3f& p) { return {p.x, p.y, p.z}; }

using core::UnionFind;

/// Two emissive triangles belong to one polygon light if they share an edge, have one
/// material, and lie in one plane facing the same way.
bool samePlane(const Scene& s, uint32_t a, uint32_t b, const std::vector<Vec3d>& normal) {
    if (s.materialIds[a] != s.materialIds[b]) return false;
    if (dot(normal[a], normal[b]) < 1.0 - 1e-6) return false;
    const Vec3d p = Vec3d(s.vertex(a, 0));
    const double size = length(Vec3d(s.vertex(a, 1)) - p) + length(Vec3d(s.vertex(a, 2)) - p);
    for (int k = 0; k < 3; ++k)
        if (std::abs(dot(normal[a], Vec3d(s.vertex(b, k)) - p)) > 1e-5 * size) return false;
    return true;
}

/// The boundary loops of a group of triangles: directed edges not cancelled by their reverse,
/// chained. False if they do not chain into closed loops with one way on from every vertex.
bool boundaryLoops(const Scene& s, const std::vector<uint32_t>& tris, std::vector<std::vector<Vec3d>>& loops) {
    std::map<std::pair<Key, Key>, int> edges;  // directed edge -> count (ordered: deterministic)
    for (uint32_t t : tris)
        for (int k = 0; k < 3; ++k) {
            const Key a = keyOf(s.vertex(t, k)), b = keyOf(s.vertex(t, (k + 1) % 3));
            auto rev = edges.find({b, a});
            if (rev != edges.end() && rev->second > 0) {
                if (--rev->second == 0) edges.erase(rev);
            } else {
                ++edges[{a, b}];
            }
        }
    std::map<Key, Key> next;
    for (const auto& [e, count] : edges) {
        if (count != 1 || next.count(e.first)) return false;
        next[e.first] = e.second;
    }
    while (!next.empty()) {
        std::vector<Vec3d> loop;
        Key start = next.begin()->first, at = start;
        do {
            auto it = next.find(at);
            if (it == next.end()) return false;
            loop.push_back(Vec3d(at[0], at[1], at[2]));
            at = it->second;
            next.erase(it);
        } while (at != start);
        if (loop.size() < 3) return false;
        loops.push_back(std::move(loop));
    }
    return !loops.empty();
}

SceneLight polygonLight(const Scene& s, const std::vector<uint32_t>& tris, const Vec3d& normal, bool planar) {
    SceneLight out;
    DirectLight& l = out.light;
    l.kind = planar ? DirectLight::Kind::Polygon : DirectLight::Kind::Mesh;
    const Material& m = s.material(tris[0]);
    l.value = m.emission;
    l.twoSided = m.twoSidedEmission;
    l.normal = normal;
    out.triangles = tris;
    if (!planar || !boundaryLoops(s, tris, l.loops)) {
        l.loops.clear();
        for (uint32_t t : tris) l.loops.push_back({Vec3d(s.vertex(t, 0)), Vec3d(s.vertex(t, 1)), Vec3d(s.vertex(t, 2))});
    }
    double total = 0;
    for (uint32_t t : tris) {
        total += 0.5 * length(cross(Vec3d(s.vertex(t, 1)) - Vec3d(s.vertex(t, 0)), Vec3d(s.vertex(t, 2)) - Vec3d(s.vertex(t, 0))));
        out.triangleCdf.push_back(total);
    }
    for (double& c : out.triangleCdf) c /= total;
    out.triangleCdf.back() = 1.0;
    out.sampledArea = total;
    return out;
}

/// Vertex k (0..2) of triangle `index` of a polygon light: a scene triangle or one of its own.
Vec3f lightVertex(const SceneLight& sl, const Scene* scene, std::size_t index, int k) {
    if (sl.triangles.empty()) return sl.ownTriangles[index * 3 + std::size_t(k)];
    return scene->vertex(sl.triangles[index], k);
}

}  // namespace

std::vector<SceneLight> sceneLights(const Scene& scene) {
    std::vector<SceneLight> out;
    const std::size_t n = scene.triangleCount();
    std::vector<Vec3d> normal(n);
    std::vector<uint32_t> emissive;
    for (std::size_t t = 0; t < n; ++t) {
        if (!scene.material(t).isEmissive()) continue;
        const Vec3d a(scene.vertex(t, 0)), b(scene.vertex(t, 1)), c(scene.vertex(t, 2));
        const Vec3d ng = cross(b - a, c - a);
        if (!(length(ng) > 0)) continue;
        normal[t] = normalize(ng);
        emissive.push_back(uint32_t(t));
    }
    // Join emissive triangles across shared (undirected) edges.
    UnionFind groups(n);
    std::map<std::pair<Key, Key>, uint32_t> firstWithEdge;
    for (uint32_t t : emissive)
        for (int k = 0; k < 3; ++k) {
            Key a = keyOf(scene.vertex(t, k)), b = keyOf(scene.vertex(t, (k + 1) % 3));
            if (b < a) std::swap(a, b);
            auto [it, inserted] = firstWithEdge.emplace(std::make_pair(a, b), t);
            if (!inserted && scene.materialIds[it->second] == scene.materialIds[t]) groups.join(it->second, t);
        }
    std::map<uint32_t, std::vector<uint32_t>> members;  // root (smallest index) -> triangles
    for (uint32_t t : emissive) members[groups.find(t)].push_back(t);
    for (const auto& [root, tris] : members) {
        bool planar = true;
        for (uint32_t t : tris) planar = planar && samePlane(scene, root, t, normal);
        out.push_back(polygonLight(scene, tris, normal[root], planar));
    }

    int32_t index = 0;
    for (const PointLight& p : scene.pointLights) {
        SceneLight l;
        l.light.kind = DirectLight::Kind::Point;
        l.light.position = Vec3d(p.position);
        l.light.value = p.intensity;
        l.punctual = index++;
        out.push_back(l);
    }
    for (const SpotLight& s : scene.spotLights) {
        SceneLight l;
        l.light.kind = DirectLight::Kind::Spot;
        l.light.position = Vec3d(s.position);
        l.light.direction = Vec3d(s.direction);  // used as is by the estimator (unit by contract)
        l.light.value = s.intensity;
        l.light.innerCone = s.innerConeAngle;
        l.light.outerCone = s.outerConeAngle;
        l.punctual = index++;
        out.push_back(l);
    }
    for (const DirectionalLight& d : scene.directionalLights) {
        SceneLight l;
        l.light.kind = DirectLight::Kind::Directional;
        l.light.direction = normalize(Vec3d(d.direction));
        l.light.value = d.irradiance;
        l.punctual = index++;
        out.push_back(l);
    }
    return out;
}

SceneLight freeLight(const DirectLight& light) {
    SceneLight out;
    out.light = light;
    if (light.kind != DirectLight::Kind::Polygon && light.kind != DirectLight::Kind::Mesh) return out;
    // A fan from each loop's first vertex: the triangles' signed areas (around the polygon's
    // normal; a mesh loop around its own) sum to the loop's, whatever its shape.
    double total = 0;
    for (const auto& loop : light.loops) {
        if (loop.size() < 3) continue;
        Vec3d loopNormal = light.normal;
        if (light.kind == DirectLight::Kind::Mesh) {
            const Vec3d v = newellVector(loop);
            if (!(length(v) > 0)) continue;
            loopNormal = normalize(v);
        }
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
            const Vec3d c = cross(loop[i] - loop[0], loop[i + 1] - loop[0]);
            const double signedArea = 0.5 * dot(c, loopNormal);
            if (signedArea == 0) continue;
            for (const Vec3d& p : {loop[0], loop[i], loop[i + 1]}) out.ownTriangles.push_back(Vec3f(p));
            out.ownSign.push_back(signedArea > 0 ? 1.0f : -1.0f);
            total += std::abs(signedArea);
            out.triangleCdf.push_back(total);
        }
    }
    if (out.triangleCdf.empty()) throw ValueError("a polygon light has no area");
    for (double& c : out.triangleCdf) c /= total;
    out.triangleCdf.back() = 1.0;
    out.sampledArea = total;
    return out;
}

PolygonLightPoint samplePolygonLight(const SceneLight& sl, const Scene* scene, float u, float v) {
    const std::size_t count = sl.triangles.empty() ? sl.ownSign.size() : sl.triangles.size();
    if (count == 0 || sl.triangleCdf.size() != count) throw ValueError("the light has no triangles to sample");
    if (!sl.triangles.empty() && !scene) throw ValueError("a light made of scene triangles needs its scene");
    const std::size_t k = std::min<std::size_t>(
        std::upper_bound(sl.triangleCdf.begin(), sl.triangleCdf.end(), double(u)) - sl.triangleCdf.begin(), count - 1);
    const double lo = k ? sl.triangleCdf[k - 1] : 0.0, hi = sl.triangleCdf[k];
    u = hi > lo ? float(std::min(0.99999994, (double(u) - lo) / (hi - lo))) : 0.5f;
    float b1, b2;
    uniformTriangle(u, v, b1, b2);
    const Vec3f a = lightVertex(sl, scene, k, 0), b = lightVertex(sl, scene, k, 1), c = lightVertex(sl, scene, k, 2);
    PolygonLightPoint out;
    out.position = a + (b - a) * b1 + (c - a) * b2;
    out.sign = sl.triangles.empty() ? sl.ownSign[k] : 1.0f;
    // A cancelling triangle runs the other way round: its own normal times its sign is the light's.
    out.normal = normalize(cross(b - a, c - a)) * out.sign;
    return out;
}

std::vector<DirectLight> splitQuadLight(const DirectLight& light, int pieces) {
    if (light.kind != DirectLight::Kind::Polygon || light.loops.size() != 1 || light.loops[0].size() != 4 || pieces < 2)
        return {light};
    const std::vector<Vec3d>& q = light.loops[0];
    // (s, t) in the unit square to the quad: q0 at (0, 0), q1 at (1, 0), q2 at (1, 1), q3 at (0, 1).
    const auto at = [&](int i, int j) {
        const double s = double(i) / pieces, t = double(j) / pieces;
        return (q[0] * (1 - s) + q[1] * s) * (1 - t) + (q[3] * (1 - s) + q[2] * s) * t;
    };
    std::vector<DirectLight> out;
    for (int j = 0; j < pieces; ++j)
        for (int i = 0; i < pieces; ++i) {
            DirectLight piece = light;
            piece.loops = {{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}};
            out.push_back(std::move(piece));
        }
    return out;
}

double lightVisibility(const Scene& scene, const Tracer& tracer, const SceneLight& sl, const Vec3f& x, uint32_t samples, uint64_t stream,
                       RayCount& rays, const Vec3f* normal) {
    const DirectLight& l = sl.light;
    if (l.kind == DirectLight::Kind::Directional) {
        ++rays.occluded;
        return tracer.occluded(Ray{x, -Vec3f(l.direction)}) ? 0.0 : 1.0;
    }
    if (l.kind != DirectLight::Kind::Polygon && l.kind != DirectLight::Kind::Mesh) {
        const Vec3f toLight = Vec3f(l.position) - x;
        if (!(dot(toLight, toLight) > 0)) return 1.0;
        ++rays.occluded;
        return tracer.occluded(Ray{x, toLight, 0.0f, kShadowEnd}) ? 0.0 : 1.0;
    }
    // Polygon or mesh: stratified points over its area (samplePolygonLight). One 2-D Sobol
    // point per sample: choosing the triangle with another sequence leaves each triangle's
    // subset of points uneven (0.46 for a half-blocked quad at 256 samples). A free light's
    // cancelling triangles (freeLight) weigh negatively, so the sums stay over its region.
    // The shadow rays of a batch of samples go to the tracer together (16-ray packets: they
    // share their origin, and the answers are the single rays', Tracer::occluded); the sums
    // then take the samples in their order, as one ray at a time did: the same bits.
    constexpr uint32_t kBatch = 64;
    Ray batch[kBatch];
    double weights[kBatch];
    bool blocked[kBatch];
    double seen = 0, total = 0;
    const uint64_t scramble = hashCombine(stream, 0x5eed);
    for (uint32_t first = 0; first < samples; first += kBatch) {
        std::size_t count = 0;
        for (uint32_t i = first; i < std::min(samples, first + kBatch); ++i) {
            float u, v;
            sobol02(i, scramble, u, v);
            const PolygonLightPoint p = samplePolygonLight(sl, &scene, u, v);
            const Vec3f toLight = p.position - x;
            const float dist2 = dot(toLight, toLight);
            if (!(dist2 > 0)) continue;
            const Vec3f wi = toLight / std::sqrt(dist2);
            // The sample's share of the light's solid angle from x; 0 from behind a one-sided face.
            float cosLight = -dot(p.normal, wi);
            if (l.twoSided) cosLight = std::abs(cosLight);
            double weight = std::max(0.0f, cosLight) / dist2;
            if (normal) weight *= std::max(0.0f, dot(*normal, wi));
            if (!(weight > 0)) continue;
            weights[count] = weight * p.sign;
            batch[count++] = Ray{x, toLight, 0.0f, kShadowEnd};
        }
        rays.occluded += count;
        tracer.occluded(batch, count, blocked);
        for (std::size_t k = 0; k < count; ++k) {
            total += weights[k];
            if (!blocked[k]) seen += weights[k];
        }
    }
    return total > 0 ? std::clamp(seen / total, 0.0, 1.0) : 1.0;
}

Rgb shadowedIrradiance(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, const Vec3f& n,
                       uint32_t samples, uint64_t stream, RayCount& rays, bool onSurface) {
    const Rgb e = exactIrradiance(light.light, Vec3d(x), normalize(Vec3d(n)));
    if (maxComponent(e) <= 0) return Rgb(0, 0, 0);  // no light for this normal: no shadow rays
    // Off the surface towards its front: the side every lit direction leaves from.
    const Vec3f from = onSurface ? offsetRayOrigin(x, n, n) : x;
    return e * float(lightVisibility(scene, tracer, light, from, samples, stream, rays, &n));
}

Rgb runtimeDirectIrradiance(const Scene& scene, const Tracer& tracer, const std::vector<SceneLight>& lights,
                            const Vec3f& x, const Vec3f& n, uint32_t samples, uint64_t stream, RayCount& rays) {
    Rgb sum(0, 0, 0);
    for (std::size_t i = 0; i < lights.size(); ++i)
        sum += shadowedIrradiance(scene, tracer, lights[i], x, n, samples, hashCombine(stream, i), rays);
    return sum;
}

std::shared_ptr<const ReceiverDirectFilter> receiverFilter(const Scene& scene, const std::vector<SceneLight>& lights) {
    auto f = std::make_shared<ReceiverDirectFilter>();
    f->triangle.assign(scene.triangleCount(), 0);
    f->punctual.assign(scene.pointLights.size() + scene.spotLights.size() + scene.directionalLights.size(), 0);
    for (const SceneLight& l : lights) {
        for (uint32_t t : l.triangles) f->triangle[t] = 1;
        if (l.punctual >= 0) f->punctual[std::size_t(l.punctual)] = 1;
    }
    return f;
}

}  // namespace vdblight
