// PRT files (docs/format.md, "PRT files"): samples as a PointDataGrid, bases and transfer
// matrices as sparse float grids whose voxel (a, b, c) is a matrix entry.
#include "vdblight/prt_io.h"

#include <cmath>
#include <filesystem>
#include <mutex>

#include <openvdb/openvdb.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointCount.h>
#include <openvdb/points/PointDataGrid.h>
#include <openvdb/tools/PointIndexGrid.h>

#include "vdblight/atomic_file.h"
#include "vdblight/errors.h"

namespace vdblight {
namespace {

namespace fs = std::filesystem;
namespace vp = openvdb::points;
using openvdb::Coord;

const std::string kP = "vdblight:";
/// 1: one bounce, no version key but prt_format_version; 2: `format_version` and `bounces`.
constexpr int64_t kPrtFormatVersion = 2;
constexpr float kHalfMax = 65504.0f;

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

struct Counter {
    uint64_t values = 0, dropped = 0;
};

/// Stores row-major matrix rows (k, j) of a basis under cluster c: voxel (c, k, j).
void putBasis(openvdb::FloatGrid& grid, const PcaBasis& b, int c, float thr, Counter& n) {
    auto acc = grid.getAccessor();
    for (int j = 0; j < b.dim; ++j) acc.setValue(Coord(c, -1, j), b.mean[std::size_t(j)]);  // row -1: the mean
    n.values += std::size_t(b.dim);
    for (int k = 0; k < b.count; ++k) {
        const float* row = b.vectors.data() + std::size_t(k) * std::size_t(b.dim);
        float mx = 0;
        for (int j = 0; j < b.dim; ++j) mx = std::max(mx, std::abs(row[j]));
        for (int j = 0; j < b.dim; ++j) {
            ++n.values;
            if (row[j] == 0.0f || std::abs(row[j]) <= thr * mx) {
                if (row[j] != 0.0f) ++n.dropped;
                continue;
            }
            acc.setValue(Coord(c, k, j), row[j]);
        }
    }
}

template <typename GridT>
void finishGrid(GridT& grid, const std::string& name, bool quantize) {
    grid.setName(name);
    grid.setGridClass(openvdb::GRID_UNKNOWN);
    bool fits = true;
    for (auto it = grid.cbeginValueOn(); it && fits; ++it) {
        const auto v = *it;
        if constexpr (std::is_same_v<typename GridT::ValueType, float>) fits = std::abs(v) < kHalfMax;
        else fits = std::abs(v[0]) < kHalfMax && std::abs(v[1]) < kHalfMax && std::abs(v[2]) < kHalfMax;
    }
    grid.setSaveFloatAsHalf(quantize && fits);
}

vp::PointDataGrid::Ptr buildPoints(const PrtData& prt, bool quantize) {
    const SurfaceSamples& s = prt.samples;
    std::vector<openvdb::Vec3f> pos(s.size()), nrm(s.size()), alb(s.size());
    std::vector<int32_t> id(s.size()), cl(s.size());
    const std::vector<float>& area = s.area;
    for (std::size_t i = 0; i < s.size(); ++i) {
        pos[i] = {s.position[i].x, s.position[i].y, s.position[i].z};
        nrm[i] = {s.normal[i].x, s.normal[i].y, s.normal[i].z};
        alb[i] = {s.albedo[i].x, s.albedo[i].y, s.albedo[i].z};
        id[i] = int32_t(i);
        cl[i] = int32_t(s.cluster[i]);
    }
    const vp::PointAttributeVector<openvdb::Vec3f> posW(pos);
    const float voxel = std::max(1e-4f, vp::computeVoxelSize(posW, 8));
    const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
    auto index = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(posW, *xform);
    auto grid = vp::createPointDataGrid<vp::NullCodec, vp::PointDataGrid>(*index, posW, *xform);
    // Index space holds the local positions; the transform places them in the world (for
    // Houdini / Blender), the reader subtracts the origin again.
    if (prt.origin != Vec3d(0, 0, 0)) grid->transform().postTranslate(openvdb::Vec3d(prt.origin.x, prt.origin.y, prt.origin.z));
    auto& tree = grid->tree();
    using PIT = openvdb::tools::PointIndexTree;
    vp::appendAttribute<openvdb::Vec3f>(tree, "N");
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<openvdb::Vec3f>>(
        tree, index->tree(), "N", vp::PointAttributeVector<openvdb::Vec3f>(nrm));
    vp::appendAttribute<openvdb::Vec3f>(tree, "Cd");
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<openvdb::Vec3f>>(
        tree, index->tree(), "Cd", vp::PointAttributeVector<openvdb::Vec3f>(alb));
    vp::appendAttribute<float>(tree, "area");
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<float>>(
        tree, index->tree(), "area", vp::PointAttributeVector<float>(area));
    vp::appendAttribute<int32_t>(tree, "id");
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<int32_t>>(
        tree, index->tree(), "id", vp::PointAttributeVector<int32_t>(id));
    vp::appendAttribute<int32_t>(tree, "cluster");
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<int32_t>>(
        tree, index->tree(), "cluster", vp::PointAttributeVector<int32_t>(cl));
    const openvdb::Index stride = openvdb::Index(prt.visCoeffStride);
    if (quantize) {
        vp::appendAttribute(tree, "vis", vp::TypedAttributeArray<float, vp::TruncateCodec>::attributeType(), stride);
    } else {
        vp::appendAttribute(tree, "vis", vp::TypedAttributeArray<float>::attributeType(), stride);
    }
    vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<float>>(
        tree, index->tree(), "vis", vp::PointAttributeVector<float>(prt.visCoeffs, stride), stride);
    grid->setName("prt_samples");
    return grid;
}

template <typename T>
T meta(const openvdb::MetaMap& m, const std::string& key, const std::string& path) {
    auto v = m.getMetadata<openvdb::TypedMetadata<T>>(kP + key);
    if (!v) throw FormatError("'" + path + "' is not a valid PRT file: no metadata " + kP + key);
    return v->value();
}

}  // namespace

void writePrt(const PrtData& prt, const std::string& path, const PrtWriteOptions& options) {
    initOpenVdb();
    const SurfaceSamples& s = prt.samples;
    if (s.size() == 0) throw ValueError("PRT data has no samples");
    const fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
        throw IoError("cannot write '" + path + "': directory '" + parent.string() + "' does not exist");
    }
    for (float v : prt.visCoeffs)
        if (!std::isfinite(v)) throw ValueError("PRT data has non-finite visibility coefficients");

    Counter n;
    n.values = prt.visCoeffs.size();
    const float thr = options.sparseThreshold;
    auto visBasis = openvdb::FloatGrid::create(0.0f);
    auto lightBasis = openvdb::FloatGrid::create(0.0f);
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        putBasis(*visBasis, prt.visBasis[c], int(c), thr, n);
        putBasis(*lightBasis, prt.lightBasis[c], int(c), thr, n);
    }
    auto transfer = openvdb::Vec3SGrid::create(openvdb::Vec3f(0.0f));
    {
        auto acc = transfer->getAccessor();
        const std::size_t ns = s.size();
        for (std::size_t c = 0; c < s.clusters(); ++c)
            for (int k = 0; k < prt.transferStride; ++k) {
                const Rgb* row = prt.transfer[c].data() + std::size_t(k) * ns;
                float mx = 0;
                for (std::size_t r = 0; r < ns; ++r) mx = std::max(mx, maxComponent(Rgb{std::abs(row[r].x), std::abs(row[r].y), std::abs(row[r].z)}));
                for (std::size_t r = 0; r < ns; ++r) {
                    n.values += 3;
                    const float a = std::max(std::abs(row[r].x), std::max(std::abs(row[r].y), std::abs(row[r].z)));
                    if (a == 0.0f || a <= thr * mx) {
                        if (a != 0.0f) n.dropped += 3;
                        continue;
                    }
                    if (!isFinite(row[r])) throw ValueError("PRT data has non-finite transfer values");
                    acc.setValue(Coord(int(c), k, int(r)), openvdb::Vec3f(row[r].x, row[r].y, row[r].z));
                }
            }
    }
    openvdb::Vec3SGrid::Ptr volumeTransfer;
    if (prt.hasVolume()) {
        volumeTransfer = openvdb::Vec3SGrid::create(openvdb::Vec3f(0.0f));
        auto acc = volumeTransfer->getAccessor();
        const std::size_t count = prt.volumeGrid.nodeCount() * 9;
        for (std::size_t c = 0; c < s.clusters(); ++c)
            for (int k = 0; k < prt.transferStride; ++k)
                for (std::size_t i = 0; i < count; ++i) {
                    const Rgb& v = prt.volumeTransfer[c][std::size_t(k) * count + i];
                    n.values += 3;
                    if (v.x == 0.0f && v.y == 0.0f && v.z == 0.0f) continue;
                    if (!isFinite(v)) throw ValueError("PRT data has non-finite volume transfer values");
                    acc.setValue(Coord(int(c), k, int(i)), openvdb::Vec3f(v.x, v.y, v.z));
                }
        finishGrid(*volumeTransfer, "prt_volume_transfer", options.quantize);
        volumeTransfer->setVectorType(openvdb::VEC_INVARIANT);
    }
    finishGrid(*visBasis, "prt_vis_basis", options.quantize);
    finishGrid(*lightBasis, "prt_light_basis", options.quantize);
    finishGrid(*transfer, "prt_transfer", options.quantize);
    transfer->setVectorType(openvdb::VEC_INVARIANT);
    auto points = buildPoints(prt, options.quantize);

    openvdb::MetaMap m;
    m.insertMeta(kP + "kind", openvdb::StringMetadata("prt"));
    m.insertMeta(kP + "format_version", openvdb::Int64Metadata(kPrtFormatVersion));
    m.insertMeta(kP + "prt_format_version", openvdb::Int64Metadata(kPrtFormatVersion));
    m.insertMeta(kP + "bounces", openvdb::Int64Metadata(prt.bounces));
    m.insertMeta(kP + "form_factors", openvdb::StringMetadata(prt.closureNormalise ? "closure_normalised" : "disk"));
    m.insertMeta(kP + "form_factor_rays", openvdb::Int64Metadata(int64_t(prt.formFactorRays)));
    m.insertMeta(kP + "method", openvdb::StringMetadata("Leonhardt & Bohn PRT, diffuse bounces sample to sample"));
    m.insertMeta(kP + "scene", openvdb::StringMetadata(prt.sceneName));
    m.insertMeta(kP + "scene_hash", openvdb::StringMetadata(prt.sceneHash));
    m.insertMeta(kP + "seed", openvdb::Int64Metadata(int64_t(prt.seed)));
    m.insertMeta(kP + "samples", openvdb::Int64Metadata(int64_t(s.size())));
    m.insertMeta(kP + "clusters", openvdb::Int64Metadata(int64_t(s.clusters())));
    m.insertMeta(kP + "sample_radius", openvdb::DoubleMetadata(s.radius));
    m.insertMeta(kP + "area_per_sample", openvdb::DoubleMetadata(s.areaPerSample));
    m.insertMeta(kP + "vis_grid", openvdb::Int64Metadata(prt.visGrid));
    m.insertMeta(kP + "vis_coeffs", openvdb::Int64Metadata(prt.visCoeffStride));
    m.insertMeta(kP + "depth_cap", openvdb::FloatMetadata(prt.depthCap));
    m.insertMeta(kP + "train_lights", openvdb::Int64Metadata(prt.trainLights));
    m.insertMeta(kP + "transfer_coeffs", openvdb::Int64Metadata(prt.transferStride - 1));
    m.insertMeta(kP + "light_basis", openvdb::StringMetadata(prt.paperBasis ? "centred" : "normalised_uncentred"));
    m.insertMeta(kP + "oriented_training", openvdb::FloatMetadata(prt.orientedTraining));
    m.insertMeta(kP + "oriented_coeffs", openvdb::Int64Metadata(prt.orientedCoeffs));
    m.insertMeta(kP + "scene_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(prt.origin.x, prt.origin.y, prt.origin.z)));
    m.insertMeta(kP + "quantized", openvdb::BoolMetadata(options.quantize));
    m.insertMeta(kP + "sparse_threshold", openvdb::FloatMetadata(thr));
    m.insertMeta(kP + "values", openvdb::Int64Metadata(int64_t(n.values)));
    m.insertMeta(kP + "dropped_values", openvdb::Int64Metadata(int64_t(n.dropped)));
    m.insertMeta(kP + "bounds_lo", openvdb::Vec3DMetadata(openvdb::Vec3d(prt.bounds.lo.x, prt.bounds.lo.y, prt.bounds.lo.z)));
    m.insertMeta(kP + "bounds_hi", openvdb::Vec3DMetadata(openvdb::Vec3d(prt.bounds.hi.x, prt.bounds.hi.y, prt.bounds.hi.z)));
    m.insertMeta(kP + "seconds_samples", openvdb::DoubleMetadata(prt.secondsSamples));
    m.insertMeta(kP + "seconds_visibility", openvdb::DoubleMetadata(prt.secondsVisibility));
    m.insertMeta(kP + "seconds_basis", openvdb::DoubleMetadata(prt.secondsBasis));
    m.insertMeta(kP + "seconds_transfer", openvdb::DoubleMetadata(prt.secondsTransfer));
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const Vec3f& r = s.clusterRoot[c];
        m.insertMeta(kP + "cluster" + std::to_string(c) + "_root", openvdb::Vec3DMetadata(openvdb::Vec3d(r.x, r.y, r.z)));
    }

    if (prt.hasVolume()) {
        const GridSpec& g = prt.volumeGrid;
        m.insertMeta(kP + "volume_origin", openvdb::Vec3DMetadata(openvdb::Vec3d(g.origin.x, g.origin.y, g.origin.z)));
        m.insertMeta(kP + "volume_spacing", openvdb::DoubleMetadata(g.spacing));
        m.insertMeta(kP + "volume_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(g.nx, g.ny, g.nz)));
    }
    openvdb::GridCPtrVec grids{points, visBasis, lightBasis, transfer};
    if (volumeTransfer) grids.push_back(volumeTransfer);
    writeFileAtomically(path, [&](const std::string& temp) { openvdb::io::File(temp).write(grids, m); });
}

namespace {

struct Opened {
    std::unique_ptr<openvdb::io::File> file;
    openvdb::MetaMap::Ptr meta;
};

Opened openPrt(const std::string& path, bool requirePrt) {
    initOpenVdb();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw IoError("cannot read '" + path + "': no such file");
    Opened o;
    o.file = std::make_unique<openvdb::io::File>(path);
    try {
        o.file->open(false);
        o.meta = o.file->getMetadata();
    } catch (const std::exception& e) {
        throw FormatError("'" + path + "' is not a readable .vdb file: " + e.what());
    }
    auto kind = o.meta->getMetadata<openvdb::StringMetadata>(kP + "kind");
    if (requirePrt && (!kind || kind->value() != "prt")) {
        throw FormatError("'" + path + "' is not a PRT file (bake one with 'vdblight prt bake')");
    }
    return o;
}

void getBasis(const openvdb::FloatGrid& g, int c, int dim, int count, PcaBasis& b) {
    auto acc = g.getConstAccessor();
    b.dim = dim;
    b.count = count;
    b.mean.resize(std::size_t(dim));
    b.vectors.assign(std::size_t(count) * std::size_t(dim), 0.0f);
    for (int j = 0; j < dim; ++j) b.mean[std::size_t(j)] = acc.getValue(Coord(c, -1, j));
    for (int k = 0; k < count; ++k)
        for (int j = 0; j < dim; ++j) b.vectors[std::size_t(k) * std::size_t(dim) + std::size_t(j)] = acc.getValue(Coord(c, k, j));
}

template <typename GridT>
typename GridT::Ptr requireGrid(openvdb::io::File& f, const std::string& name, const std::string& path) {
    if (!f.hasGrid(name)) throw FormatError("'" + path + "' is not a valid PRT file: no grid " + name);
    auto g = openvdb::gridPtrCast<GridT>(f.readGrid(name));
    if (!g) throw FormatError("'" + path + "' is not a valid PRT file: grid " + name + " has the wrong type");
    return g;
}

}  // namespace

bool isPrtFile(const std::string& path) {
    Opened o = openPrt(path, false);
    auto kind = o.meta->getMetadata<openvdb::StringMetadata>(kP + "kind");
    return kind && kind->value() == "prt";
}

PrtData readPrt(const std::string& path) {
    Opened o = openPrt(path, true);
    const openvdb::MetaMap& m = *o.meta;
    const auto versionMeta = m.getMetadata<openvdb::Int64Metadata>(kP + "format_version");
    const int64_t version = versionMeta ? versionMeta->value() : meta<int64_t>(m, "prt_format_version", path);
    if (version < 1 || version > kPrtFormatVersion) {
        throw FormatError("'" + path + "' has PRT format version " + std::to_string(version) +
                          "; this build reads PRT versions 1 to " + std::to_string(kPrtFormatVersion));
    }
    PrtData prt;
    prt.bounces = version >= 2 ? int(meta<int64_t>(m, "bounces", path)) : 1;
    if (prt.bounces < 1) throw FormatError("'" + path + "' is not a valid PRT file: bounces < 1");
    prt.closureNormalise = version >= 2 && meta<std::string>(m, "form_factors", path) == "closure_normalised";
    // Absent in files written before sampled form factors existed: dense pairs.
    if (const auto rays = m.getMetadata<openvdb::Int64Metadata>(kP + "form_factor_rays")) {
        if (rays->value() < 0 || rays->value() > 65536)
            throw FormatError("'" + path + "' is not a valid PRT file: form_factor_rays out of range");
        prt.formFactorRays = uint32_t(rays->value());
    }
    const std::size_t n = std::size_t(meta<int64_t>(m, "samples", path));
    const std::size_t k = std::size_t(meta<int64_t>(m, "clusters", path));
    prt.sceneName = meta<std::string>(m, "scene", path);
    prt.sceneHash = meta<std::string>(m, "scene_hash", path);
    prt.seed = uint64_t(meta<int64_t>(m, "seed", path));
    prt.visGrid = int(meta<int64_t>(m, "vis_grid", path));
    prt.visCoeffStride = int(meta<int64_t>(m, "vis_coeffs", path));
    prt.depthCap = meta<float>(m, "depth_cap", path);
    prt.trainLights = uint32_t(meta<int64_t>(m, "train_lights", path));
    prt.paperBasis = meta<std::string>(m, "light_basis", path) == "centred";
    // Optional (files before them: point-light basis, scene at the world origin).
    if (auto f = m.getMetadata<openvdb::FloatMetadata>(kP + "oriented_training")) prt.orientedTraining = f->value();
    if (auto v = m.getMetadata<openvdb::Int64Metadata>(kP + "oriented_coeffs")) prt.orientedCoeffs = int(v->value());
    if (auto o = m.getMetadata<openvdb::Vec3DMetadata>(kP + "scene_origin")) {
        prt.origin = {o->value()[0], o->value()[1], o->value()[2]};
        if (!std::isfinite(prt.origin.x) || !std::isfinite(prt.origin.y) || !std::isfinite(prt.origin.z)) {
            throw FormatError("'" + path + "' is not a valid PRT file: non-finite scene origin");
        }
    }
    prt.transferStride = int(meta<int64_t>(m, "transfer_coeffs", path)) + 1;
    if (prt.orientedCoeffs < 0 || prt.orientedCoeffs >= prt.transferStride) {
        throw FormatError("'" + path + "' is not a valid PRT file: oriented_coeffs out of range");
    }
    const openvdb::Vec3d lo = meta<openvdb::Vec3d>(m, "bounds_lo", path), hi = meta<openvdb::Vec3d>(m, "bounds_hi", path);
    prt.bounds.lo = {lo[0], lo[1], lo[2]};
    prt.bounds.hi = {hi[0], hi[1], hi[2]};
    prt.secondsSamples = meta<double>(m, "seconds_samples", path);
    prt.secondsVisibility = meta<double>(m, "seconds_visibility", path);
    prt.secondsBasis = meta<double>(m, "seconds_basis", path);
    prt.secondsTransfer = meta<double>(m, "seconds_transfer", path);
    if (n == 0 || k == 0 || k > n || prt.visGrid < 2 || prt.visCoeffStride < 1 || prt.transferStride < 2) {
        throw FormatError("'" + path + "' is not a valid PRT file: inconsistent sizes");
    }
    SurfaceSamples& s = prt.samples;
    s.radius = meta<double>(m, "sample_radius", path);
    s.areaPerSample = meta<double>(m, "area_per_sample", path);
    s.position.resize(n);
    s.normal.resize(n);
    s.albedo.resize(n);
    s.cluster.resize(n);
    s.area.resize(n);
    prt.visCoeffs.assign(n * std::size_t(prt.visCoeffStride), 0.0f);
    for (std::size_t c = 0; c < k; ++c) {
        const openvdb::Vec3d r = meta<openvdb::Vec3d>(m, "cluster" + std::to_string(c) + "_root", path);
        s.clusterRoot.push_back(Vec3f{float(r[0]), float(r[1]), float(r[2])});
    }

    auto points = requireGrid<vp::PointDataGrid>(*o.file, "prt_samples", path);
    std::vector<char> seen(n, 0);
    const openvdb::math::Transform& xf = points->transform();
    try {
        for (auto leaf = points->tree().cbeginLeaf(); leaf; ++leaf) {
            vp::AttributeHandle<openvdb::Vec3f> hp(leaf->constAttributeArray("P"));
            vp::AttributeHandle<openvdb::Vec3f> hn(leaf->constAttributeArray("N"));
            vp::AttributeHandle<openvdb::Vec3f> ha(leaf->constAttributeArray("Cd"));
            vp::AttributeHandle<int32_t> hi(leaf->constAttributeArray("id"));
            vp::AttributeHandle<float> har(leaf->constAttributeArray("area"));
            vp::AttributeHandle<int32_t> hc(leaf->constAttributeArray("cluster"));
            vp::AttributeHandle<float> hv(leaf->constAttributeArray("vis"));
            if (hv.stride() != openvdb::Index(prt.visCoeffStride)) throw FormatError("vis stride mismatch");
            for (auto idx = leaf->beginIndexOn(); idx; ++idx) {
                const int32_t i = hi.get(*idx);
                const int32_t c = hc.get(*idx);
                if (i < 0 || std::size_t(i) >= n || seen[std::size_t(i)] || c < 0 || std::size_t(c) >= k) {
                    throw FormatError("bad sample id or cluster");
                }
                seen[std::size_t(i)] = 1;
                const openvdb::Vec3d w =
                    xf.indexToWorld(hp.get(*idx) + idx.getCoord().asVec3d()) - openvdb::Vec3d(prt.origin.x, prt.origin.y, prt.origin.z);
                const openvdb::Vec3f nn = hn.get(*idx), aa = ha.get(*idx);
                s.position[std::size_t(i)] = {float(w[0]), float(w[1]), float(w[2])};
                s.normal[std::size_t(i)] = {nn[0], nn[1], nn[2]};
                s.albedo[std::size_t(i)] = {aa[0], aa[1], aa[2]};
                s.cluster[std::size_t(i)] = uint32_t(c);
                s.area[std::size_t(i)] = har.get(*idx);
                for (int q = 0; q < prt.visCoeffStride; ++q)
                    prt.visCoeffs[std::size_t(i) * std::size_t(prt.visCoeffStride) + std::size_t(q)] = hv.get(*idx, openvdb::Index(q));
            }
        }
    } catch (const FormatError& e) {
        throw FormatError("'" + path + "' is not a valid PRT file: " + e.what());
    } catch (const std::exception& e) {
        throw FormatError("'" + path + "' is not a valid PRT file: " + e.what());
    }
    for (char v : seen)
        if (!v) throw FormatError("'" + path + "' is not a valid PRT file: samples missing");
    s.clusterBegin.assign(k + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (i > 0 && s.cluster[i] < s.cluster[i - 1]) throw FormatError("'" + path + "' is not a valid PRT file: samples not ordered by cluster");
        s.clusterBegin[s.cluster[i] + 1]++;
    }
    for (std::size_t c = 0; c < k; ++c) s.clusterBegin[c + 1] += s.clusterBegin[c];

    auto visBasis = requireGrid<openvdb::FloatGrid>(*o.file, "prt_vis_basis", path);
    auto lightBasis = requireGrid<openvdb::FloatGrid>(*o.file, "prt_light_basis", path);
    auto transfer = requireGrid<openvdb::Vec3SGrid>(*o.file, "prt_transfer", path);
    const int d = prt.visGrid * prt.visGrid;
    prt.visBasis.resize(k);
    prt.lightBasis.resize(k);
    for (std::size_t c = 0; c < k; ++c) {
        const int nc = int(s.clusterBegin[c + 1] - s.clusterBegin[c]);
        getBasis(*visBasis, int(c), d, std::min({prt.visCoeffStride, nc, d}), prt.visBasis[c]);
        // The point lights' vectors (at most train_lights of them), then the one-sided ones.
        getBasis(*lightBasis, int(c), nc,
                 std::min({prt.transferStride - 1, int(prt.trainLights) + prt.orientedCoeffs, nc}), prt.lightBasis[c]);
    }
    prt.transfer.assign(k, std::vector<Rgb>(std::size_t(prt.transferStride) * n, Rgb{0, 0, 0}));
    for (auto it = transfer->cbeginValueOn(); it; ++it) {
        const Coord xyz = it.getCoord();
        if (xyz.x() < 0 || std::size_t(xyz.x()) >= k || xyz.y() < 0 || xyz.y() >= prt.transferStride || xyz.z() < 0 ||
            std::size_t(xyz.z()) >= n) {
            throw FormatError("'" + path + "' is not a valid PRT file: transfer entry out of range");
        }
        const openvdb::Vec3f v = *it;
        prt.transfer[std::size_t(xyz.x())][std::size_t(xyz.y()) * n + std::size_t(xyz.z())] = Rgb{v[0], v[1], v[2]};
    }
    if (m.getMetadata<openvdb::Vec3IMetadata>(kP + "volume_dims")) {
        GridSpec& g = prt.volumeGrid;
        const openvdb::Vec3d origin = meta<openvdb::Vec3d>(m, "volume_origin", path);
        const openvdb::Vec3i d = meta<openvdb::Vec3i>(m, "volume_dims", path);
        g.origin = {origin[0], origin[1], origin[2]};
        g.spacing = meta<double>(m, "volume_spacing", path);
        g.nx = d[0];
        g.ny = d[1];
        g.nz = d[2];
        if (g.nx < 1 || g.ny < 1 || g.nz < 1 || g.nodeCount() > (1u << 24) || !(g.spacing > 0)) {
            throw FormatError("'" + path + "' is not a valid PRT file: bad volume dims");
        }
        const std::size_t count = g.nodeCount() * 9;
        auto vt = requireGrid<openvdb::Vec3SGrid>(*o.file, "prt_volume_transfer", path);
        prt.volumeTransfer.assign(k, std::vector<Rgb>(std::size_t(prt.transferStride) * count, Rgb{0, 0, 0}));
        for (auto it = vt->cbeginValueOn(); it; ++it) {
            const Coord xyz = it.getCoord();
            if (xyz.x() < 0 || std::size_t(xyz.x()) >= k || xyz.y() < 0 || xyz.y() >= prt.transferStride ||
                xyz.z() < 0 || std::size_t(xyz.z()) >= count) {
                throw FormatError("'" + path + "' is not a valid PRT file: volume transfer entry out of range");
            }
            const openvdb::Vec3f v = *it;
            prt.volumeTransfer[std::size_t(xyz.x())][std::size_t(xyz.y()) * count + std::size_t(xyz.z())] = Rgb{v[0], v[1], v[2]};
        }
    }
    prepareRelight(prt);
    return prt;
}

PrtFileInfo inspectPrt(const std::string& path) {
    Opened o = openPrt(path, true);
    const openvdb::MetaMap& m = *o.meta;
    PrtFileInfo info;
    info.fileBytes = uint64_t(fs::file_size(path));
    info.samples = uint64_t(meta<int64_t>(m, "samples", path));
    info.clusters = uint64_t(meta<int64_t>(m, "clusters", path));
    info.values = uint64_t(meta<int64_t>(m, "values", path));
    info.droppedValues = uint64_t(meta<int64_t>(m, "dropped_values", path));
    info.bytesFloat32 = info.values * 4;
    uint64_t stored = 0;
    for (const char* name : {"prt_vis_basis", "prt_light_basis", "prt_transfer", "prt_volume_transfer"}) {
        if (!o.file->hasGrid(name)) continue;
        auto g = o.file->readGrid(name);
        const uint64_t channels = std::string(name).find("transfer") != std::string::npos ? 3 : 1;
        stored += g->activeVoxelCount() * channels * (g->saveFloatAsHalf() ? 2 : 4);
    }
    const uint64_t visValues = info.samples * uint64_t(meta<int64_t>(m, "vis_coeffs", path));
    stored += visValues * (meta<bool>(m, "quantized", path) ? 2 : 4);
    info.bytesStored = stored;
    return info;
}

}  // namespace vdblight
