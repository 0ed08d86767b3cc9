// The textures of one streaming cell (export_cells.h): for each kind of texture the whole
// export writes (export.cpp), its texels at the cell's lattice points, computed as the whole
// export computes them there, so that the cells reassemble into the whole export's texels.
// Internal to the export module.
#pragma once

#include <functional>
#include <vector>

#include "export_internal.h"
#include "query/light_visibility.h"

namespace vdblight::exporter {

/// Texels [first, first + dims) per axis of the whole export lattice.
struct CellRange {
    int first[3] = {0, 0, 0};
    int dims[3] = {0, 0, 0};
    std::size_t texels() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
};

/// The layout's texels (sampleLayout's for the SH layouts; sampleBasis's for `basis`, which
/// needs `basis`): one RGBA array per texture, x fastest.
std::vector<std::vector<float>> cellLayoutTextures(const VolumeLookup& lookup, const TextureLattice& whole,
                                                   const CellRange& cell, ExportLayout layout, const Basis* basis,
                                                   std::size_t textures);

/// The light visibility textures (sampleVisibility's texels: four lights per texture).
std::vector<std::vector<float>> cellVisibilityTextures(const LightVisibility& visibility, const TextureLattice& whole,
                                                       const CellRange& cell, std::size_t lights);

/// The finest level's depth moments of node (i, j, k) into out (depth::kFloatsPerNode floats);
/// false where that level stores no node.
using FinestNodeDepth = std::function<bool(int i, int j, int k, float* out)>;

/// True if the whole export writes depth textures on `lattice`: its texels are exactly the
/// nodes of the finest level `finest` (depthTextures's rule).
bool depthOnFinestNodes(const GridSpec& finest, const TextureLattice& lattice);

/// The three depth textures (depthTextures's texels: free faces where the finest level stores
/// no node), for a lattice on which depthOnFinestNodes holds.
std::vector<std::vector<float>> cellDepthTextures(const FinestNodeDepth& depth, const CellRange& cell);

/// Level 0's shadow edges at node (i, j, k) into out (shadow_edge::kFloatsPerLight floats per
/// listed light, in VolumeLevel::lightShadowEdges's order).
using NodeShadowEdges = std::function<void(int i, int j, int k, float* out)>;

/// The shadow-edge textures (edgeTextures's texels, in edgeTextureDescs's order, through
/// packEdgeTexel), for a single-level volume's lattice on which depthOnFinestNodes holds.
std::vector<std::vector<float>> cellEdgeTextures(const NodeShadowEdges& edges, const CellRange& cell, std::size_t lights,
                                                 bool withRamp, bool withStrips);

}  // namespace vdblight::exporter
