// probe_grid.json of `export --format three` (internal to the export module): what a loader
// needs to place three.js's LightProbeGridWebGL over the volume and fill its atlas.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "vdblight/export/export.h"

namespace vdblight::exporter {

struct ThreeGridJsonInput {
    const TextureLattice* lattice = nullptr;  ///< the probe points (with the border probes)
    int atlasDepth = 0;
    bool halfFloat = true;
    std::string basisKind;       ///< the volume's vdblight:basis
    bool hasDepthMoments = false;
    nlohmann::ordered_json foldedDirect;  ///< foldedDirectJson (fold_direct.h) of an occlusion volume, or null
};

/// The JSON text (docs/engines.md, "three.js" lists the fields).
std::string threeGridJson(const ThreeGridJsonInput& in);

}  // namespace vdblight::exporter
