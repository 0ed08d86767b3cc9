#include <cmath>
#include <sstream>

#include "core/grid_index.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

Vec3d GridSpec::node(std::size_t index) const {
    const core::Index3 n = core::unflatten(index, uint64_t(nx), uint64_t(ny));
    return node(n.i, n.j, n.k);
}

Bounds GridSpec::nodeBounds() const {
    Bounds b;
    b.lo = origin;
    b.hi = origin + Vec3d(nx - 1, ny - 1, nz - 1) * spacing;
    return b;
}

namespace {

std::string formatBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 5) {
        bytes /= 1024.0;
        ++u;
    }
    std::ostringstream s;
    s.precision(bytes < 10 ? 2 : 1);
    s << std::fixed << bytes << ' ' << units[u];
    return s.str();
}

// Node count along one axis of extent `extent`, in double so that absurd requests are
// caught before any integer overflows.
double countAlong(double extent, double spacing, bool cellCentred) {
    return cellCentred ? std::max(1.0, std::round(extent / spacing)) : std::floor(extent / spacing + 1e-9) + 1.0;
}

}  // namespace

GridSpec placeUniformGrid(const Bounds& sceneBounds, const GridPlacement& p, std::size_t bytesPerNode) {
    if ((p.spacing > 0) == (p.resolution > 0))
        throw ValueError(p.spacing < 0 || p.resolution < 0
                             ? "grid spacing and resolution must be positive"
                             : "give exactly one of spacing or resolution");
    if (!std::isfinite(p.spacing)) throw ValueError("grid spacing must be a finite number");

    const bool explicitBounds = p.bounds.has_value();
    const Bounds box = explicitBounds ? *p.bounds : sceneBounds;
    if (box.empty() || !isFinite(box.lo) || !isFinite(box.hi))
        throw ValueError("grid bounds are empty or not finite");
    const Vec3d extent = box.size();
    const double longest = std::max(extent.x, std::max(extent.y, extent.z));
    if (!(longest > 0)) throw ValueError("grid bounds have zero size");

    // Over scene bounds the nodes are cell centres of a tiling (inset by half a spacing);
    // over explicit bounds the outermost nodes lie on the box.
    double spacing = p.spacing;
    if (p.resolution > 0)
        spacing = explicitBounds ? (p.resolution > 1 ? longest / (p.resolution - 1) : longest)
                                 : longest / p.resolution;

    double counts[3];
    for (int a = 0; a < 3; ++a) counts[a] = countAlong(extent[a], spacing, !explicitBounds);
    const double nodes = counts[0] * counts[1] * counts[2];
    const double bytes = nodes * double(bytesPerNode);
    if (!(nodes <= double(p.maxNodes))) {
        std::ostringstream s;
        s << "grid of " << counts[0] << " x " << counts[1] << " x " << counts[2] << " = " << nodes
          << " nodes would need " << formatBytes(bytes) << "; the limit is " << p.maxNodes
          << " nodes (use a larger spacing or a smaller resolution)";
        throw ValueError(s.str());
    }

    GridSpec g;
    g.spacing = spacing;
    g.nx = int(counts[0]);
    g.ny = int(counts[1]);
    g.nz = int(counts[2]);
    // Centre the nodes in the box so that the leftover is split evenly on both sides.
    const Vec3d span = Vec3d(g.nx - 1, g.ny - 1, g.nz - 1) * spacing;
    g.origin = box.center() - span * 0.5;
    return g;
}

}  // namespace vdblight
