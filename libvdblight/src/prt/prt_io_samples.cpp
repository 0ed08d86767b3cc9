// The samples section of a PRT file: one OpenVDB point per surface sample, so that Houdini
// and Blender show the samples where they are (prt_io_sections.h).
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointCount.h>
#include <openvdb/tools/PointIndexGrid.h>

#include "prt_io_sections.h"

namespace vdblight::prt_io {

namespace vp = openvdb::points;

vp::PointDataGrid::Ptr writeSamples(const PrtData& prt, bool quantize) {
    const SurfaceSamples& s = prt.samples;
    std::vector<openvdb::Vec3f> pos(s.size()), nrm(s.size()), alb(s.size());
    std::vector<int32_t> id(s.size()), cl(s.size());
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
    auto attribute = [&](const char* name, const auto& values) {
        using T = typename std::decay_t<decltype(values)>::value_type;
        vp::appendAttribute<T>(tree, name);
        vp::populateAttribute<vp::PointDataTree, PIT, vp::PointAttributeVector<T>>(tree, index->tree(), name,
                                                                                   vp::PointAttributeVector<T>(values));
    };
    attribute("N", nrm);
    attribute("Cd", alb);
    attribute("area", s.area);
    attribute("id", id);
    attribute("cluster", cl);
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

namespace {
/// Copies every point of one leaf into its sample (by its id), marking the id seen.
void readLeaf(const vp::PointDataTree::LeafNodeType& leaf, const openvdb::math::Transform& xf, PrtData& prt,
              std::vector<char>& seen) {
    SurfaceSamples& s = prt.samples;
    const std::size_t n = s.position.size(), k = s.clusterRoot.size();
    vp::AttributeHandle<openvdb::Vec3f> hp(leaf.constAttributeArray("P"));
    vp::AttributeHandle<openvdb::Vec3f> hn(leaf.constAttributeArray("N"));
    vp::AttributeHandle<openvdb::Vec3f> ha(leaf.constAttributeArray("Cd"));
    vp::AttributeHandle<int32_t> hi(leaf.constAttributeArray("id"));
    vp::AttributeHandle<float> har(leaf.constAttributeArray("area"));
    vp::AttributeHandle<int32_t> hc(leaf.constAttributeArray("cluster"));
    vp::AttributeHandle<float> hv(leaf.constAttributeArray("vis"));
    const std::size_t stride = std::size_t(prt.visCoeffStride);
    if (hv.stride() != openvdb::Index(stride)) throw FormatError("vis stride mismatch");
    for (auto idx = leaf.beginIndexOn(); idx; ++idx) {
        const int32_t i = hi.get(*idx);
        const int32_t c = hc.get(*idx);
        if (i < 0 || std::size_t(i) >= n || seen[std::size_t(i)] || c < 0 || std::size_t(c) >= k)
            throw FormatError("bad sample id or cluster");
        const std::size_t at = std::size_t(i);
        seen[at] = 1;
        const openvdb::Vec3d w =
            xf.indexToWorld(hp.get(*idx) + idx.getCoord().asVec3d()) - openvdb::Vec3d(prt.origin.x, prt.origin.y, prt.origin.z);
        const openvdb::Vec3f nn = hn.get(*idx), aa = ha.get(*idx);
        s.position[at] = {float(w[0]), float(w[1]), float(w[2])};
        s.normal[at] = {nn[0], nn[1], nn[2]};
        s.albedo[at] = {aa[0], aa[1], aa[2]};
        s.cluster[at] = uint32_t(c);
        s.area[at] = har.get(*idx);
        for (std::size_t q = 0; q < stride; ++q) prt.visCoeffs[at * stride + q] = hv.get(*idx, openvdb::Index(q));
    }
}
}  // namespace

void readSamples(openvdb::io::File& file, PrtData& prt, const std::string& path) {
    SurfaceSamples& s = prt.samples;
    const std::size_t n = s.position.size(), k = s.clusterRoot.size();
    auto points = requireGrid<vp::PointDataGrid>(file, "prt_samples", path);
    std::vector<char> seen(n, 0);
    try {
        for (auto leaf = points->tree().cbeginLeaf(); leaf; ++leaf) readLeaf(*leaf, points->transform(), prt, seen);
    } catch (const std::exception& e) {  // OpenVDB's own (a missing attribute) and ours
        throw FormatError("'" + path + "' is not a valid PRT file: " + e.what());
    }
    for (char v : seen)
        if (!v) throw FormatError("'" + path + "' is not a valid PRT file: samples missing");
    s.clusterBegin.assign(k + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (i > 0 && s.cluster[i] < s.cluster[i - 1])
            throw FormatError("'" + path + "' is not a valid PRT file: samples not ordered by cluster");
        s.clusterBegin[s.cluster[i] + 1]++;
    }
    for (std::size_t c = 0; c < k; ++c) s.clusterBegin[c + 1] += s.clusterBegin[c];
}

}  // namespace vdblight::prt_io
