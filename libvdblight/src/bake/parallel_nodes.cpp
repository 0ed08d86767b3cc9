#include "parallel_nodes.h"

#include <algorithm>
#include <cmath>

#include "vdblight/bake/each_pass.h"
#include "vdblight/basis/basis.h"
#include "vdblight/volume/volume.h"
#include "vdblight/layout/layout.h"
#include "basis/sh.h"

namespace vdblight {
namespace bake_detail {

std::vector<std::pair<int, std::size_t>> nodesToBake(const Volume& volume, uint64_t& seams, const NodeMask* only) {
    if (only && only->size() != volume.levels.size()) throw ValueError("the node mask does not match the levels");
    std::vector<std::pair<int, std::size_t>> work;
    const int K = volume.refineFactor();
    for (std::size_t l = 0; l < volume.levels.size(); ++l) {
        const std::size_t stored = volume.levels[l].storedNodes();
        std::vector<char> skip(stored, 0);
        if (l > 0)
            for (std::size_t n : seamNodes(volume.levels, int(l), K)) skip[n] = 1, ++seams;
        for (std::size_t n = 0; n < stored; ++n)
            if (!skip[n] && (!only || (*only)[l].at(n))) work.emplace_back(int(l), n);
    }
    return work;
}

std::size_t checkThreadsAndGrid(int threads, const GridSpec& grid) {
    if (threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    const std::size_t nodes = grid.nodeCount();
    if (nodes == 0) throw ValueError("the grid has no nodes");
    return nodes;
}

Volume emptyShVolume(const GridSpec& grid, const NodeMask* only, const Basis* basis) {
    Volume volume;
    volume.basis = basis ? basis->desc() : BasisDesc::sh2();
    volume.levels.resize(1);
    volume.levels[0].grid = grid;
    setTileWindows(volume.levels, only);
    const std::size_t floats = basis ? basis->floatsPerNode() : std::size_t(sh::kCoeffs) * 3;
    volume.levels[0].data.assign(volume.levels[0].heldNodes() * floats, 0.0f);
    return volume;
}

}  // namespace bake_detail

double BakeStats::errorQuantile(double q) const { return vdblight::errorQuantile(estimatedError, q); }
}  // namespace vdblight
