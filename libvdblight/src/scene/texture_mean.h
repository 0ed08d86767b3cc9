// The mean colour of a texture, for a material whose diffuse colour comes from a texture:
// a Lambertian bake needs one albedo per material (docs/scene.md, "Formats").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "vdblight/core/math.h"

namespace vdblight {

/// Mean linear RGB of a PNG image of any kind (palette, grey, grey + alpha, RGB, RGBA, 1 to
/// 16 bits, interlaced or not; decoded by libpng), its sRGB values decoded to linear; alpha
/// and gamma chunks are ignored. Decodes row by row (memory: one row), refuses images over
/// 2^28 pixels. Returns false and says why in `why` (libpng's reason) if the data cannot be read.
bool pngMeanLinear(const uint8_t* data, std::size_t size, Rgb& mean, std::string& why);

}  // namespace vdblight
