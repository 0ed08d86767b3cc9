// The preview .vdb (preview.h): irradiance for the six axis normals and their mean as
// colour grids on the export lattice, sampled through IrradianceQuery.
#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdio>
#include <mutex>

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/export/slice.h"
#include "vdblight/query/query.h"

namespace vdblight {

namespace {
const char* const kNames[8] = {"irradiance_avg",  "irradiance_xpos", "irradiance_xneg", "irradiance_ypos",
                               "irradiance_yneg", "irradiance_zpos", "irradiance_zneg", "density"};

openvdb::math::Transform::Ptr latticeTransform(const TextureLattice& l) {
    const Vec3d h = l.spacing();
    double s[3];
    for (int a = 0; a < 3; ++a) s[a] = h[a] > 0 ? h[a] : 1.0;  // a single layer: any positive size
    auto xf = openvdb::math::Transform::createLinearTransform(1.0);
    xf->preScale(openvdb::Vec3d(s[0], s[1], s[2]));
    xf->postTranslate(openvdb::Vec3d(l.lo.x, l.lo.y, l.lo.z));
    return xf;
}
}  // namespace

const char* const* previewGridNames(int* count) {
    if (count) *count = 8;
    return kNames;
}

TextureLattice exportPreviewVdb(const Volume& volume, const std::string& path, int resolution, uint64_t maxVoxels) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    const IrradianceQuery query(volume);
    double finest = 0;
    for (const VolumeLevel& level : volume.levels)
        finest = finest > 0 ? std::min(finest, level.grid.spacing) : level.grid.spacing;
    const TextureLattice l = chooseLattice(query.bounds(), finest, resolution);
    if (l.texelCount() > maxVoxels)
        throw ValueError("the preview would have " + std::to_string(l.texelCount()) + " voxels (limit " +
                         std::to_string(maxVoxels) + "); lower --resolution");
    const int nx = l.dims[0], ny = l.dims[1], nz = l.dims[2];
    const std::size_t count = l.texelCount();
    std::vector<Rgb> values(count * 7);
    tbb::parallel_for(tbb::blocked_range<int>(0, nz), [&](const tbb::blocked_range<int>& r) {
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    const Vec3d x = l.point(i, j, k);  // double: volumes far from the origin
                    Rgb* v = values.data() + ((std::size_t(k) * ny + j) * nx + i) * 7;
                    Rgb sum(0, 0, 0);
                    for (int d = 0; d < 6; ++d) {
                        Vec3f n(0, 0, 0);
                        n[d / 2] = d % 2 ? -1.0f : 1.0f;
                        v[1 + d] = query.irradianceWorld(x, n);
                        sum += v[1 + d];
                    }
                    v[0] = sum * (1.0f / 6.0f);
                }
    });

    openvdb::GridPtrVec grids;
    const auto xf = latticeTransform(l);
    for (int g = 0; g < 7; ++g) {
        auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
        auto acc = grid->getAccessor();
        for (int k = 0; k < nz; ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    const Rgb& c = values[((std::size_t(k) * ny + j) * nx + i) * 7 + g];
                    acc.setValue(openvdb::Coord(i, j, k), openvdb::Vec3s(c.x, c.y, c.z));
                }
        grid->setName(kNames[g]);
        grid->setTransform(xf->copy());
        grid->setGridClass(openvdb::GRID_UNKNOWN);
        grid->setVectorType(openvdb::VEC_INVARIANT);
        grids.push_back(grid);
    }
    auto density = openvdb::FloatGrid::create(0.0f);
    density->fill(openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(nx - 1, ny - 1, nz - 1)), 1.0f, true);
    density->tree().voxelizeActiveTiles();
    density->setName(kNames[7]);
    density->setTransform(xf->copy());
    density->setGridClass(openvdb::GRID_FOG_VOLUME);
    grids.push_back(density);

    openvdb::MetaMap meta;
    meta.insertMeta("vdblight:preview_of_kind", openvdb::StringMetadata(query.kind()));
    meta.insertMeta("vdblight:preview_units", openvdb::StringMetadata("irradiance W/m^2"));
    writeFileAtomically(path, [&](const std::string& temp) { openvdb::io::File(temp).write(grids, meta); });
    return l;
}

}  // namespace vdblight
