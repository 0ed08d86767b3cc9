#include "sample_grid.h"

#include <cmath>
#include <limits>

namespace vdblight::prt_detail {

SampleGrid::SampleGrid(const std::vector<Vec3f>& points, const std::vector<Vec3f>& normals, float cell)
    : points_(points), normals_(normals), cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3f& p = points[i];
        cells_[cellKey(int(std::floor(p.x / cell_)), int(std::floor(p.y / cell_)), int(std::floor(p.z / cell_)))]
            .push_back(uint32_t(i));
    }
}

uint32_t SampleGrid::nearestFacing(const Vec3f& p, const Vec3f& n) const {
    const int cx = int(std::floor(p.x / cell_)), cy = int(std::floor(p.y / cell_)), cz = int(std::floor(p.z / cell_));
    float best = std::numeric_limits<float>::infinity();
    uint32_t owner = kNone;
    for (int reach = 1; reach <= 2 && owner == kNone; ++reach)
        for (int dz = -reach; dz <= reach; ++dz)
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) {
                    const auto it = cells_.find(cellKey(cx + dx, cy + dy, cz + dz));
                    if (it == cells_.end()) continue;
                    for (uint32_t j : it->second) {
                        const Vec3f d = points_[j] - p;
                        const float d2 = dot(d, d);
                        if (dot(normals_[j], n) > 0.0f && (d2 < best || (d2 == best && j < owner))) {
                            best = d2;
                            owner = j;
                        }
                    }
                }
    return owner;
}

}  // namespace vdblight::prt_detail
