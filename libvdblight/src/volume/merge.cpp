// Merging the tiles of one bake (tiles.h) into the volume a single-process bake gives.
//
// Every node belongs to exactly one tile and was baked there with the same sample streams
// as in a single bake, so copying the nodes back gives the same values. What crosses tile
// borders is applied here: the seam constraints of bilevel / adaptive layouts (a seam node
// interpolates the coarser level, whose nodes may lie in other tiles). Metadata counts that
// each tile measured for its own nodes (rays) are summed in tile order.
//
// So does the blend of pass 0 into the probe pass (first_pass_blend.h, the default's): its
// variances are pooled over neighbouring nodes, so a last-stage tile carries pass 0's values
// and errors and the merge blends, before the error summary and the node filter, as the single
// bake does.
//
// Stage-0 tiles of `--probe-cache surface` also hold the bins of their nodes' paths as sparse
// integer sums (SurfaceBinSums, surface_bin_sums.h), which the merge adds (exact in any order).
//
// Photon tiles are not nodes but runs of photon batches: each holds the whole grid's exact
// sums of its batches (photon_sums.h), which the merge adds (integers: exact in any order)
// and normalises as the single bake does. Their depth moments (bake --depth-moments) are per
// node: each tile holds those of a run of nodes (photonTileDepthNodes), copied back here.
#include <algorithm>
#include <map>
#include <set>

#include "first_pass_blend.h"
#include "node_filter.h"
#include "tile_io.h"
#include "vdblight/volume/volume.h"
#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"
#include "vdblight/volume/tiles.h"
#include "basis/shadow_edges.h"
#include "volume/volume_compact.h"

namespace vdblight {
namespace {
using vdb_detail::TileFile;

std::string quoted(const std::string& path) { return "'" + path + "'"; }

/// Refuses tiles of other bakes, duplicates and gaps, naming the files.
void checkIdentities(const std::vector<TileFile>& tiles, const std::vector<std::string>& paths) {
    const TileId& first = tiles[0].id;
    for (std::size_t t = 1; t < tiles.size(); ++t) {
        const TileId& id = tiles[t].id;
        if (id.count != first.count)
            throw ValueError(quoted(paths[t]) + " is a tile of " + std::to_string(id.count) + " but " + quoted(paths[0]) +
                             " is a tile of " + std::to_string(first.count) + ": not the same bake");
        if (id.paramsHash != first.paramsHash)
            throw ValueError(quoted(paths[t]) + " and " + quoted(paths[0]) +
                             " were baked with different scenes or parameters (parameter hashes " +
                             id.paramsHash.substr(0, 12) + " and " + first.paramsHash.substr(0, 12) + ")");
    }
    std::map<int, std::size_t> seen;
    for (std::size_t t = 0; t < tiles.size(); ++t) {
        const auto [it, fresh] = seen.emplace(tiles[t].id.index, t);
        if (!fresh)
            throw ValueError(quoted(paths[it->second]) + " and " + quoted(paths[t]) + " are both tile " +
                             std::to_string(tiles[t].id.index) + " of " + std::to_string(first.count));
    }
    std::string missing;
    int missingCount = 0;
    for (int i = 0; i < first.count; ++i)
        if (!seen.count(i)) missing += (missingCount++ ? ", " : "") + std::to_string(i);
    if (missingCount > 0)
        throw ValueError(std::string(missingCount == 1 ? "tile " : "tiles ") + missing + " of " +
                         std::to_string(first.count) + (missingCount == 1 ? " is" : " are") + " missing (" +
                         std::to_string(tiles.size()) + " given)");
}

/// The counts each tile measured for its own nodes or batches (tileSummedKeys), summed in tile
/// order, plus (staged bakes) the earlier stages' once, into `meta` (a copy of the first tile's).
void sumTileCounts(Metadata& meta, const std::vector<TileFile>& tiles, const std::vector<std::size_t>& order) {
    const TileFile& first = tiles[order[0]];
    for (const std::string& key : tileSummedKeys()) {
        if (!meta.count(key)) continue;
        const auto earlier = first.part.meta.find("tile_earlier_" + key);
        if (std::holds_alternative<int64_t>(meta[key])) {
            int64_t sum = 0;
            for (std::size_t t : order) {
                const auto it = tiles[t].part.meta.find(key);
                if (it != tiles[t].part.meta.end() && std::holds_alternative<int64_t>(it->second))
                    sum += std::get<int64_t>(it->second);
            }
            if (earlier != first.part.meta.end() && std::holds_alternative<int64_t>(earlier->second))
                sum += std::get<int64_t>(earlier->second);
            meta[key] = sum;
        } else {
            double sum = 0;
            for (std::size_t t : order) sum += metaNumber(tiles[t].part.meta, key, 0);
            sum += metaNumber(first.part.meta, "tile_earlier_" + key, 0);
            meta[key] = sum;
        }
    }
}

/// The metadata of the first tile (in tile order) without the tile keys.
Metadata mergedMetadata(const std::vector<TileFile>& tiles, const std::vector<std::size_t>& order) {
    Metadata meta;
    for (const auto& [key, value] : tiles[order[0]].part.meta)
        if (key.compare(0, 5, "tile_") != 0) meta[key] = value;
    sumTileCounts(meta, tiles, order);
    return meta;
}

/// The depth moments of photon tiles (writePhotonTile), each of its own nodes, as the whole
/// grid's VolumeLevel::depth; refuses a set where some tiles have them and others not, or
/// where a node's are held by two tiles or by none. Empty if the tiles have none.
std::vector<float> photonTileDepth(const std::vector<TileFile>& tiles, const std::vector<std::size_t>& order,
                                   const std::vector<std::string>& paths) {
    const TileFile& first = tiles[order[0]];
    for (std::size_t t : order)
        if (tiles[t].depth != first.depth)
            throw FormatError(quoted(paths[t]) + (tiles[t].depth ? " has" : " has no") + " depth moments but " +
                              quoted(paths[order[0]]) + (first.depth ? " has" : " has none") +
                              ": tiles of bakes with and without --depth-moments");
    if (!first.depth) return {};
    const std::size_t nodes = first.photon->grid.nodeCount();
    std::vector<float> out(nodes * depth::kFloatsPerNode, 0.0f);
    std::vector<std::size_t> holder(nodes, tiles.size());  // the tile holding each node's
    for (std::size_t t : order) {
        const VolumeLevel& part = tiles[t].part.levels[0];
        for (std::size_t n = 0; n < part.activeNodes.size(); ++n) {
            const uint64_t node = part.activeNodes[n];
            if (holder[node] != tiles.size())
                throw FormatError(quoted(paths[holder[node]]) + " and " + quoted(paths[t]) +
                                  " both hold the depth moments of node " + std::to_string(node));
            holder[node] = t;
            std::copy(part.nodeDepth(n), part.nodeDepth(n) + depth::kFloatsPerNode,
                      out.begin() + std::ptrdiff_t(node * depth::kFloatsPerNode));
        }
    }
    const std::size_t missing = std::size_t(std::count(holder.begin(), holder.end(), tiles.size()));
    if (missing > 0)
        throw FormatError("the photon tiles hold the depth moments of " + std::to_string(nodes - missing) + " of the " +
                          std::to_string(nodes) + " nodes (node " +
                          std::to_string(std::find(holder.begin(), holder.end(), tiles.size()) - holder.begin()) +
                          " in none)");
    return out;
}

/// Photon tiles (writePhotonTile): each holds the whole grid's exact sums of a run of batches;
/// their sum is the single bake's total (photon_sums.h), normalised by the same photonVolume.
MergedTiles mergePhotonTiles(const std::vector<TileFile>& tiles, const std::vector<std::size_t>& order,
                             const std::vector<std::string>& paths) {
    const TileFile& first = tiles[order[0]];
    const PhotonSums& a = *first.photon;
    PhotonSums total;
    total.grid = a.grid;
    total.exponent = a.exponent;
    total.batches = a.batches;
    total.values.assign(a.values.size(), 0);
    uint64_t next = 0;  // the tiles' runs of batches, in tile order, must cover 0 .. batches
    for (std::size_t t : order) {
        if (!tiles[t].photon)
            throw FormatError(quoted(paths[t]) + " is no photon tile, but " + quoted(paths[order[0]]) + " is");
        const PhotonSums& p = *tiles[t].photon;
        if (p.exponent != a.exponent || p.batches != a.batches || p.grid.nx != a.grid.nx || p.grid.ny != a.grid.ny ||
            p.grid.nz != a.grid.nz || p.grid.spacing != a.grid.spacing || p.grid.origin.x != a.grid.origin.x ||
            p.grid.origin.y != a.grid.origin.y || p.grid.origin.z != a.grid.origin.z ||
            tiles[t].photonCompact != first.photonCompact)
            throw FormatError(quoted(paths[t]) + " and " + quoted(paths[order[0]]) + " differ in their photon grid or scale");
        if (p.firstBatch != next)
            throw FormatError(quoted(paths[t]) + " holds photon batches " + std::to_string(p.firstBatch) + ".." +
                              std::to_string(p.endBatch) + ", expected batches from " + std::to_string(next));
        next = p.endBatch;
        // Exact integer sums (photon_sums.h: a valid bake cannot overflow; a damaged file may).
        bool overflow = false;
        for (std::size_t n = 0; n < total.values.size(); ++n)
            overflow |= __builtin_add_overflow(total.values[n], p.values[n], &total.values[n]);
        if (overflow) throw FormatError(quoted(paths[t]) + " holds photon sums out of range (damaged?)");
    }
    total.firstBatch = 0;
    total.endBatch = next;
    if (next != total.batches)
        throw FormatError("the photon tiles hold batches 0.." + std::to_string(next) + " of " + std::to_string(total.batches));
    MergedTiles out;
    out.volume = photonVolume(total, mergedMetadata(tiles, order));
    out.volume.levels[0].depth = photonTileDepth(tiles, order, paths);
    out.write.halfFloat = first.halfFloat;
    out.write.reproducible = first.reproducible;
    if (first.photonCompact) {  // as the pass's finish (bake --compact)
        out.volume = iv::compact(out.volume);
        out.write.halfFloat = true;
    }
    return out;
}

}  // namespace

MergedTiles mergeTiles(const std::vector<std::string>& paths) {
    if (paths.empty()) throw ValueError("no tiles to merge");
    std::vector<TileFile> tiles;
    for (const std::string& p : paths) tiles.push_back(vdb_detail::readTileFile(p));
    checkIdentities(tiles, paths);
    std::vector<std::size_t> order(tiles.size());  // by tile index: the sums' fixed order
    for (std::size_t t = 0; t < tiles.size(); ++t) order[std::size_t(tiles[t].id.index)] = t;

    const TileFile& first = tiles[order[0]];
    if (first.photon) return mergePhotonTiles(tiles, order, paths);
    const int channels = first.part.basis.channelCount();
    const std::size_t floats = std::size_t(channels) * 3;
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const TileFile& t = tiles[i];
        if (t.photon || t.depth != first.depth || t.visibility != first.visibility || t.edges != first.edges || t.error != first.error ||
            t.firstPass != first.firstPass ||
            bool(t.part.surfaceBins) != bool(first.part.surfaceBins) ||
            t.part.direct.mode != first.part.direct.mode || t.part.direct.lights.size() != first.part.direct.lights.size())
            throw FormatError(quoted(paths[i]) + " and " + quoted(paths[order[0]]) + " differ in the grids or lights they carry");
    }
    MergedTiles out;
    Volume& v = out.volume;
    std::vector<float> error;  // level 0's per-node errors (TileNodeStats)
    std::vector<float> firstValues, firstError;  // and pass 0's, for the blend
    v.basis = first.part.basis;
    for (std::size_t l = 0; l < first.part.levels.size(); ++l) {
        const VolumeLevel& shape = first.part.levels[l];
        VolumeLevel level;
        level.grid = shape.grid;
        level.refinedCells = shape.refinedCells;
        // (linear index, tile, position in the tile) of every node, sorted by linear index.
        std::vector<std::tuple<uint64_t, std::size_t, std::size_t>> nodes;
        for (std::size_t t : order) {
            const VolumeLevel& part = tiles[t].part.levels[l];
            for (std::size_t n = 0; n < part.activeNodes.size(); ++n) nodes.emplace_back(part.activeNodes[n], t, n);
        }
        std::sort(nodes.begin(), nodes.end());
        for (std::size_t n = 1; n < nodes.size(); ++n)
            if (std::get<0>(nodes[n]) == std::get<0>(nodes[n - 1]))
                throw FormatError(quoted(paths[std::get<1>(nodes[n - 1])]) + " and " + quoted(paths[std::get<1>(nodes[n])]) +
                                  " both hold node " + std::to_string(std::get<0>(nodes[n])) + " of level " + std::to_string(l));
        const bool dense = first.denseLevels[l] != 0;
        if (dense && nodes.size() != level.grid.nodeCount())
            throw FormatError("the tiles hold " + std::to_string(nodes.size()) + " of the " +
                              std::to_string(level.grid.nodeCount()) + " nodes of level " + std::to_string(l));
        level.data.resize(nodes.size() * floats);
        if (!dense) level.activeNodes.reserve(nodes.size());
        // Depth moments, light visibility and per-node errors follow the nodes (tile_io.h).
        if (first.depth) level.depth.resize(nodes.size() * depth::kFloatsPerNode);
        const std::size_t lights = first.visibility && l == 0 ? first.part.direct.lights.size() : 0;
        level.lightVisibility.resize(nodes.size() * lights);
        const std::size_t edgeFloats = first.edges ? lights * shadow_edge::kFloatsPerLight : 0;
        level.lightShadowEdges.resize(nodes.size() * edgeFloats);
        if (first.error && l == 0) error.resize(nodes.size());
        if (first.firstPass && l == 0) {
            firstValues.resize(nodes.size() * floats);
            firstError.resize(nodes.size());
        }
        for (std::size_t n = 0; n < nodes.size(); ++n) {
            const auto& [linear, t, at] = nodes[n];
            if (!dense) level.activeNodes.push_back(linear);
            const VolumeLevel& part = tiles[t].part.levels[l];
            const float* src = part.nodeData(at, channels);
            std::copy(src, src + floats, level.data.begin() + std::ptrdiff_t(n * floats));
            if (first.depth)
                std::copy(part.nodeDepth(at), part.nodeDepth(at) + depth::kFloatsPerNode,
                          level.depth.begin() + std::ptrdiff_t(n * depth::kFloatsPerNode));
            if (lights)
                std::copy(part.lightVisibility.begin() + std::ptrdiff_t(at * lights),
                          part.lightVisibility.begin() + std::ptrdiff_t((at + 1) * lights),
                          level.lightVisibility.begin() + std::ptrdiff_t(n * lights));
            if (edgeFloats)
                std::copy(part.lightShadowEdges.begin() + std::ptrdiff_t(at * edgeFloats),
                          part.lightShadowEdges.begin() + std::ptrdiff_t((at + 1) * edgeFloats),
                          level.lightShadowEdges.begin() + std::ptrdiff_t(n * edgeFloats));
            if (first.error && l == 0) error[n] = tiles[t].estimatedError.at(at);
            if (first.firstPass && l == 0) {
                firstError[n] = tiles[t].firstPassError.at(at);
                const auto from = tiles[t].firstPassValues.begin() + std::ptrdiff_t(at * floats);
                std::copy(from, from + std::ptrdiff_t(floats), firstValues.begin() + std::ptrdiff_t(n * floats));
            }
        }
        v.levels.push_back(std::move(level));
    }
    v.direct = first.part.direct;
    // --probe-cache surface, stage 0: every tile's bins hold its own nodes' samples; their
    // integer sums add exactly, in any order, to the whole bake's bins.
    if (first.part.surfaceBins) {
        auto sums = std::make_shared<SurfaceBinSums>(*first.part.surfaceBins);
        for (std::size_t t : order) {
            if (t == order[0]) continue;
            const SurfaceBinSums* b = tiles[t].part.surfaceBins.get();
            if (!b || b->unit != sums->unit)
                throw FormatError(quoted(paths[t]) + " and " + quoted(paths[order[0]]) + " differ in their surface bins");
            sums->add(*b);
        }
        v.surfaceBins = std::move(sums);
    }
    v.meta = mergedMetadata(tiles, order);
    // Pass 0 blended in (first_pass_blend.h) as the single bake does, before the error summary
    // and the node filter, which read the blend's errors: its pooled variances cross tile borders.
    if (first.firstPass) {
        if (v.levels.size() != 1 || v.levels[0].sparse())
            throw FormatError("the tiles carry pass-0 values for a blend, which needs one dense level");
        blendWithFirstPass(v.levels[0].grid, floats, firstValues, firstError, v.levels[0].data, error);
    }
    // Summaries of per-node statistics, by the code the bakes use (error_summary.h).
    if (first.error) addErrorSummary(v.meta, error, v.levels[0].grid);
    if (v.meta.count("samples_total") && v.meta.count("max_rays") && v.meta.count("rays_per_node_mean"))
        addSampleSummary(v.meta);
    if (v.levels.size() > 1) applySeamConstraints(v);  // seams cross tile borders
    // So does the node filter's kernel: a tile's bake leaves it to the merge, which runs it
    // on every node with the single bake's inputs (values, depth moments, per-node errors).
    if (const int64_t passes = int64_t(metaNumber(first.part.meta, "tile_node_filter_passes", 0)); passes > 0) {
        const bool byNoise = metaNumber(first.part.meta, "tile_node_filter_by_noise", 0) != 0;
        if (byNoise && !first.error) throw FormatError("the tiles ask for the node filter by noise but carry no per-node errors");
        filterNodes(v, int(passes), byNoise ? &error : nullptr);
    }
    try {
        v.validate();
    } catch (const FormatError& e) {
        throw FormatError(std::string("the merged tiles are inconsistent: ") + e.what());
    }
    out.write.halfFloat = first.halfFloat;
    out.write.reproducible = first.reproducible;
    return out;
}

}  // namespace vdblight
