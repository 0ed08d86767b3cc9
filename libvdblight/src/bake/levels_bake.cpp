#include "levels_bake.h"

#include <string>

#include "pass_metadata.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"

namespace vdblight::bake_detail {

void checkLevelsBake(uint64_t samples, const char* what, int threads, const LevelLayout& layout) {
    if (samples == 0) throw ValueError(std::string(what) + " must be at least 1");
    if (threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    if (layout.levels.empty()) throw ValueError("the layout has no levels");
}

Volume emptyLevelsVolume(const LevelLayout& layout, const BasisDesc& basis, std::size_t floatsPerNode,
                         const NodeMask* only) {
    Volume volume;
    volume.basis = basis;
    volume.levels = volumeLevels(layout.levels);
    setTileWindows(volume.levels, only);
    for (VolumeLevel& l : volume.levels) l.data.assign(l.heldNodes() * floatsPerNode, 0.0f);
    return volume;
}

LevelNode levelNode(Volume& volume, const std::pair<int, std::size_t>& item) {
    VolumeLevel& level = volume.levels[std::size_t(item.first)];
    const uint64_t linear = level.sparse() ? level.activeNodes[item.second] : item.second;
    return {level, item.second, linear, (uint64_t(item.first) << 56) | linear};
}

void finishLevelsBake(Volume& volume, const LevelLayout& layout, uint64_t seams, const ParallelRun& run,
                      const NodeMask* only, LevelsBakeStats* stats) {
    if (volume.levels.size() > 1 && !only) applySeamConstraints(volume);
    PassMetadata(volume.meta)
        .text("layout", layoutName(layout.kind))
        .count("refine", layout.refine)
        .count("nodes_seam", int64_t(seams));
    if (stats) {
        stats->nodes = layout.totalNodes();
        stats->rays = run.rays;
        stats->seconds = run.seconds;
        stats->seamNodes = seams;
    }
}

}  // namespace vdblight::bake_detail
