// The mean colour of a texture, for a material whose diffuse colour comes from a texture:
// a Lambertian bake needs one albedo per material (docs/scene.md, "Formats").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "vdblight/core/math.h"

namespace vdblight {

/// Mean linear RGB of a PNG image (8-bit gray, gray + alpha, RGB, RGBA or palette; 16-bit
/// gray, gray + alpha, RGB or RGBA; not interlaced), its sRGB values decoded to linear; alpha
/// is ignored. Decodes row by row (memory: two rows), refuses images over 2^28 pixels.
/// Returns false and says why in `why` if the data cannot be read.
bool pngMeanLinear(const uint8_t* data, std::size_t size, Rgb& mean, std::string& why);

}  // namespace vdblight
