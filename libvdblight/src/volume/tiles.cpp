// The fixed partition of a volume's nodes into tiles (tiles.h): bricks of 8^3 nodes of every
// level, cut into contiguous runs of about equal cost.
#include "vdblight/volume/tiles.h"

#include <algorithm>

#include "sha256.h"
#include "core/grid_index.h"
#include "vdblight/core/errors.h"

namespace vdblight {
namespace {

constexpr int kBrick = 8;  // the VDB leaf node: 8^3 voxels

/// Per level, the brick of every stored node: ((bk * nby) + bj) * nbx + bi.
std::vector<uint64_t> nodeBricks(const VolumeLevel& level) {
    const GridSpec& g = level.grid;
    const uint64_t nbx = uint64_t(g.nx + kBrick - 1) / kBrick, nby = uint64_t(g.ny + kBrick - 1) / kBrick;
    const std::size_t stored = level.storedNodes();
    std::vector<uint64_t> out(stored);
    const uint64_t nx = uint64_t(g.nx), ny = uint64_t(g.ny);
    for (std::size_t n = 0; n < stored; ++n) {
        const uint64_t linear = level.sparse() ? level.activeNodes[n] : n;
        const core::Index3 c = core::unflatten(linear, nx, ny);
        out[n] = ((uint64_t(c.k) / kBrick) * nby + uint64_t(c.j) / kBrick) * nbx + uint64_t(c.i) / kBrick;
    }
    return out;
}

/// (brick, nodes in it) of one level, bricks ascending.
std::vector<std::pair<uint64_t, uint64_t>> brickCosts(const std::vector<uint64_t>& bricks) {
    std::vector<uint64_t> sorted = bricks;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::pair<uint64_t, uint64_t>> out;
    for (uint64_t b : sorted) {
        if (out.empty() || out.back().first != b) out.emplace_back(b, 0);
        ++out.back().second;
    }
    return out;
}

}  // namespace

std::string tileParamsHash(const std::string& sceneHash, const std::string& parameters) {
    vdb_detail::Sha256 h;
    const std::string text = "vdblight tile parameters v1\nscene=" + sceneHash + "\n" + parameters;
    h.update(text.data(), text.size());
    return vdb_detail::Sha256::hex(h.finish());
}

const std::vector<std::string>& tileSummedKeys() {
    static const std::vector<std::string> keys = {"rays_intersect",   "rays_occluded",     "bake_seconds",
                                                  "direct_visibility_rays", "samples_total", "nodes_at_max_rays",
                                                  "probe_stage_samples", "photon_segments", "photon_face_crossings"};
    return keys;
}

BasisDesc probeStageBasis() {
    BasisDesc b;
    b.kind = "sh2_reflected";
    for (int j = 0; j < 9; ++j) b.channelNames.push_back("reflected_sh_" + std::to_string(j));
    return b;
}

void addEarlierStageSums(Metadata& tileMeta, const Metadata& stageInput) {
    for (const std::string& key : tileSummedKeys())
        if (auto it = stageInput.find(key); it != stageInput.end()) tileMeta["tile_earlier_" + key] = it->second;
}

uint64_t countBricks(const std::vector<VolumeLevel>& levels) {
    uint64_t total = 0;
    for (const VolumeLevel& l : levels) total += brickCosts(nodeBricks(l)).size();
    return total;
}

NodeMask tileNodeMask(const std::vector<VolumeLevel>& levels, int count, int index) {
    const uint64_t bricks = countBricks(levels);
    if (count < 1 || uint64_t(count) > bricks)
        throw ValueError("--tiles must be between 1 and " + std::to_string(bricks) +
                         " (the bricks of 8^3 nodes of this layout), got " + std::to_string(count));
    if (index < 0 || index >= count)
        throw ValueError("--tile must be between 0 and " + std::to_string(count - 1) + ", got " + std::to_string(index));
    uint64_t total = 0;
    for (const VolumeLevel& l : levels) total += l.storedNodes();
    // A brick goes to the tile in which the middle of its cost falls, bricks in (level, z, y, x)
    // order: contiguous runs, each within one brick of total / count.
    NodeMask mask(levels.size());
    uint64_t before = 0;
    for (std::size_t l = 0; l < levels.size(); ++l) {
        const std::vector<uint64_t> nodeBrick = nodeBricks(levels[l]);
        const std::vector<std::pair<uint64_t, uint64_t>> costs = brickCosts(nodeBrick);
        std::vector<uint64_t> mine;  // bricks of this level in tile `index`, ascending
        for (const auto& [brick, cost] : costs) {
            const long double middle = (long double)before + 0.5L * (long double)cost;
            const int tile = std::min(count - 1, int(middle * count / (long double)total));
            if (tile == index) mine.push_back(brick);
            before += cost;
        }
        mask[l].assign(nodeBrick.size(), 0);
        for (std::size_t n = 0; n < nodeBrick.size(); ++n)
            mask[l][n] = std::binary_search(mine.begin(), mine.end(), nodeBrick[n]) ? 1 : 0;
    }
    return mask;
}

NodeMask photonTileDepthNodes(const GridSpec& grid, int count, int index) {
    if (count < 1) throw ValueError("--tiles must be at least 1, got " + std::to_string(count));
    if (index < 0 || index >= count)
        throw ValueError("--tile must be between 0 and " + std::to_string(count - 1) + ", got " + std::to_string(index));
    // Contiguous runs of equal node counts: every node costs the same depth rays (128-bit
    // products: no overflow for any count).
    const uint64_t n = grid.nodeCount();
    const uint64_t first = uint64_t((unsigned __int128)index * n / unsigned(count));
    const uint64_t end = uint64_t((unsigned __int128)(index + 1) * n / unsigned(count));
    NodeMask mask(1, std::vector<uint8_t>(n, 0));
    std::fill(mask[0].begin() + std::ptrdiff_t(first), mask[0].begin() + std::ptrdiff_t(end), uint8_t(1));
    return mask;
}

void setTileWindows(std::vector<VolumeLevel>& levels, const NodeMask* only) {
    if (only && only->size() != levels.size()) throw ValueError("the node mask does not match the levels");
    for (std::size_t l = 0; l < levels.size(); ++l) {
        VolumeLevel& level = levels[l];
        level.windowFirst = 0, level.windowNodes = 0;
        if (!only) continue;
        const std::vector<uint8_t>& m = (*only)[l];
        if (m.size() != level.storedNodes()) throw ValueError("the node mask does not match level " + std::to_string(l));
        const auto first = std::find(m.begin(), m.end(), uint8_t(1));
        if (first == m.end()) {
            level.windowNodes = std::min<std::size_t>(1, m.size());
            continue;
        }
        const auto last = std::find(m.rbegin(), m.rend(), uint8_t(1));
        level.windowFirst = std::size_t(first - m.begin());
        level.windowNodes = std::size_t(m.rend() - last) - level.windowFirst;
    }
}

}  // namespace vdblight
