// Occlusion volumes with shadow edges (shadow_edges.h): the edge textures an engine's shader
// needs beside the light_visibility textures (docs/shadow_visibility.md).

#include <algorithm>
#include <cmath>

#include "export_internal.h"
#include "basis/shadow_edges.h"

namespace vdblight::exporter {

bool hasShadowStrips(const Volume& volume) {
    if (volume.levels.empty()) return false;
    const std::vector<float>& e = volume.levels[0].lightShadowEdges;
    for (std::size_t k = shadow_edge::kFar; k < e.size(); k += shadow_edge::kFloatsPerLight)
        if (e[k] > 0.0f) return true;
    return false;
}

std::vector<TextureDesc> edgeTextureDescs(const DirectLightSet& direct, bool withRamp, bool withStrips) {
    std::vector<TextureDesc> out;
    if (!direct.hasVisibility()) return out;
    const std::size_t n = direct.lights.size();
    for (const char* part : {"distance", "width", "ramp"}) {
        if (!withRamp && std::string(part) == "ramp") continue;
        for (std::size_t first = 0; first < n; first += 4) {
            const std::size_t last = std::min(n, first + 4) - 1;
            TextureDesc d;
            d.name = std::string("light_edge_") + part + "_" + std::to_string(first) + "_" + std::to_string(last);
            for (std::size_t c = 0; c < 4; ++c)
                d.components[c] = first + c <= last ? std::string("edge ") + part + " of light " + std::to_string(first + c) : "0";
            out.push_back(d);
        }
    }
    // The second edge (shadow_edges.h, Part): one texture per light, its four floats.
    for (std::size_t l = 0; withStrips && l < n; ++l) {
        TextureDesc d;
        d.name = "light_edge_strip_" + std::to_string(l);
        const std::string of = " of light " + std::to_string(l);
        d.components = {"edge direction x" + of, "edge direction y" + of, "edge direction z" + of, "strip far side" + of};
        out.push_back(d);
    }
    return out;
}

std::vector<std::vector<float>> edgeTextures(const Volume& volume, const TextureLattice& lattice, bool withRamp, bool withStrips) {
    if (volume.levels.size() != 1 || volume.levels[0].lightShadowEdges.empty()) return {};
    // As the depth textures: the edges belong to the nodes (distances in cells), so only a
    // lattice that is the nodes carries them.
    const VolumeLevel& level = volume.levels[0];
    const GridSpec& g = level.grid;
    if (lattice.dims[0] != g.nx || lattice.dims[1] != g.ny || lattice.dims[2] != g.nz) return {};
    const double tol = 1e-9 * std::max(1.0, g.spacing * std::max({g.nx, g.ny, g.nz}));
    for (int a = 0; a < 3; ++a)
        if (std::fabs(lattice.lo[a] - g.origin[a]) > tol) return {};
    const std::size_t lights = volume.direct.lights.size(), groups = (lights + 3) / 4;
    const std::size_t strips = withStrips ? lights : 0;
    std::vector<std::vector<float>> out((withRamp ? 3 : 2) * groups + strips, std::vector<float>(g.nodeCount() * 4, 0.0f));
    for (std::size_t n = 0; n < g.nodeCount(); ++n)
        packEdgeTexel(&level.lightShadowEdges[n * lights * shadow_edge::kFloatsPerLight], lights, withRamp, withStrips, n, out);
    return out;
}

void packEdgeTexel(const float* nodeEdges, std::size_t lights, bool withRamp, bool withStrips, std::size_t texel,
                   std::vector<std::vector<float>>& out) {
    const std::size_t groups = (lights + 3) / 4;
    for (std::size_t l = 0; l < lights; ++l) {
        const float* e = nodeEdges + l * shadow_edge::kFloatsPerLight;
        const std::size_t at = texel * 4 + l % 4;
        out[l / 4][at] = e[shadow_edge::kDistance];
        out[groups + l / 4][at] = e[shadow_edge::kWidth];
        if (withRamp) out[2 * groups + l / 4][at] = shadow_edge::ramp(e[shadow_edge::kDistance], e[shadow_edge::kWidth]);
        if (withStrips) std::copy_n(e + shadow_edge::kDirectionX, 4, &out[(withRamp ? 3 : 2) * groups + l][texel * 4]);
    }
}

}  // namespace vdblight::exporter
