// A probe view any DCC opens: `vdblight export --format gltf` writes a glTF 2.0 binary (.glb)
// with one small sphere per node, coloured per vertex by the irradiance for that vertex's
// normal (so a sphere shows where the light comes from), and the volume's box as lines.
//
//   GltfProbeOptions o;
//   o.every = 4;  // every 4th node along each axis
//   exportGltfProbes(readVolume("office.vdb"), "office_probes.glb", o);
#pragma once

#include <cstdint>
#include <string>

#include "vdblight/volume.h"

namespace vdblight {

struct GltfProbeOptions {
    int every = 0;          ///< keep nodes whose (i, j, k) are all multiples of `every` (0 or 1: all)
    int sliceAxis = -1;     ///< 0, 1, 2: keep only the nodes of each level on the plane nearest `sliceAt`
    double sliceAt = 0;     ///< world coordinate of the slice plane along sliceAxis
    double radius = 0;      ///< sphere radius; 0: 0.2 of each level's node spacing
    /// Without `every` or a slice, a volume with more nodes than this is refused (one line
    /// naming --every and --slice): a sphere per node of a million-node volume is a file of
    /// gigabytes that no DCC opens comfortably.
    uint64_t maxSpheresWithoutDecimation = 100000;
    uint64_t maxSpheres = 2000000;  ///< refused above this even with decimation (names --every)
};

struct GltfProbeSummary {
    uint64_t spheres = 0;
    uint64_t bytes = 0;
    double colourScale = 0;  ///< vertex colour = clamp(colourScale * E(n) / pi, 0, 1)
};

/// Writes the .glb to `path` (atomically: a temporary file renamed at the end). Colours: the
/// irradiance E(x_node, n_vertex) of the library's query, divided by pi (the radiance of a
/// white Lambertian surface there) and scaled by one factor for the file so that the
/// brightest channel is 1 (glTF's COLOR_0 is linear, in [0, 1]); the factor is in the file's
/// scene extras (`vdblight.colour_scale`). Throws ValueError for a refused size or bad option
/// and IoError if the file cannot be written.
GltfProbeSummary exportGltfProbes(const Volume& volume, const std::string& path, const GltfProbeOptions& options);

}  // namespace vdblight
