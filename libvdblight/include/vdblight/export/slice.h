// The export module's pictures to look at: slices through a volume (below) and the .vdb
// preview for Blender / Houdini (second part).
//
// Images of irradiance on a plane through a volume, so that a user can look at a bake
// instead of reading numbers.
//
// The plane is perpendicular to an axis at a world coordinate; every pixel holds
// E(x, n) = IrradianceQuery::irradiance at the pixel's centre for one fixed normal n, so any
// volume kind slices the same way. Image axes (u to the right, v up; row 0 is the top):
//   --axis x: (u, v) = (z, y)     --axis y: (u, v) = (x, z)     --axis z: (u, v) = (x, y)
// The image covers the volume's node box in u and v; pixel (c, r) has its centre at
//   u = lo_u + (c + 0.5) * (hi_u - lo_u) / width,  v = hi_v - (r + 0.5) * (hi_v - lo_v) / height.
//
//   SliceOptions o;  o.axis = 2;  o.at = 0.25;  o.normal = {0, 0, 1};
//   SliceImage img = sliceVolume(readVolume("cornell.vdb"), o);
//   writeSlice("slice.png", img, ToneMap{});
#pragma once

#include <string>
#include <vector>

#include "vdblight/export/export.h"
#include "vdblight/core/math.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

struct SliceOptions {
    int axis = 2;                 ///< 0 = x, 1 = y, 2 = z: the plane's normal axis
    double at = 0.0;              ///< world coordinate of the plane along `axis` (inside the node box)
    Vec3f normal{0, 0, 1};        ///< surface normal the irradiance is evaluated for (any length > 0)
    int size = 256;               ///< pixels along the longer image axis (the other in proportion, >= 1)
};

/// Linear irradiance (W/m^2) per pixel, RGB, row 0 at the top.
struct SliceImage {
    int width = 0, height = 0;
    std::vector<float> rgb;       ///< 3 floats per pixel, rows top to bottom
    int uAxis = 0, vAxis = 1;     ///< world axes of the image's u (right) and v (up) directions
    Bounds box;                   ///< the volume's node box
    /// World position of the centre of pixel (column c, row r).
    Vec3d pixelCentre(int c, int r, int axis, double at) const;
};

/// Samples the slice. Throws ValueError (axis not 0..2, `at` outside the node box, zero or
/// non-finite normal, size < 1 or > 16384) or FormatError (no lookup for the volume kind).
SliceImage sliceVolume(const Volume& volume, const SliceOptions& options);

/// How a PNG maps irradiance to display values (docs/engines.md "Slices"):
///   L = 2^exposure * k * E / pi   (E / pi: the radiance of a white Lambertian surface)
///   display = sRGB_encode(L / (1 + L))   per channel (Reinhard), 8 bits.
/// With `autoExposure`, k = 0.18 / (mean luminance of E / pi over the slice) (k = 1 when the
/// slice is black), so mid-grey is the slice's average; otherwise k = 1.
struct ToneMap {
    bool autoExposure = true;
    double exposure = 0.0;        ///< extra stops (EV) on top of k
};

/// The 8-bit sRGB values of the PNG (3 per pixel) after tone mapping.
std::vector<uint8_t> toneMapSlice(const SliceImage& image, const ToneMap& tone);

/// Writes `.png` (tone-mapped 8-bit sRGB, RGB) or `.exr` (linear float RGB, the values of
/// the slice; header attributes vdblightAxis, vdblightAt, vdblightNormal) chosen by the
/// extension, atomically (temporary file, then rename). Throws ValueError for another
/// extension and IoError if the file cannot be written.
void writeSlice(const std::string& path, const SliceImage& image, const ToneMap& tone, int axis = 2,
                double at = 0.0, const Vec3f& normal = Vec3f(0, 0, 1));

/// Writes `rgb` (8-bit sRGB, 3 bytes per pixel, rows top to bottom) as an RGB PNG to `path`
/// atomically (core/atomic_file.h), encoded by libpng. Throws ValueError if `rgb` does not hold
/// width x height pixels, IoError if the file cannot be encoded or written.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Preview grids for looking at a bake in Blender or Houdini (docs/format.md "Preview file").
//
// `exportPreviewVdb` samples any volume kind through IrradianceQuery on the export lattice
// (export/export.h: the volume's finest node spacing over its node box, or `resolution` texels
// along the longest axis) and writes a separate .vdb whose grids a DCC tool shows directly:
//   irradiance_avg                 Vec3f  mean of E(x, n) over the six axis normals
//   irradiance_xpos ... _zneg      Vec3f  E(x, n) for n = +x, -x, +y, -y, +z, -z
//   density                        float  1 on every lattice point (for volume shaders)
// Voxel (i, j, k) sits at the lattice point (i, j, k); vector_type invariant; names use
// letters, digits and underscores only. The baked volume itself is left untouched.

namespace vdblight {

/// Writes the preview grids to `path` atomically (temporary file, then rename) and returns
/// the lattice used. Throws ValueError (lattice too large: over `maxVoxels` points),
/// FormatError (no lookup for the volume kind) or IoError.
TextureLattice exportPreviewVdb(const Volume& volume, const std::string& path, int resolution = 0,
                                uint64_t maxVoxels = 64ull << 20);

/// The grid names written by exportPreviewVdb, in order.
const char* const* previewGridNames(int* count);

}  // namespace vdblight
