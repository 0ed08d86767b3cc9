// Unreal's Sparse Volume Textures from OpenVDB: an SVT asset has at most two attributes
// (A and B) of up to four channels each, filled at import from the grids' components. So
// every .vdb written here carries two RGBA textures at most, as half grids of 3 (RGB) and 1
// (alpha) components, and L2's seven textures span four files (engine_internal.h).
#include <openvdb/openvdb.h>

#include <mutex>

#include "engine_internal.h"

namespace vdblight::exporter {

namespace {
// shC's alpha is 0 by construction ("unused (0)", docs/engines.md): no grid for it.
bool alphaAlwaysZero(const TextureDesc& d) { return d.components[3].rfind("unused", 0) == 0; }
}  // namespace

std::vector<SvtFile> planSvtFiles(const std::vector<TextureDesc>& descs) {
    std::vector<SvtFile> files;
    for (std::size_t t = 0; t < descs.size(); t += 2) {
        SvtFile f;
        f.file = "svt_" + std::to_string(files.size()) + ".vdb";
        for (std::size_t u = t; u < std::min(descs.size(), t + 2); ++u) {
            f.textures.push_back(descs[u].name);
            f.grids.push_back(descs[u].name + "_rgb");
            if (!alphaAlwaysZero(descs[u])) f.grids.push_back(descs[u].name + "_a");
        }
        files.push_back(f);
    }
    return files;
}

void writeSvtFile(const std::string& path, const SvtFile& plan, const std::vector<TextureDesc>& descs,
                  const std::vector<std::vector<float>>& textures, const TextureLattice& l, double finestUnits) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    // Voxel centres on the texel points, in the engine's units and axes.
    const Vec3d h = l.spacing();
    auto xf = openvdb::math::Transform::createLinearTransform(1.0);
    xf->preScale(openvdb::Vec3d(h[0] > 0 ? h[0] : finestUnits, h[1] > 0 ? h[1] : finestUnits, h[2] > 0 ? h[2] : finestUnits));
    xf->postTranslate(openvdb::Vec3d(l.lo.x, l.lo.y, l.lo.z));
    openvdb::GridPtrVec grids;
    for (const std::string& name : plan.textures) {
        std::size_t t = 0;
        while (descs[t].name != name) ++t;
        auto rgb = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        openvdb::FloatGrid::Ptr alpha = alphaAlwaysZero(descs[t]) ? nullptr : openvdb::FloatGrid::create(0.0f);
        auto rgbAcc = rgb->getAccessor();
        std::size_t texel = 0;
        for (int k = 0; k < l.dims[2]; ++k)
            for (int j = 0; j < l.dims[1]; ++j)
                for (int i = 0; i < l.dims[0]; ++i, ++texel) {
                    const float* v = &textures[t][4 * texel];
                    rgbAcc.setValue(openvdb::Coord(i, j, k), openvdb::Vec3s(v[0], v[1], v[2]));
                    if (alpha) alpha->tree().setValue(openvdb::Coord(i, j, k), v[3]);
                }
        rgb->setName(name + "_rgb");
        rgb->setVectorType(openvdb::VEC_INVARIANT);
        for (openvdb::GridBase::Ptr g : {openvdb::GridBase::Ptr(rgb), openvdb::GridBase::Ptr(alpha)}) {
            if (!g) continue;
            if (g != rgb) g->setName(name + "_a");
            g->setTransform(xf->copy());
            g->setGridClass(openvdb::GRID_UNKNOWN);
            g->setSaveFloatAsHalf(true);
            grids.push_back(g);
        }
    }
    openvdb::MetaMap meta;
    meta.insertMeta("vdblight:preset", openvdb::StringMetadata("unreal"));
    meta.insertMeta("vdblight:frame", openvdb::StringMetadata("left-handed, +Z up, +X forward, centimetres (Unreal)"));
    openvdb::io::File(path).write(grids, meta);
}

}  // namespace vdblight::exporter
