// The glTF probe view (export_gltf.h): spheres at the chosen nodes, vertex colours from the
// query for each vertex's normal, and the volume's box as a line primitive, in one .glb.
// The volume's frame (right-handed, +Y up, metres) is glTF's, so positions go in unchanged.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "engine_internal.h"
#include "glb_writer.h"
#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/engines.h"
#include "vdblight/query/query.h"

namespace vdblight {

using namespace exporter;

namespace {

// A UV sphere of unit radius: two poles and kRings rings of kSegments vertices; triangles
// fan from the poles and join neighbouring rings (no degenerate triangle).
constexpr int kRings = 4, kSegments = 8;
constexpr int kSphereVertices = 2 + kRings * kSegments;
constexpr int kSphereTriangles = 2 * kSegments + 2 * kSegments * (kRings - 1);

struct UnitSphere {
    std::vector<Vec3d> normals;
    std::vector<uint32_t> indices;
    UnitSphere() {
        normals.push_back(Vec3d(0, 1, 0));
        for (int r = 1; r <= kRings; ++r) {
            const double theta = M_PI * r / (kRings + 1);
            for (int s = 0; s < kSegments; ++s) {
                const double phi = 2 * M_PI * s / kSegments;
                normals.push_back(Vec3d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
            }
        }
        normals.push_back(Vec3d(0, -1, 0));
        const auto ring = [](int r, int s) { return uint32_t(1 + (r - 1) * kSegments + (s % kSegments)); };
        const uint32_t south = kSphereVertices - 1;
        for (int s = 0; s < kSegments; ++s) {  // counter-clockwise seen from outside
            indices.insert(indices.end(), {0u, ring(1, s + 1), ring(1, s)});
            for (int r = 1; r < kRings; ++r) {
                indices.insert(indices.end(), {ring(r, s), ring(r, s + 1), ring(r + 1, s)});
                indices.insert(indices.end(), {ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s)});
            }
            indices.insert(indices.end(), {south, ring(kRings, s), ring(kRings, s + 1)});
        }
    }
};

struct Probe {
    Vec3d position;
    double radius;
};

bool onSlice(const GridSpec& g, const int idx[3], const GltfProbeOptions& o) {
    if (o.sliceAxis < 0) return true;
    const double at = (o.sliceAt - g.origin[o.sliceAxis]) / g.spacing;
    return idx[o.sliceAxis] == int(std::lround(at));
}

std::vector<Probe> chooseProbes(const Volume& volume, const GltfProbeOptions& o) {
    const int every = std::max(1, o.every);
    const bool decimated = every > 1 || o.sliceAxis >= 0;
    uint64_t total = 0;
    for (const VolumeLevel& level : volume.levels) total += level.storedNodes();
    if (!decimated && total > o.maxSpheresWithoutDecimation)
        throw ValueError("the volume has " + std::to_string(total) + " nodes, over " +
                         std::to_string(o.maxSpheresWithoutDecimation) + " spheres for a glTF view; choose nodes with "
                         "--every K or --slice AXIS=VALUE");
    std::vector<Probe> probes;
    for (const VolumeLevel& level : volume.levels) {
        const GridSpec& g = level.grid;
        for (std::size_t s = 0; s < level.storedNodes(); ++s) {
            const uint64_t linear = level.sparse() ? level.activeNodes[s] : s;
            const int idx[3] = {int(linear % uint64_t(g.nx)), int(linear / uint64_t(g.nx) % uint64_t(g.ny)),
                                int(linear / (uint64_t(g.nx) * uint64_t(g.ny)))};
            if (idx[0] % every || idx[1] % every || idx[2] % every || !onSlice(g, idx, o)) continue;
            probes.push_back({g.node(idx[0], idx[1], idx[2]), o.radius > 0 ? o.radius : 0.2 * g.spacing});
            if (probes.size() > o.maxSpheres)
                throw ValueError("over " + std::to_string(o.maxSpheres) + " spheres for a glTF view; choose a larger --every");
        }
    }
    if (probes.empty()) throw ValueError("no node lies on the chosen --slice / --every; nothing to show");
    return probes;
}

// The glTF JSON is built as an object whose keys keep the order they are added in.
using Json = nlohmann::ordered_json;

Json accessor(int view, int componentType, std::size_t count, const char* type) {
    return {{"bufferView", view}, {"componentType", componentType}, {"count", count}, {"type", type}};
}

/// A VEC3 accessor's min and max (glTF requires them for POSITION): the floats themselves,
/// written as doubles that read back as the same floats.
Json withMinMax(Json accessor, const std::vector<float>& xyz) {
    float lo[3] = {xyz[0], xyz[1], xyz[2]}, hi[3] = {xyz[0], xyz[1], xyz[2]};
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], xyz[i]);
        hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    }
    accessor["min"] = {double(lo[0]), double(lo[1]), double(lo[2])};
    accessor["max"] = {double(hi[0]), double(hi[1]), double(hi[2])};
    return accessor;
}

}  // namespace

GltfProbeSummary exportGltfProbes(const Volume& volume, const std::string& path, const GltfProbeOptions& o) {
    if (o.every < 0) throw ValueError("--every must be 1 or more");
    if (o.sliceAxis > 2) throw ValueError("--slice axis must be x, y or z");
    const IrradianceQuery query(volume);
    const std::vector<Probe> probes = chooseProbes(volume, o);
    const UnitSphere sphere;
    const std::size_t vertices = probes.size() * kSphereVertices;
    std::vector<float> positions(3 * vertices), normals(3 * vertices);
    std::vector<double> radiance(3 * vertices);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t p = r.begin(); p < r.end(); ++p)
            for (int v = 0; v < kSphereVertices; ++v) {
                const std::size_t at = 3 * (p * kSphereVertices + v);
                const Vec3d& n = sphere.normals[v];
                const Rgb e = query.irradianceWorld(probes[p].position, Vec3f(n));
                for (int a = 0; a < 3; ++a) {
                    positions[at + a] = float(probes[p].position[a] + probes[p].radius * n[a]);
                    normals[at + a] = float(n[a]);
                    radiance[at + a] = double(e[a]) / M_PI;
                }
            }
    });
    double brightest = 0;
    for (double v : radiance) brightest = std::max(brightest, v);
    GltfProbeSummary summary;
    summary.spheres = probes.size();
    summary.colourScale = brightest > 0 ? 1.0 / brightest : 1.0;
    std::vector<float> colours(radiance.size());
    for (std::size_t i = 0; i < radiance.size(); ++i)
        colours[i] = float(std::clamp(radiance[i] * summary.colourScale, 0.0, 1.0));
    std::vector<uint32_t> indices;
    indices.reserve(probes.size() * sphere.indices.size());
    for (std::size_t p = 0; p < probes.size(); ++p)
        for (uint32_t i : sphere.indices) indices.push_back(uint32_t(p * kSphereVertices) + i);

    // The box of the volume's nodes: 8 corners, 12 edges.
    const Bounds& b = query.bounds();
    std::vector<float> corners;
    for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) corners.push_back(float((c >> a) & 1 ? b.hi[a] : b.lo[a]));
    std::vector<uint32_t> edges;
    for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a)
            if (!((c >> a) & 1)) edges.insert(edges.end(), {uint32_t(c), uint32_t(c | (1 << a))});

    GlbBuffer buf;
    struct View { uint32_t offset, length; int target; };
    std::vector<View> views;
    const auto add = [&](const void* data, std::size_t bytes, int target) {
        views.push_back({buf.append(data, bytes), uint32_t(bytes), target});
        return int(views.size() - 1);
    };
    const int vPos = add(positions.data(), positions.size() * 4, 34962);
    const int vNrm = add(normals.data(), normals.size() * 4, 34962);
    const int vCol = add(colours.data(), colours.size() * 4, 34962);
    const int vIdx = add(indices.data(), indices.size() * 4, 34963);
    const int vBox = add(corners.data(), corners.size() * 4, 34962);
    const int vEdge = add(edges.data(), edges.size() * 4, 34963);
    if (buf.bin.size() > (uint64_t(1) << 31))
        throw ValueError("the glTF view would be over 2 GiB; choose fewer nodes with --every K or --slice AXIS=VALUE");

    Json j;
    j["asset"] = {{"version", "2.0"}, {"generator", "vdblight export --format gltf"}};
    j["extensionsUsed"] = {"KHR_materials_unlit"};
    j["scene"] = 0;
    Json vdblight = {{"spheres", probes.size()}, {"colour_scale", summary.colourScale},
                     {"colour", "per vertex: clamp(colour_scale * E(node, vertex normal) / pi, 0, 1), linear RGB; E in W/m^2"}};
    j["scenes"] = Json::array({{{"name", "vdblight probes"}, {"nodes", {0, 1}}, {"extras", {{"vdblight", vdblight}}}}});
    j["nodes"] = Json::array({{{"name", "probes"}, {"mesh", 0}}, {{"name", "volume_box"}, {"mesh", 1}}});
    j["materials"] = Json::array(
        {{{"name", "probe_irradiance"},
          {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
          {"extensions", {{"KHR_materials_unlit", Json::object()}}}}});
    j["meshes"] = Json::array(
        {{{"name", "probes"},
          {"primitives", Json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"COLOR_0", 2}}},
                                       {"indices", 3}, {"material", 0}, {"mode", 4}}})}},
         {{"name", "volume_box"},
          {"primitives", Json::array({{{"attributes", {{"POSITION", 4}}}, {"indices", 5}, {"mode", 1}}})}}});
    j["accessors"] = Json::array({withMinMax(accessor(vPos, 5126, vertices, "VEC3"), positions),
                                  accessor(vNrm, 5126, vertices, "VEC3"), accessor(vCol, 5126, vertices, "VEC3"),
                                  accessor(vIdx, 5125, indices.size(), "SCALAR"),
                                  withMinMax(accessor(vBox, 5126, 8, "VEC3"), corners),
                                  accessor(vEdge, 5125, edges.size(), "SCALAR")});
    Json bufferViews = Json::array();
    for (const View& v : views)
        bufferViews.push_back({{"buffer", 0}, {"byteOffset", v.offset}, {"byteLength", v.length}, {"target", v.target}});
    j["bufferViews"] = std::move(bufferViews);
    j["buffers"] = Json::array({{{"byteLength", (buf.bin.size() + 3) / 4 * 4}}});
    const std::string glb = glbBytes(j.dump() + "\n", std::move(buf.bin));
    writeFileAtomically(path, glb);
    summary.bytes = glb.size();
    return summary;
}

}  // namespace vdblight
