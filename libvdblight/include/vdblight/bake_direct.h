// Direct light out of the SH (issue 15, `bake --direct runtime | occlusion`; direct_light.h).
//
// A bake in these modes first chooses the lights whose direct light it leaves out of the
// basis (planDirectLight), bakes with TransportOptions::skipAtReceiver set to the plan's
// filter, and then (occlusion) bakes each chosen light's visibility at every node
// (bakeLightVisibility). The lights are chosen by their measured contribution to the volume:
// at a subset of nodes, the light's mean irradiance over all normals times its visibility
// from the node (shadow rays), summed; not by power alone, so a bright light behind a wall
// ranks below a dim one in the room.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vdblight/direct_light.h"
#include "vdblight/layout.h"
#include "vdblight/scene_lights.h"
#include "vdblight/tiles.h"
#include "vdblight/volume.h"

namespace vdblight {

struct Scene;
class Tracer;
class Interrupter;

struct DirectOptions {
    DirectMode mode = DirectMode::Baked;
    /// Occlusion: how many lights get a visibility channel (the most important ones), 1..16.
    int maxLights = 4;
    /// Shadow rays per node and polygon light for the visibility channels (stratified over its area).
    uint32_t visibilitySamples = 64;
    /// Occlusion: also bake each light's shadow edges (shadow_edges.h), which keep its shadow
    /// edges sharp between the nodes. false: the visibility channels alone (as before issue 32).
    bool shadowEdges = true;
    /// Ranking: at most this many nodes (evenly strided) and shadow rays per polygon light there.
    uint32_t rankingNodes = 512;
    uint32_t rankingSamples = 16;
    uint64_t seed = 1;
    int threads = 0;
};

/// Which lights a bake leaves out at the receiver, in the scene's local frame.
struct DirectPlan {
    DirectMode mode = DirectMode::Baked;
    std::vector<SceneLight> lights;     ///< runtime: every light; occlusion: the chosen K, most important first
    std::vector<double> contribution;   ///< per light in `lights`: measured share of the volume's direct light (0..1)
    std::size_t sceneLightCount = 0;
    std::shared_ptr<const ReceiverDirectFilter> filter;  ///< for TransportOptions::skipAtReceiver (null: baked)
};

/// Chooses the lights (see above). Throws ValueError for occlusion in a scene without lights
/// and for maxLights outside 1..16.
DirectPlan planDirectLight(const Scene& scene, const Tracer& tracer, const GridSpec& grid, const DirectOptions& options);

/// Writes the plan into a baked single-level volume: Volume::direct (mode, lights) and, for
/// occlusion, level 0's lightVisibility (lightVisibility() of scene_lights.h at each node; a
/// node the light cannot reach at all -- behind a one-sided polygon, outside a spot's cone --
/// gets 1, so that interpolating towards the lit side is not darkened by it) and, with
/// DirectOptions::shadowEdges, level 0's lightShadowEdges (shadow_edges.h). Deterministic:
/// the samples of node n and light i depend on (seed, n, i) only. With `only` (one tile of a
/// bake, tiles.h) only those nodes are baked (direct_visibility_rays counts their rays).
void bakeLightVisibility(const Scene& scene, const Tracer& tracer, const DirectPlan& plan, const DirectOptions& options,
                         Volume& volume, Interrupter* interrupter = nullptr, const NodeMask* only = nullptr);

}  // namespace vdblight
