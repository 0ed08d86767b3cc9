// exportNanoVdb (export_nanovdb.h): the volume's grids built with NanoVDB's GridBuilder (no
// OpenVDB grids in between: the Volume's plain arrays go straight into NanoVDB trees) and
// written with io::writeGrids through an AtomicFile.
#include "vdblight/export/engines.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include <nanovdb/NanoVDB.h>
#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include "basis/shadow_edges.h"
#include "core/grid_index.h"
#include "export_internal.h"
#include "vdblight/core/atomic_file.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/core/errors.h"

namespace vdblight {

namespace {
using Handle = nanovdb::GridHandle<nanovdb::HostBuffer>;

/// The `.vdb`'s grid name of a level's grid (docs/format.md: `_L<k>` on levels k > 0).
std::string levelName(const std::string& base, std::size_t level) {
    return level == 0 ? base : base + "_L" + std::to_string(level);
}

/// (i, j, k) of stored position n of a level.
nanovdb::Coord nodeCoord(const VolumeLevel& level, std::size_t n) {
    const uint64_t linear = level.sparse() ? level.activeNodes[n] : uint64_t(n);
    const core::Index3 c = core::unflatten(linear, uint64_t(level.grid.nx), uint64_t(level.grid.ny));
    return nanovdb::Coord(c.i, c.j, c.k);
}

/// A grid on the level's nodes (index (i, j, k) at origin + spacing (i, j, k), the `.vdb`'s
/// transform), one value per stored node from `value(n)`.
template <class Value, class F>
Handle levelGrid(const VolumeLevel& level, const std::string& name, F&& value) {
    nanovdb::GridBuilder<Value> builder(Value(0));
    auto acc = builder.getAccessor();
    for (std::size_t n = 0; n < level.storedNodes(); ++n) acc.setValue(nodeCoord(level, n), value(n));
    const Vec3d& o = level.grid.origin;
    return builder.getHandle(level.grid.spacing, nanovdb::Vec3d(o.x, o.y, o.z), name);
}

/// The refined-cell mask of a level: voxel (i, j, k) active (value 1) for the refined cell with
/// lower corner (i, j, k); transform shifted by half a spacing (cell centres), as the `.vdb`'s.
/// A float grid: NanoVDB 32.4's GridBuilder builds no Mask grids ("does not yet support bool leafs").
Handle refinedGrid(const VolumeLevel& level, std::size_t l) {
    nanovdb::GridBuilder<float> builder(0.0f);
    auto acc = builder.getAccessor();
    for (uint64_t cell : level.refinedCells) {
        const core::Index3 c = core::unflatten(cell, uint64_t(level.grid.nx), uint64_t(level.grid.ny));
        acc.setValue(nanovdb::Coord(c.i, c.j, c.k), 1.0f);
    }
    const Vec3d o = level.grid.origin + Vec3d(0.5, 0.5, 0.5) * level.grid.spacing;
    return builder.getHandle(level.grid.spacing, nanovdb::Vec3d(o.x, o.y, o.z), "refined_L" + std::to_string(l));
}

/// `bytes` rounded up to NanoVDB's 32-byte alignment: a grid's size (which ends with its blind
/// data) stays a multiple of 32, so the next grid of a buffer holding them back to back starts
/// aligned (PNanoVDB reads 64-bit values at 8-byte offsets).
uint64_t alignedBlindSize(uint64_t bytes) {
    return (bytes + NANOVDB_DATA_ALIGNMENT - 1) / NANOVDB_DATA_ALIGNMENT * NANOVDB_DATA_ALIGNMENT;
}

/// Fills the one blind-data block of `grid` (built with room for `padded` bytes): its name,
/// `count` elements of `type`, and the bytes themselves, zero-padded.
template <class Value>
void setBlindData(nanovdb::NanoGrid<Value>* grid, const char* name, nanovdb::GridType type, uint64_t count,
                  const void* data, uint64_t bytes, uint64_t padded) {
    auto* blind = reinterpret_cast<nanovdb::GridBlindMetaData*>(reinterpret_cast<char*>(grid) + grid->data()->mBlindMetadataOffset);
    blind->mElementCount = count;
    blind->mFlags = 0;
    blind->mSemantic = nanovdb::GridBlindDataSemantic::Unknown;
    blind->mDataClass = nanovdb::GridBlindDataClass::Unknown;
    blind->mDataType = type;
    std::memset(blind->mName, 0, sizeof(blind->mName));
    std::strncpy(blind->mName, name, sizeof(blind->mName) - 1);
    char* out = reinterpret_cast<char*>(blind) + blind->mByteOffset;  // relative to the block's record
    std::memset(out, 0, padded);
    std::memcpy(out, data, bytes);
}

/// What the file holds of the shadow edges (nanovdb_meta::kShadowEdges): 0 none, 1 each node's
/// nearest edge, 2 also the strips' second edge (some node of the volume has one).
int shadowEdgeKind(const Volume& v) {
    if (!v.direct.hasVisibility() || v.levels[0].lightShadowEdges.empty()) return 0;
    return exporter::hasShadowStrips(v) ? 2 : 1;
}

/// The names of level 0's per-light arrays, in file order (the `.vdb`'s grid names and, for the
/// strips, the texture export's: docs/shadow_visibility.md).
std::vector<std::string> lightArrayNames(const Volume& v) {
    std::vector<std::string> names;
    if (!v.direct.hasVisibility()) return names;
    const std::size_t m = v.direct.lights.size();
    const int edges = shadowEdgeKind(v);
    for (std::size_t i = 0; i < m; ++i) names.push_back("light_visibility_" + std::to_string(i));
    for (std::size_t i = 0; edges > 0 && i < m; ++i) {
        names.push_back(shadow_edge::distanceGridName(i));
        names.push_back(shadow_edge::widthGridName(i));
    }
    for (std::size_t i = 0; edges > 1 && i < m; ++i) names.push_back("light_edge_strip_" + std::to_string(i));
    return names;
}

/// The SH order of sh2 and of sh:1 .. sh:9, -1 for other bases.
int shOrder(const BasisDesc& basis) {
    const int order = basis.shOrder();
    return order >= 1 && order <= 9 ? order : -1;
}

/// The metadata as text, one `key=value` per line: what the numbers of the meta grid say,
/// the lights in their one-line form, then every `vdblight:` item of the volume.
std::string metadataText(const Volume& v) {
    std::ostringstream s;
    s.precision(17);
    s << "format=vdblight-nanovdb " << nanovdb_meta::kVersionValue << "\nbasis=" << v.basis.kind << "\nchannels=";
    for (int c = 0; c < v.basis.channelCount(); ++c) s << (c ? "," : "") << v.basis.channelNames[std::size_t(c)];
    s << "\nlevels=" << v.levels.size() << "\nrefine=" << v.refineFactor() << "\ndepth_moments=" << (v.hasDepth() ? 1 : 0)
      << "\ndirect=" << directModeName(v.direct.mode) << "\ndirect_lights=" << v.direct.lights.size()
      << "\nshadow_edges=" << shadowEdgeKind(v) << "\nlight_arrays=";
    const std::vector<std::string> arrays = lightArrayNames(v);
    for (std::size_t i = 0; i < arrays.size(); ++i) s << (i ? "," : "") << arrays[i];
    s << "\n";
    for (std::size_t i = 0; i < v.direct.lights.size(); ++i)
        s << "direct_light_" << i << "=" << formatDirectLight(v.direct.lights[i]) << "\n";
    for (const auto& [key, value] : v.meta) {
        s << "vdblight:" << key << "=";
        std::visit([&](const auto& x) { s << x; }, value);
        s << "\n";
    }
    return s.str();
}

/// The lights' records and loops (nanovdb_meta::kLightFloats), appended to `out` (which holds
/// the kFieldCount numbers already).
void appendLights(const std::vector<DirectLight>& lights, std::vector<float>& out) {
    const std::size_t recordsAt = out.size();
    out.resize(recordsAt + lights.size() * nanovdb_meta::kLightFloats, 0.0f);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const DirectLight& l = lights[i];
        float* r = out.data() + recordsAt + i * nanovdb_meta::kLightFloats;
        const float values[18] = {float(int(l.kind)), l.twoSided ? 1.0f : 0.0f, l.value.x, l.value.y, l.value.z,
                                  float(l.position.x), float(l.position.y), float(l.position.z),
                                  float(l.direction.x), float(l.direction.y), float(l.direction.z),
                                  float(std::cos(l.innerCone)), float(std::cos(l.outerCone)),
                                  float(l.normal.x), float(l.normal.y), float(l.normal.z),
                                  float(out.size()), float(l.loops.size())};
        std::copy(values, values + 18, r);
        for (const auto& loop : l.loops) {  // r is not used below: out may move
            out.push_back(float(loop.size()));
            for (const Vec3d& p : loop) out.insert(out.end(), {float(p.x), float(p.y), float(p.z)});
        }
    }
}

/// The leading `bits` significant bits of v (round to nearest), 0 for 0.
double leadingBits(double v, int bits) {
    if (v == 0) return 0;
    int exponent;
    std::frexp(v, &exponent);  // v = m 2^exponent, 0.5 <= |m| < 1
    return std::ldexp(std::round(std::ldexp(v, bits - exponent)), exponent - bits);
}

/// Level 0's exact frame (nanovdb_meta::kFrame), appended to `out`: what lets a float lookup
/// measure a point's offset from a node as (x - origin) - i * spacing to within float rounding
/// of the offset itself, not of x's index coordinate (shaders/vdblight_nanovdb_lights.h).
void appendFrame(const GridSpec& grid, std::vector<float>& out) {
    const double s1 = leadingBits(grid.spacing, 12), s2 = leadingBits(grid.spacing - s1, 12);
    for (int a = 0; a < 3; ++a) out.push_back(float(grid.origin[a]));
    for (int a = 0; a < 3; ++a) out.push_back(float(grid.origin[a] - double(float(grid.origin[a]))));
    out.insert(out.end(), {float(s1), float(s2), float(grid.spacing - s1 - s2), float(1.0 / grid.spacing)});
}

/// The grid `vdblight_meta`: the numbers of nanovdb_meta in voxels (i, 0, 0), identity
/// transform, and `text` (NUL-terminated) as its one blind data block.
Handle metaGrid(const Volume& v, const std::string& text) {
    std::vector<float> field(nanovdb_meta::kFieldCount, 0.0f);
    field[nanovdb_meta::kVersion] = float(nanovdb_meta::kVersionValue);
    field[nanovdb_meta::kShOrder] = float(shOrder(v.basis));
    field[nanovdb_meta::kChannels] = float(v.basis.channelCount());
    field[nanovdb_meta::kLevels] = float(v.levels.size());
    field[nanovdb_meta::kRefine] = float(v.refineFactor());
    field[nanovdb_meta::kDepth] = v.hasDepth() ? 1.0f : 0.0f;
    field[nanovdb_meta::kDirectMode] = float(int(v.direct.mode));
    field[nanovdb_meta::kLights] = float(v.direct.lights.size());
    field[nanovdb_meta::kVisibility] = v.direct.hasVisibility() ? float(v.direct.lights.size()) : 0.0f;
    field[nanovdb_meta::kValidity] = v.levels[0].validity.empty() ? 0.0f : 1.0f;
    field[nanovdb_meta::kDimsX] = float(v.levels[0].grid.nx);
    field[nanovdb_meta::kDimsY] = float(v.levels[0].grid.ny);
    field[nanovdb_meta::kDimsZ] = float(v.levels[0].grid.nz);
    field[nanovdb_meta::kShKind] = v.basis.isSh2() ? 1.0f : 0.0f;
    field[nanovdb_meta::kShadowEdges] = float(shadowEdgeKind(v));
    appendLights(v.direct.lights, field);
    field[nanovdb_meta::kFrame] = float(field.size());
    appendFrame(v.levels[0].grid, field);

    const uint64_t padded = alignedBlindSize(text.size() + 1);
    nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::Unknown, padded);
    auto acc = builder.getAccessor();
    for (std::size_t i = 0; i < field.size(); ++i) acc.setValue(nanovdb::Coord(int(i), 0, 0), field[i]);
    Handle handle = builder.getHandle(1.0, nanovdb::Vec3d(0.0), "vdblight_meta");
    setBlindData(handle.grid<float>(), "vdblight_metadata", nanovdb::GridType::Unknown, text.size() + 1, text.c_str(),
                 text.size() + 1, padded);
    return handle;
}

/// Level 0's shadow-edge arrays of an occlusion volume (levelChannels), appended to `out`.
void appendShadowEdges(const Volume& v, std::vector<float>& out) {
    const int kind = shadowEdgeKind(v);
    if (kind == 0) return;
    const VolumeLevel& level = v.levels[0];
    const std::size_t n = level.storedNodes(), m = v.direct.lights.size();
    const auto edge = [&](std::size_t node, std::size_t light) {
        return level.lightShadowEdges.data() + (level.held(node) * m + light) * shadow_edge::kFloatsPerLight;
    };
    for (std::size_t light = 0; light < m; ++light)
        for (int part : {shadow_edge::kDistance, shadow_edge::kWidth})
            for (std::size_t i = 0; i < n; ++i) out.push_back(edge(i, light)[part]);
    if (kind < 2) return;
    for (std::size_t light = 0; light < m; ++light)
        for (std::size_t i = 0; i < n; ++i) {
            const float* e = edge(i, light);
            out.insert(out.end(), {e[shadow_edge::kDirectionX], e[shadow_edge::kDirectionY], e[shadow_edge::kDirectionZ],
                                   e[shadow_edge::kFar]});
        }
}

/// The channel arrays of a level, channel-major so that a shader steps from one channel to the
/// next by one stride (N nodes x 12 bytes): the basis channels and then the four depth
/// channels, N RGB / xyz triples each, in stored node order; then (level 0 of an occlusion
/// volume) N visibility values per listed light, and with shadow edges (shadow_edges.h) per
/// light N distances and N widths, then, where some node has a strip, per light N (direction
/// x, y, z, far) quadruples: lightArrayNames' order.
std::vector<float> levelChannels(const Volume& v, std::size_t l) {
    const VolumeLevel& level = v.levels[l];
    const std::size_t n = level.storedNodes();
    const int channels = v.basis.channelCount();
    std::vector<float> out;
    out.reserve(n * 3 * std::size_t(channels + (level.hasDepth() ? depth::kChannels : 0)));
    for (int c = 0; c < channels; ++c)
        for (std::size_t i = 0; i < n; ++i) {
            const float* p = level.nodeData(i, channels) + 3 * c;
            out.insert(out.end(), p, p + 3);
        }
    if (level.hasDepth())
        for (int c = 0; c < depth::kChannels; ++c)
            for (std::size_t i = 0; i < n; ++i) {
                const float* p = level.nodeDepth(i) + 3 * c;
                out.insert(out.end(), p, p + 3);
            }
    if (l == 0 && v.direct.hasVisibility()) {
        const std::size_t m = v.direct.lights.size();
        for (std::size_t light = 0; light < m; ++light)
            for (std::size_t i = 0; i < n; ++i) out.push_back(level.lightVisibility[level.held(i) * m + light]);
        appendShadowEdges(v, out);
    }
    return out;
}

/// The grid `vdblight_nodes` of a level: a UInt32 grid on the level's nodes (the `.vdb`'s
/// transform and active voxels) whose value is the node's index in the channel arrays, which
/// ride in its blind data (`vdblight_channels`, levelChannels): one tree for every channel.
Handle nodesGrid(const Volume& v, std::size_t l) {
    const VolumeLevel& level = v.levels[l];
    const std::vector<float> channels = levelChannels(v, l);
    const uint64_t bytes = channels.size() * sizeof(float), padded = alignedBlindSize(bytes);
    nanovdb::GridBuilder<uint32_t> builder(0u, nanovdb::GridClass::Unknown, padded);
    auto acc = builder.getAccessor();
    for (std::size_t n = 0; n < level.storedNodes(); ++n) acc.setValue(nodeCoord(level, n), uint32_t(n));
    const Vec3d& o = level.grid.origin;
    Handle handle = builder.getHandle(level.grid.spacing, nanovdb::Vec3d(o.x, o.y, o.z), levelName("vdblight_nodes", l));
    setBlindData(handle.grid<uint32_t>(), "vdblight_channels", nanovdb::GridType::Float, channels.size(), channels.data(),
                 bytes, padded);
    return handle;
}

/// The grids of one level in the documented order: the nodes grid with the channels, the
/// refined mask, the validity.
void appendLevel(const Volume& v, std::size_t l, std::vector<Handle>& out) {
    const VolumeLevel& level = v.levels[l];
    if (level.storedNodes() > uint64_t(UINT32_MAX)) throw FormatError("NanoVDB export: more than 2^32 nodes in one level");
    out.push_back(nodesGrid(v, l));
    if (l + 1 < v.levels.size()) out.push_back(refinedGrid(level, l));
    if (!level.validity.empty())
        out.push_back(levelGrid<float>(level, levelName("validity", l), [&](std::size_t n) { return level.validity[level.held(n)]; }));
}
}  // namespace

NanoVdbSummary exportNanoVdb(const Volume& volume, const std::string& file) {
    uint64_t nodes = 0;
    for (const VolumeLevel& level : volume.levels) nodes += level.storedNodes();
    if (nodes == 0) throw ValueError("cannot export an empty volume to NanoVDB: it has no nodes");
    volume.validate();
    for (const VolumeLevel& level : volume.levels)
        if (level.windowNodes != 0) throw FormatError("cannot export a tile's bake to NanoVDB: merge the tiles first");

    std::vector<Handle> handles;
    handles.push_back(metaGrid(volume, metadataText(volume)));
    for (std::size_t l = 0; l < volume.levels.size(); ++l) appendLevel(volume, l, handles);

    NanoVdbSummary summary;
    summary.activeNodes = nodes;
    for (const Handle& h : handles) summary.grids.push_back(h.gridMetaData()->shortGridName());
    writeFileAtomically(file, [&](const std::string& temp) {
        nanovdb::io::writeGrids<nanovdb::HostBuffer, std::vector>(temp, handles);
    });
    summary.bytes = uint64_t(std::filesystem::file_size(file));
    return summary;
}

}  // namespace vdblight
