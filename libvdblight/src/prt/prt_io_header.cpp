// The header section of a PRT file: what was baked, with which parameters, and how big
// every other section is (prt_io_sections.h).
#include <cmath>

#include "prt_io_sections.h"

namespace vdblight::prt_io {

namespace {
openvdb::Vec3d toVdb(const Vec3d& v) { return {v.x, v.y, v.z}; }
}  // namespace

openvdb::MetaMap writeHeader(const PrtData& prt, const PrtWriteOptions& options, const Counter& n) {
    const SurfaceSamples& s = prt.samples;
    openvdb::MetaMap m;
    auto put = [&](const std::string& key, const openvdb::Metadata& value) { m.insertMeta(kP + key, value); };
    put("kind", openvdb::StringMetadata("prt"));
    put("format_version", openvdb::Int64Metadata(kPrtFormatVersion));
    put("prt_format_version", openvdb::Int64Metadata(kPrtFormatVersion));
    put("bounces", openvdb::Int64Metadata(prt.bounces));
    put("form_factors", openvdb::StringMetadata(prt.closureNormalise ? "closure_normalised" : "disk"));
    put("form_factor_rays", openvdb::Int64Metadata(int64_t(prt.formFactorRays)));
    put("method", openvdb::StringMetadata("Leonhardt & Bohn PRT, diffuse bounces sample to sample"));
    put("scene", openvdb::StringMetadata(prt.sceneName));
    put("scene_hash", openvdb::StringMetadata(prt.sceneHash));
    put("seed", openvdb::Int64Metadata(int64_t(prt.seed)));
    put("samples", openvdb::Int64Metadata(int64_t(s.size())));
    put("clusters", openvdb::Int64Metadata(int64_t(s.clusters())));
    put("sample_radius", openvdb::DoubleMetadata(s.radius));
    put("area_per_sample", openvdb::DoubleMetadata(s.areaPerSample));
    put("vis_grid", openvdb::Int64Metadata(prt.visGrid));
    put("vis_coeffs", openvdb::Int64Metadata(prt.visCoeffStride));
    put("depth_cap", openvdb::FloatMetadata(prt.depthCap));
    put("train_lights", openvdb::Int64Metadata(prt.trainLights));
    put("transfer_coeffs", openvdb::Int64Metadata(prt.transferStride - 1));
    put("light_basis", openvdb::StringMetadata(prt.paperBasis ? "centred" : "normalised_uncentred"));
    put("oriented_training", openvdb::FloatMetadata(prt.orientedTraining));
    put("oriented_coeffs", openvdb::Int64Metadata(prt.orientedCoeffs));
    put("scene_origin", openvdb::Vec3DMetadata(toVdb(prt.origin)));
    put("quantized", openvdb::BoolMetadata(options.quantize));
    put("sparse_threshold", openvdb::FloatMetadata(options.sparseThreshold));
    put("values", openvdb::Int64Metadata(int64_t(n.values)));
    put("dropped_values", openvdb::Int64Metadata(int64_t(n.dropped)));
    put("bounds_lo", openvdb::Vec3DMetadata(toVdb(prt.bounds.lo)));
    put("bounds_hi", openvdb::Vec3DMetadata(toVdb(prt.bounds.hi)));
    put("seconds_samples", openvdb::DoubleMetadata(prt.secondsSamples));
    put("seconds_visibility", openvdb::DoubleMetadata(prt.secondsVisibility));
    put("seconds_basis", openvdb::DoubleMetadata(prt.secondsBasis));
    put("seconds_transfer", openvdb::DoubleMetadata(prt.secondsTransfer));
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const Vec3f& r = s.clusterRoot[c];
        put("cluster" + std::to_string(c) + "_root", openvdb::Vec3DMetadata(openvdb::Vec3d(r.x, r.y, r.z)));
    }
    if (prt.hasVolume()) {
        const GridSpec& g = prt.volumeGrid;
        put("volume_origin", openvdb::Vec3DMetadata(toVdb(g.origin)));
        put("volume_spacing", openvdb::DoubleMetadata(g.spacing));
        put("volume_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(g.nx, g.ny, g.nz)));
    }
    return m;
}

PrtData readHeader(const openvdb::MetaMap& m, const std::string& path) {
    auto invalid = [&](const std::string& why) { return FormatError("'" + path + "' is not a valid PRT file: " + why); };
    const auto versionMeta = m.getMetadata<openvdb::Int64Metadata>(kP + "format_version");
    const int64_t version = versionMeta ? versionMeta->value() : meta<int64_t>(m, "prt_format_version", path);
    if (version < 1 || version > kPrtFormatVersion) {
        throw FormatError("'" + path + "' has PRT format version " + std::to_string(version) +
                          "; this build reads PRT versions 1 to " + std::to_string(kPrtFormatVersion));
    }
    PrtData prt;
    prt.bounces = version >= 2 ? int(meta<int64_t>(m, "bounces", path)) : 1;
    if (prt.bounces < 1) throw invalid("bounces < 1");
    prt.closureNormalise = version >= 2 && meta<std::string>(m, "form_factors", path) == "closure_normalised";
    // Absent in files written before sampled form factors existed: dense pairs.
    if (const auto rays = m.getMetadata<openvdb::Int64Metadata>(kP + "form_factor_rays")) {
        if (rays->value() < 0 || rays->value() > 65536) throw invalid("form_factor_rays out of range");
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
        if (!std::isfinite(prt.origin.x) || !std::isfinite(prt.origin.y) || !std::isfinite(prt.origin.z))
            throw invalid("non-finite scene origin");
    }
    prt.transferStride = int(meta<int64_t>(m, "transfer_coeffs", path)) + 1;
    if (prt.orientedCoeffs < 0 || prt.orientedCoeffs >= prt.transferStride) throw invalid("oriented_coeffs out of range");
    const openvdb::Vec3d lo = meta<openvdb::Vec3d>(m, "bounds_lo", path), hi = meta<openvdb::Vec3d>(m, "bounds_hi", path);
    prt.bounds.lo = {lo[0], lo[1], lo[2]};
    prt.bounds.hi = {hi[0], hi[1], hi[2]};
    prt.secondsSamples = meta<double>(m, "seconds_samples", path);
    prt.secondsVisibility = meta<double>(m, "seconds_visibility", path);
    prt.secondsBasis = meta<double>(m, "seconds_basis", path);
    prt.secondsTransfer = meta<double>(m, "seconds_transfer", path);
    if (n == 0 || k == 0 || k > n || prt.visGrid < 2 || prt.visCoeffStride < 1 || prt.transferStride < 2)
        throw invalid("inconsistent sizes");

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
    if (m.getMetadata<openvdb::Vec3IMetadata>(kP + "volume_dims")) {
        GridSpec& g = prt.volumeGrid;
        const openvdb::Vec3d origin = meta<openvdb::Vec3d>(m, "volume_origin", path);
        const openvdb::Vec3i d = meta<openvdb::Vec3i>(m, "volume_dims", path);
        g.origin = {origin[0], origin[1], origin[2]};
        g.spacing = meta<double>(m, "volume_spacing", path);
        g.nx = d[0];
        g.ny = d[1];
        g.nz = d[2];
        if (g.nx < 1 || g.ny < 1 || g.nz < 1 || g.nodeCount() > (1u << 24) || !(g.spacing > 0))
            throw invalid("bad volume dims");
    }
    return prt;
}

}  // namespace vdblight::prt_io
