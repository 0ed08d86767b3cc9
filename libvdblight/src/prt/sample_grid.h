// A hash grid over surface samples that answers "which sample stands for this surface
// point?": the nearest sample facing the same side (dot of normals > 0), ties to the lower
// index. The same rule assigns area to samples (surface_samples.cpp) and maps a ray's hit
// point to its sender (sampled_form_factors.cpp), so a sample's area and the rays that find
// it describe the same piece of surface.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight::prt_detail {

class SampleGrid {
public:
    static constexpr uint32_t kNone = 0xffffffffu;

    /// Indexes points[i] (with unit normals[i]) in cubic cells of edge `cell` (> 0).
    SampleGrid(const std::vector<Vec3f>& points, const std::vector<Vec3f>& normals, float cell);

    /// The nearest indexed point facing n within the 3^3 cells around p, else within the
    /// 5^3 cells; kNone if there is none.
    uint32_t nearestFacing(const Vec3f& p, const Vec3f& n) const;

    /// The key of the cell holding p (exposed for the incremental thinning of
    /// surface_samples.cpp, which must use the same cells).
    static uint64_t cellKey(int x, int y, int z) {
        return (uint64_t(uint32_t(x) & 0x1fffffu) << 42) | (uint64_t(uint32_t(y) & 0x1fffffu) << 21) |
               uint64_t(uint32_t(z) & 0x1fffffu);
    }

private:
    const std::vector<Vec3f>& points_;
    const std::vector<Vec3f>& normals_;
    float cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace vdblight::prt_detail
