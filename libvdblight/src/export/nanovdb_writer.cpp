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

#include "core/grid_index.h"
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
      << "\ndirect=" << directModeName(v.direct.mode) << "\ndirect_lights=" << v.direct.lights.size() << "\n";
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
    appendLights(v.direct.lights, field);

    // The block padded with zeros to NanoVDB's 32-byte alignment: the grid's size (which ends
    // with it) stays a multiple of 32, so the next grid of a buffer holding them back to back
    // starts aligned (PNanoVDB reads 64-bit values at 8-byte offsets).
    const uint64_t padded = (text.size() + 1 + NANOVDB_DATA_ALIGNMENT - 1) / NANOVDB_DATA_ALIGNMENT * NANOVDB_DATA_ALIGNMENT;
    nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::Unknown, padded);
    auto acc = builder.getAccessor();
    for (std::size_t i = 0; i < field.size(); ++i) acc.setValue(nanovdb::Coord(int(i), 0, 0), field[i]);
    Handle handle = builder.getHandle(1.0, nanovdb::Vec3d(0.0), "vdblight_meta");
    nanovdb::NanoGrid<float>* grid = handle.grid<float>();
    auto* blind = reinterpret_cast<nanovdb::GridBlindMetaData*>(reinterpret_cast<char*>(grid) +
                                                                  grid->data()->mBlindMetadataOffset);
    blind->mElementCount = text.size() + 1;
    blind->mFlags = 0;
    blind->mSemantic = nanovdb::GridBlindDataSemantic::Unknown;
    blind->mDataClass = nanovdb::GridBlindDataClass::Unknown;
    blind->mDataType = nanovdb::GridType::Unknown;
    std::memset(blind->mName, 0, sizeof(blind->mName));
    std::strncpy(blind->mName, "vdblight_metadata", sizeof(blind->mName) - 1);
    char* bytes = reinterpret_cast<char*>(blind) + blind->mByteOffset;
    std::memset(bytes, 0, padded);
    std::memcpy(bytes, text.c_str(), text.size() + 1);
    return handle;
}

/// The lookup (shaders/vdblight_nanovdb.h) steps over a run of grids of one type on one
/// topology by a single stride: their sizes must agree (they do: same tree, same value type).
void sameSizes(const std::vector<Handle>& handles, std::size_t begin, std::size_t end) {
    for (std::size_t g = begin + 1; g < end; ++g)
        if (handles[g].size() != handles[begin].size())
            throw FormatError("NanoVDB export: grid '" + std::string(handles[g].gridMetaData()->shortGridName()) +
                              "' differs in size from the other grids of its level");
}

/// The grids of one level in the documented order: channels, depth, refined mask, validity,
/// then (level 0 of an occlusion volume) the light visibility.
void appendLevel(const Volume& v, std::size_t l, std::vector<Handle>& out) {
    const VolumeLevel& level = v.levels[l];
    const std::size_t first = out.size();
    const int channels = v.basis.channelCount();
    for (int c = 0; c < channels; ++c)
        out.push_back(levelGrid<nanovdb::Vec3f>(level, levelName(v.basis.channelNames[std::size_t(c)], l), [&](std::size_t n) {
            const float* p = level.nodeData(n, channels) + 3 * c;
            return nanovdb::Vec3f(p[0], p[1], p[2]);
        }));
    if (level.hasDepth())
        for (int c = 0; c < depth::kChannels; ++c)
            out.push_back(levelGrid<nanovdb::Vec3f>(level, levelName(depth::channelName(c), l), [&](std::size_t n) {
                const float* p = level.nodeDepth(n) + 3 * c;
                return nanovdb::Vec3f(p[0], p[1], p[2]);
            }));
    sameSizes(out, first, out.size());  // channels and depth: one stride for the shader's walk
    if (l + 1 < v.levels.size()) out.push_back(refinedGrid(level, l));
    if (!level.validity.empty())
        out.push_back(levelGrid<float>(level, levelName("validity", l), [&](std::size_t n) { return level.validity[level.held(n)]; }));
    if (l == 0 && v.direct.hasVisibility()) {
        const std::size_t m = v.direct.lights.size();
        const std::size_t firstVisibility = out.size();
        for (std::size_t i = 0; i < m; ++i)
            out.push_back(levelGrid<float>(level, "light_visibility_" + std::to_string(i),
                                           [&](std::size_t n) { return level.lightVisibility[level.held(n) * m + i]; }));
        sameSizes(out, firstVisibility, out.size());
    }
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
