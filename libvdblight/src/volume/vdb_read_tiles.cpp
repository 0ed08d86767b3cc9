// The tiles of a split bake (tiles.h, docs/scaling.md): gather tiles (each level's grids of the
// tile's nodes) and photon tiles (128-bit fixed-point sums, photon_sums.h).
#include "tile_io.h"
#include "vdb_read_parts.h"
#include "vdb_surface_bins.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/volume/tiles.h"
#include "basis/shadow_edges.h"

namespace vdblight {
namespace vdb_detail {

namespace {
/// A photon tile's depth moments (bake --depth-moments): level 0 gets the nodes they cover
/// (the active voxels of the four depth grids, the same in each; maybe none) and their values.
void readPhotonTileDepth(OpenedFile& f, VolumeLevel& level, const std::string& path) {
    for (int c = 0; c < depth::kChannels; ++c) {
        const std::string name = gridNameFor(depth::channelName(c), 0);
        if (!f.file->hasGrid(name)) formatError(path, "has depth moments without grid '" + name + "'");
        if (c > 0) continue;
        Vec3SGrid::Ptr grid = checkPlacedChannel(readGridChecked(f, name, path), level.grid, path);
        grid->tree().voxelizeActiveTiles();
        if (!insideBox(grid->evalActiveVoxelBoundingBox(), level.grid.nx, level.grid.ny, level.grid.nz))
            formatError(path, "grid '" + name + "' has active voxels outside its level's node box");
        level.activeNodes = activeLinear(*grid, level.grid);
    }
    if (!level.activeNodes.empty()) readDepth(f, level, 0, path);  // all four, active at the same nodes
}

/// The rest of a photon tile (writePhotonTile) after its identity: level 0's grid, the
/// metadata, the 128-bit sums from their Int64Grids (every node an active voxel) and the depth
/// moments of the tile's nodes, if any.
void readPhotonTile(OpenedFile& f, TileFile& t, const std::string& path) {
    const openvdb::MetaMap& meta = *f.meta;
    Volume& v = t.part;
    VolumeLevel level;
    level.grid = readLevelSpec(meta, 0, path);
    const GridSpec& g = level.grid;
    if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin))
        formatError(path, "has invalid dimensions, spacing or origin for level 0");
    v.levels.push_back(level);
    v.meta = userMetadata(meta);
    t.denseLevels = {1};
    auto sums = std::make_shared<PhotonSums>();
    sums->grid = g;
    sums->exponent = int(requireMeta<int64_t>(meta, kPrefix + "tile_photon_exponent", path));
    const int64_t first = requireMeta<int64_t>(meta, kPrefix + "tile_photon_first_batch", path);
    const int64_t end = requireMeta<int64_t>(meta, kPrefix + "tile_photon_end_batch", path);
    const int64_t batches = requireMeta<int64_t>(meta, kPrefix + "tile_photon_batches", path);
    if (first < 0 || end <= first || batches < end) formatError(path, "has an invalid run of photon batches");
    sums->firstBatch = uint64_t(first), sums->endBatch = uint64_t(end), sums->batches = uint64_t(batches);
    t.photonCompact = requireMeta<int64_t>(meta, kPrefix + "tile_photon_compact", path) != 0;
    const std::size_t count = g.nodeCount() * iv::kFloatsPerNode;
    std::vector<uint64_t> words[2] = {std::vector<uint64_t>(count), std::vector<uint64_t>(count)};  // hi, lo
    const PhotonSumLayout layout(g);
    for (int w = 0; w < 2 * iv::kFloatsPerNode; ++w) {
        const int value = w / 2, d = value / 9, component = value % 9;
        const bool high = w % 2 == 0;
        const std::string name = photonSumGridName(value, high);
        const openvdb::Int64Grid::Ptr grid = readPlacedInt64Grid(f, name, g, path);
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        if (grid->activeVoxelCount() != g.nodeCount() || box.min() != Coord(0, 0, 0) ||
            box.max() != Coord(g.nx - 1, g.ny - 1, g.nz - 1))
            formatError(path, "grid '" + name + "' does not have exactly one active voxel per node");
        std::vector<uint64_t>& out = words[high ? 0 : 1];
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const Coord c = it.getCoord();
            out[layout.offset(d, c.x(), c.y(), c.z()) + std::size_t(component)] = uint64_t(*it);
        }
    }
    // Two's complement words (writePhotonTile): value = hi * 2^64 + (unsigned) lo.
    sums->values.resize(count);
    for (std::size_t n = 0; n < count; ++n)
        sums->values[n] = PhotonFixed(((unsigned __int128)words[0][n] << 64) | words[1][n]);
    t.photon = std::move(sums);
    t.depth = metaNumber(v.meta, "tile_depth", 0) != 0;
    if (t.depth) readPhotonTileDepth(f, v.levels[0], path);
}
}  // namespace

TileFile readTileFile(const std::string& path) {
    OpenedFile f = openVolumeFile(path, OpenFor::Data);
    const openvdb::MetaMap& meta = *f.meta;
    if (!meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count"))
        formatError(path, "is not a tile (no vdblight:tile_count): a complete volume or another file");
    TileFile t;
    t.id.index = int(requireMeta<int64_t>(meta, kPrefix + "tile_index", path));
    t.id.count = int(requireMeta<int64_t>(meta, kPrefix + "tile_count", path));
    t.id.paramsHash = requireMeta<std::string>(meta, kPrefix + "tile_params_hash", path);
    t.halfFloat = requireMeta<int64_t>(meta, kPrefix + "tile_half_float", path) != 0;
    t.reproducible = requireMeta<int64_t>(meta, kPrefix + "tile_reproducible", path) != 0;
    Volume& v = t.part;
    v.basis.kind = requireMeta<std::string>(meta, kPrefix + "basis", path);
    v.basis.channelNames = splitNames(requireMeta<std::string>(meta, kPrefix + "channels", path));
    const int64_t levels = requireMeta<int64_t>(meta, kPrefix + "levels", path);
    if (levels < 1 || levels > 64) formatError(path, "has an invalid level count " + std::to_string(levels));
    if (meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_photon_sums")) {
        readPhotonTile(f, t, path);
        return t;
    }
    const std::vector<std::string> dense = splitNames(requireMeta<std::string>(meta, kPrefix + "tile_dense_levels", path));
    if (dense.size() != std::size_t(levels)) formatError(path, "has a tile_dense_levels entry per level missing");
    const int channels = v.basis.channelCount();
    for (int l = 0; l < int(levels); ++l) {
        t.denseLevels.push_back(dense[std::size_t(l)] == "1" ? 1 : 0);
        VolumeLevel out;
        out.grid = readLevelSpec(meta, l, path);
        const GridSpec& g = out.grid;
        if (g.nx <= 0 || g.ny <= 0 || g.nz <= 0 || !(g.spacing > 0) || !isFinite(g.origin))
            formatError(path, "has invalid dimensions, spacing or origin for level " + std::to_string(l));
        Vec3SGrid::Ptr first;
        for (int c = 0; c < channels; ++c) {
            const std::string name = gridNameFor(v.basis.channelNames[std::size_t(c)], l);
            if (!f.file->hasGrid(name)) formatError(path, "has no grid '" + name + "'");
            const openvdb::GridBase::Ptr base = readGridChecked(f, name, path);
            Vec3SGrid::Ptr grid = checkPlacedChannel(base, g, path);
            grid->tree().voxelizeActiveTiles();
            if (!insideBox(grid->evalActiveVoxelBoundingBox(), g.nx, g.ny, g.nz))
                formatError(path, "grid '" + name + "' has active voxels outside its level's node box");
            if (first && !grid->tree().hasSameTopology(first->tree()))
                formatError(path, "grid '" + name + "' has other active voxels than the first channel of its level");
            if (c == 0) {
                first = grid;
                out.activeNodes = activeLinear(*grid, g);
                out.data.assign(out.activeNodes.size() * std::size_t(channels) * 3, 0.0f);
            }
            copySparseChannel(*grid, out, c, channels);
        }
        v.levels.push_back(std::move(out));
    }
    if (levels > 1)
        for (int l = 0; l + 1 < int(levels); ++l) readMask(f, v.levels[std::size_t(l)], l, path);
    v.meta = userMetadata(meta);
    t.depth = metaNumber(v.meta, "tile_depth", 0) != 0;
    t.visibility = metaNumber(v.meta, "tile_visibility", 0) != 0;
    t.edges = metaNumber(v.meta, "tile_shadow_edges", 0) != 0;
    if (t.edges && !t.visibility) formatError(path, "has shadow edges without light visibility");
    t.error = metaNumber(v.meta, "tile_estimated_error", 0) != 0;
    if ((t.visibility || t.error) && levels != 1) formatError(path, "has per-node visibility or errors on several levels");
    // Depth moments, light visibility and errors of the tile's nodes (none on a level
    // without nodes in this tile).
    for (int l = 0; l < int(levels) && t.depth; ++l)
        if (!v.levels[std::size_t(l)].activeNodes.empty()) readDepth(f, v.levels[std::size_t(l)], l, path);
    readDirectLights(f, v, path);
    VolumeLevel& level0 = v.levels[0];
    if (t.visibility && !level0.activeNodes.empty()) {
        if (!v.direct.hasVisibility()) formatError(path, "has light visibility but no occlusion-mode lights");
        const std::size_t lights = v.direct.lights.size();
        level0.lightVisibility.assign(level0.activeNodes.size() * lights, 0.0f);
        for (std::size_t i = 0; i < lights; ++i) {
            const std::vector<float> values = readSparseScalar(f, visibilityGridName(i), level0, path);
            for (std::size_t n = 0; n < values.size(); ++n) level0.lightVisibility[n * lights + i] = values[n];
        }
        constexpr int parts = shadow_edge::kFloatsPerLight;
        if (t.edges) level0.lightShadowEdges.assign(level0.activeNodes.size() * lights * parts, 0.0f);
        for (std::size_t i = 0; i < lights && t.edges; ++i)
            for (int part = 0; part < parts; ++part) {
                const std::string name = shadow_edge::partGridName(part, i);
                const std::vector<float> values = readSparseScalar(f, name, level0, path);
                for (std::size_t n = 0; n < values.size(); ++n) level0.lightShadowEdges[(n * lights + i) * parts + part] = values[n];
            }
    }
    if (t.error && !level0.activeNodes.empty()) t.estimatedError = readSparseScalar(f, kTileErrorName, level0, path);
    const int64_t firstPassFloats = int64_t(metaNumber(v.meta, "tile_first_pass_floats", 0));
    if (firstPassFloats != 0 && (!t.error || firstPassFloats != int64_t(v.basis.channelCount()) * 3))
        formatError(path, "has pass-0 values that do not match its basis or carry no per-node errors");
    t.firstPass = firstPassFloats != 0;
    if (t.firstPass && !level0.activeNodes.empty()) {
        t.firstPassError = readSparseScalar(f, kTileFirstPassErrorName, level0, path);
        const std::size_t floats = std::size_t(firstPassFloats);
        t.firstPassValues.assign(level0.activeNodes.size() * floats, 0.0f);
        for (std::size_t c = 0; c < floats; ++c) {
            const std::vector<float> values = readSparseScalar(f, kTileFirstPassPrefix + std::to_string(c), level0, path);
            for (std::size_t n = 0; n < values.size(); ++n) t.firstPassValues[n * floats + c] = values[n];
        }
    }
    readSurfaceBins(f, v, path);  // a stage-0 tile of --probe-cache surface: its bins' sums
    return t;
}

}  // namespace vdb_detail

bool readTileId(const std::string& path, TileId& id) {
    using namespace vdb_detail;
    OpenedFile f = openVolumeFile(path, OpenFor::Metadata);
    const openvdb::MetaMap& meta = *f.meta;
    if (!meta.getMetadata<openvdb::Int64Metadata>(kPrefix + "tile_count")) return false;
    id.index = int(requireMeta<int64_t>(meta, kPrefix + "tile_index", path));
    id.count = int(requireMeta<int64_t>(meta, kPrefix + "tile_count", path));
    id.paramsHash = requireMeta<std::string>(meta, kPrefix + "tile_params_hash", path);
    return true;
}

}  // namespace vdblight
