// Hemispherical depth buffers (Leonhardt & Bohn 4.2) on a g x g grid of the concentric
// square, and the four-nearest-directions lookup of figure 2.
#include <algorithm>
#include <cmath>

#include "vdblight/prt/prt.h"
#include "vdblight/sampling/sampling.h"

namespace vdblight {

Vec3f visibilityDirection(int g, int index) {
    const int i = index % g, j = index / g;
    float dx, dy;
    concentricSquareToDisk((float(i) + 0.5f) / float(g), (float(j) + 0.5f) / float(g), dx, dy);
    const float r2 = std::min(1.0f, dx * dx + dy * dy);
    const float s = std::sqrt(std::max(0.0f, 2.0f - r2));  // uniform hemisphere: z = 1 - r^2
    return {dx * s, dy * s, 1.0f - r2};
}

int visibilityNeighbours(int g, const Vec3f& d, int index[4], float weight[4]) {
    const float z = std::clamp(d.z, 0.0f, 1.0f);
    const float r = std::sqrt(1.0f - z);
    const float rho = std::sqrt(d.x * d.x + d.y * d.y);
    const float dx = rho > 0 ? d.x / rho * r : 0.0f, dy = rho > 0 ? d.y / rho * r : 0.0f;
    float u, v;
    concentricDiskToSquare(dx, dy, u, v);
    const float fx = std::clamp(u * float(g) - 0.5f, 0.0f, float(g - 1));
    const float fy = std::clamp(v * float(g) - 0.5f, 0.0f, float(g - 1));
    const int x0 = std::min(int(fx), g - 1), y0 = std::min(int(fy), g - 1);
    const int x1 = std::min(x0 + 1, g - 1), y1 = std::min(y0 + 1, g - 1);
    const float tx = fx - float(x0), ty = fy - float(y0);
    index[0] = y0 * g + x0; weight[0] = (1 - tx) * (1 - ty);
    index[1] = y0 * g + x1; weight[1] = tx * (1 - ty);
    index[2] = y1 * g + x0; weight[2] = (1 - tx) * ty;
    index[3] = y1 * g + x1; weight[3] = tx * ty;
    return 4;
}

}  // namespace vdblight
