// The probe grid of three.js's LightProbeGridWebGL (npm `three` 0.187.0, r187,
// examples/jsm/lighting/LightProbeGridWebGL.js): `vdblight export --format three`.
//
// That class keeps L2 SH probes in one RGBA 3-D atlas of seven packed sub-volumes stacked
// along z, each with one padding slice (a copy of its first / last data slice) at both ends:
// nx x ny x 7 (nz + 2) texels. Sub-volume t holds components 4t .. 4t + 3 of the 27 floats
// c0.rgb, c1.rgb, ..., c8.rgb (the last alpha is 0). Its shader evaluates
//   E(n) = 0.886227 c0 + 1.023328 (c1 y + c2 z + c3 x) + ...  =  sum_j A_l(j) c_j Y_j(n),
// so c_j are radiance SH coefficients in docs/format.md's convention (orthonormal, no
// Condon-Shortley phase, j = l (l + 1) + m): the volume's bands 0..2 go in unchanged.
// The probes are export's lattice (the volume's nodes by default) plus one border probe on
// each side of every axis, a spacing outside, holding the edge node's value: between them
// three's trilinear filtering is the volume's trilinear interpolation, and beyond the nodes
// it gives what `query` gives there (the clamped value). Three puts probes at cell centres
// (a grid of width w and n probes has them at x0 + (i + 1/2) w / n), so the grid's box is
// the node box grown by 1.5 spacings: it covers the scene that a default bake's nodes (its
// bounds inset by half a spacing) leave a thin band of near the walls, which three would
// leave unlit (it lights only fragments whose sample point lies in the box).
//
//   ThreeGridSummary s = exportThreeGrid(readVolume("cornell.vdb"), "web/", {});
//   // web/probe_grid_sh.bin (the atlas texels) + web/probe_grid.json (bounds, resolution)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/export.h"
#include "vdblight/volume.h"

namespace vdblight {

struct ThreeGridOptions {
    bool halfFloat = true;           ///< HalfFloatType texels (default; 8 B per texel) or FloatType (16 B)
    int resolution = 0;              ///< probes along the longest axis; 0: the finest node spacing
    uint64_t maxBytes = 4ull << 30;  ///< refuse exports needing more memory than this
};

struct ThreeGridSummary {
    TextureLattice lattice;          ///< the probe points: export's lattice and one border probe per side
    int atlasDepth = 0;              ///< 7 (nz + 2)
    std::vector<std::string> files;  ///< probe_grid_sh.bin, probe_grid.json (full paths)
    uint64_t bytes = 0;
    int foldedLights = 0;            ///< lights whose direct light was folded into the SH (occlusion volumes)
};

/// The file names written into the output directory.
constexpr const char* kThreeGridAtlasFile = "probe_grid_sh.bin";
constexpr const char* kThreeGridJsonFile = "probe_grid.json";

/// Packs nine SH order-2 coefficient textures (RGB + unused alpha each, x fastest, as the
/// `sh2` layout samples them) of a dims[0] x dims[1] x dims[2] lattice into the atlas:
/// 4 floats per texel, dims[0] x dims[1] x 7 (dims[2] + 2) texels, x fastest, then y, then
/// the atlas slice.
std::vector<float> packThreeGridAtlas(const std::vector<std::vector<float>>& sh2Textures, const int dims[3]);

/// Writes probe_grid_sh.bin (the atlas as little-endian half or float RGBA, no header) and
/// probe_grid.json (what LightProbeGridWebGL needs: bounds, resolution, texel type; docs/engines.md)
/// into `outDir` (created if missing), all or nothing. The volume must hold real SH of order
/// >= 2 (sh2, sh:N; bands above 2 are left out, as `query --sh-order 2` does); FormatError
/// otherwise, and for a `--direct runtime` volume (its lights need the scene at run time). An
/// occlusion volume's listed lights (the default bake) have their direct light folded into
/// the probes' SH bands 0..2 (the query's exact direct light x visibility, fitted per probe;
/// probe_grid.json's "direct_light" names them). ValueError for an axis with a single probe, values beyond the half range, or
/// memory above maxBytes; IoError if the directory cannot be written.
ThreeGridSummary exportThreeGrid(const Volume& volume, const std::string& outDir, const ThreeGridOptions& options);

}  // namespace vdblight
