// The in-memory volume: basis description, consistency checks, metadata accessors.
#include "vdblight/volume/volume.h"

#include <cmath>
#include <cstdio>
#include <set>

#include "vdblight/core/errors.h"
#include "basis/shadow_edges.h"

namespace vdblight {
namespace {

bool isValidGridName(const std::string& name) {
    if (name.empty()) return false;
    for (char ch : name) {
        const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_';
        if (!ok) return false;
    }
    return true;
}

void validateLevel(const VolumeLevel& level, std::size_t index, int channels) {
    const GridSpec& g = level.grid;
    const std::string where = "volume level " + std::to_string(index);
    if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0) {
        throw FormatError(where + " has non-positive dimensions " + std::to_string(g.nx) + " x " +
                          std::to_string(g.ny) + " x " + std::to_string(g.nz));
    }
    if (!(std::isfinite(g.spacing) && g.spacing > 0.0)) {
        throw FormatError(where + " has invalid spacing " + std::to_string(g.spacing) + " (must be finite and > 0)");
    }
    if (!isFinite(g.origin)) throw FormatError(where + " has a non-finite origin");
    if (level.windowNodes && level.windowFirst + level.windowNodes > level.storedNodes())
        throw FormatError(where + " holds a window of nodes beyond its " + std::to_string(level.storedNodes()) + " nodes");
    const std::size_t expected = level.heldNodes() * std::size_t(channels) * 3;
    if (level.data.size() != expected) {
        throw FormatError(where + " holds " + std::to_string(level.data.size()) + " floats, expected " +
                          std::to_string(expected) + " (" + std::to_string(level.heldNodes()) + " nodes x " +
                          std::to_string(channels) + " channels x 3)");
    }
    if (!level.validity.empty()) {
        if (level.validity.size() != g.nodeCount()) {
            throw FormatError(where + " has " + std::to_string(level.validity.size()) + " validity values, expected " +
                              std::to_string(g.nodeCount()));
        }
        for (float v : level.validity)
            if (!(v >= 0.0f && v <= 1.0f)) throw FormatError(where + " has a validity outside [0, 1]");
    }
    if (!level.depth.empty()) {
        const std::size_t want = level.heldNodes() * std::size_t(depth::kFloatsPerNode);
        if (level.depth.size() != want)
            throw FormatError(where + " has " + std::to_string(level.depth.size()) + " depth values, expected " +
                              std::to_string(want));
        for (float v : level.depth)
            if (!(v >= 0.0f && v <= 1.0f)) throw FormatError(where + " has a depth moment outside [0, 1]");
    }
}

/// Direct light (direct_light.h): visibility only in occlusion mode, only on dense level 0,
/// one value in [0, 1] per node and listed light.
void validateDirect(const Volume& v) {
    const DirectLightSet& d = v.direct;
    if (d.mode == DirectMode::Baked && !d.lights.empty()) throw FormatError("a baked-direct volume lists lights");
    if (d.mode == DirectMode::Occlusion && d.lights.empty()) throw FormatError("an occlusion volume lists no lights");
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        const VolumeLevel& level = v.levels[l];
        if (level.lightVisibility.empty()) {
            if (l == 0 && d.hasVisibility()) throw FormatError("an occlusion volume has no light visibility");
            continue;
        }
        if (l != 0 || !d.hasVisibility()) throw FormatError("light visibility only on level 0 of an occlusion volume");
        if (level.lightVisibility.size() != level.heldNodes() * d.lights.size())
            throw FormatError("volume level 0 has " + std::to_string(level.lightVisibility.size()) +
                              " light visibility values, expected " +
                              std::to_string(level.heldNodes() * d.lights.size()));
        for (float x : level.lightVisibility)
            if (!(x >= 0.0f && x <= 1.0f)) throw FormatError("volume level 0 has a light visibility outside [0, 1]");
    }
    for (std::size_t l = 0; l < v.levels.size(); ++l) {
        const std::vector<float>& edges = v.levels[l].lightShadowEdges;
        if (edges.empty()) continue;
        if (l != 0 || v.levels[0].lightVisibility.empty())
            throw FormatError("shadow edges only beside the light visibility of level 0");
        if (edges.size() != v.levels[0].lightVisibility.size() * shadow_edge::kFloatsPerLight)
            throw FormatError("volume level 0 has " + std::to_string(edges.size()) + " shadow edge values, expected " +
                              std::to_string(v.levels[0].lightVisibility.size() * shadow_edge::kFloatsPerLight));
        for (std::size_t k = 0; k < edges.size(); k += shadow_edge::kFloatsPerLight) {
            const float* e = &edges[k];
            const float direction = std::fabs(e[shadow_edge::kDirectionX]) + std::fabs(e[shadow_edge::kDirectionY]) +
                                    std::fabs(e[shadow_edge::kDirectionZ]);
            if (!(std::fabs(e[shadow_edge::kDistance]) <= shadow_edge::kRange && e[shadow_edge::kWidth] >= 0.0f &&
                  e[shadow_edge::kWidth] <= shadow_edge::kNoEdge && direction <= 2.0f &&
                  e[shadow_edge::kFar] >= 0.0f && e[shadow_edge::kFar] <= shadow_edge::kRange + shadow_edge::kMaxStrip))
                throw FormatError("volume level 0 has a shadow edge outside its range (shadow_edges.h)");
        }
    }
}

}  // namespace

void Volume::validate() const {
    if (basis.kind.empty()) throw FormatError("volume basis kind is empty");
    if (basis.channelCount() == 0) throw FormatError("volume basis has no channels");
    std::set<std::string> seen;
    for (const std::string& name : basis.channelNames) {
        if (!isValidGridName(name)) {
            throw FormatError("channel name '" + name + "' is invalid (letters, digits and underscores only)");
        }
        if (!seen.insert(name).second) throw FormatError("channel name '" + name + "' appears twice");
    }
    if (levels.empty()) throw FormatError("volume has no levels");
    for (std::size_t i = 0; i < levels.size(); ++i) validateLevel(levels[i], i, basis.channelCount());
    for (const VolumeLevel& level : levels)
        if (level.hasDepth() != levels[0].hasDepth()) throw FormatError("depth moments on some levels but not all");
    for (int c = 0; c < depth::kChannels; ++c)
        if (seen.count(depth::channelName(c))) throw FormatError("channel name '" + depth::channelName(c) + "' is reserved for depth moments");
    validateDirect(*this);
    validateLevelStructure(*this);
}

bool Volume::hasDepth() const { return !levels.empty() && levels[0].hasDepth(); }

std::vector<VolumeLevel> volumeLevels(const std::vector<LevelTopology>& topology) {
    std::vector<VolumeLevel> levels(topology.size());
    for (std::size_t l = 0; l < topology.size(); ++l) static_cast<LevelTopology&>(levels[l]) = topology[l];
    return levels;
}

void placeVolumeInWorld(Volume& volume, const Vec3d& origin) {
    for (VolumeLevel& level : volume.levels) level.grid.origin += origin;
    for (DirectLight& light : volume.direct.lights) light.translate(origin);  // bake --direct
}

int Volume::refineFactor() const {
    return levels.size() < 2 ? 1 : int(std::lround(levels[0].grid.spacing / levels[1].grid.spacing));
}

double metaNumber(const Metadata& meta, const std::string& key, double fallback) {
    const auto it = meta.find(key);
    if (it == meta.end()) return fallback;
    if (const auto* i = std::get_if<int64_t>(&it->second)) return double(*i);
    if (const auto* d = std::get_if<double>(&it->second)) return *d;
    return fallback;  // a string is not converted
}

std::string metaString(const Metadata& meta, const std::string& key, const std::string& fallback) {
    const auto it = meta.find(key);
    if (it == meta.end()) return fallback;
    if (const auto* s = std::get_if<std::string>(&it->second)) return *s;
    if (const auto* i = std::get_if<int64_t>(&it->second)) return std::to_string(*i);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", std::get<double>(it->second));
    return buf;
}

}  // namespace vdblight
