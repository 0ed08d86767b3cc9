// A linear index of a box of nx x ny x nz entries, x fastest (GridSpec::index, cells, bricks),
// back to (i, j, k). (Internal.)
#pragma once

#include <cstdint>

namespace vdblight::core {

struct Index3 {
    int i = 0, j = 0, k = 0;
};

/// The inverse of i + nx * (j + ny * k).
inline Index3 unflatten(uint64_t linear, uint64_t nx, uint64_t ny) {
    return {int(linear % nx), int((linear / nx) % ny), int(linear / (nx * ny))};
}

}  // namespace vdblight::core
