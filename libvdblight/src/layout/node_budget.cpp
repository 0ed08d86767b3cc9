#include "vdblight/layout/layout.h"

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"

namespace vdblight {

double spacingForNodeBudget(const Bounds& box, uint64_t nodes) {
    if (nodes == 0) throw ValueError("the node budget must be at least 1");
    if (box.empty() || !isFinite(box.lo) || !isFinite(box.hi)) throw ValueError("grid bounds are empty or not finite");
    const Vec3d extent = box.size();
    const double longest = std::max(extent.x, std::max(extent.y, extent.z));
    if (!(longest > 0)) throw ValueError("grid bounds have zero size");
    double volume = 1.0;
    for (int a = 0; a < 3; ++a) volume *= std::max(extent[a], longest / kBudgetMinNodesOnLongestAxis);
    const double spacing = std::cbrt(volume / double(nodes));
    return std::min(std::max(spacing, longest / kBudgetMaxNodesOnLongestAxis), longest / kBudgetMinNodesOnLongestAxis);
}

}  // namespace vdblight
