// Preview grids for looking at a bake in Blender or Houdini (docs/format.md "Preview file").
//
// `exportPreviewVdb` samples any volume kind through IrradianceQuery on the export lattice
// (export.h: the volume's finest node spacing over its node box, or `resolution` texels
// along the longest axis) and writes a separate .vdb whose grids a DCC tool shows directly:
//   irradiance_avg                 Vec3f  mean of E(x, n) over the six axis normals
//   irradiance_xpos ... _zneg      Vec3f  E(x, n) for n = +x, -x, +y, -y, +z, -z
//   density                        float  1 on every lattice point (for volume shaders)
// Voxel (i, j, k) sits at the lattice point (i, j, k); vector_type invariant; names use
// letters, digits and underscores only. The baked volume itself is left untouched.
#pragma once

#include <string>

#include "vdblight/export.h"
#include "vdblight/volume.h"

namespace vdblight {

/// Writes the preview grids to `path` atomically (temporary file, then rename) and returns
/// the lattice used. Throws ValueError (lattice too large: over `maxVoxels` points),
/// FormatError (no lookup for the volume kind) or IoError.
TextureLattice exportPreviewVdb(const Volume& volume, const std::string& path, int resolution = 0,
                                uint64_t maxVoxels = 64ull << 20);

/// The grid names written by exportPreviewVdb, in order.
const char* const* previewGridNames(int* count);

}  // namespace vdblight
