// The dense texel lattice and sampling a volume onto it through IrradianceQuery.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "export_internal.h"
#include "vdblight/core/errors.h"

namespace vdblight {

Vec3d TextureLattice::spacing() const {
    Vec3d s;
    for (int a = 0; a < 3; ++a) s[a] = dims[a] > 1 ? (hi[a] - lo[a]) / double(dims[a] - 1) : 0.0;
    return s;
}

Vec3d TextureLattice::point(int i, int j, int k) const {
    const int idx[3] = {i, j, k};
    Vec3d p;
    // lo + (hi - lo) * i / (n - 1): exact at both ends, so the outermost texels sit on the box.
    for (int a = 0; a < 3; ++a)
        p[a] = dims[a] > 1 ? lo[a] + (hi[a] - lo[a]) * double(idx[a]) / double(dims[a] - 1) : lo[a];
    return p;
}

TextureLattice chooseLattice(const Bounds& bounds, double finestSpacing, int resolution) {
    if (resolution != 0 && resolution < 2) throw ValueError("--resolution must be at least 2 texels");
    TextureLattice l;
    l.lo = bounds.lo;
    l.hi = bounds.hi;
    const Vec3d size = bounds.size();
    const double longest = std::max(size.x, std::max(size.y, size.z));
    double step = finestSpacing;
    if (resolution > 0 && longest > 0) step = longest / double(resolution - 1);
    if (!(step > 0)) throw ValueError("the volume has no node spacing to export at");
    for (int a = 0; a < 3; ++a) {
        const double n = std::round(size[a] / step) + 1.0;
        if (!(n < 1e9)) throw ValueError("the export lattice would have over 1e9 texels along an axis");
        l.dims[a] = std::max(1, int(n));
    }
    return l;
}

namespace exporter {

std::vector<std::vector<float>> sampleBasis(const IrradianceQuery& query, const TextureLattice& lattice, const Basis& basis) {
    const VolumeLookup& lookup = query.lookup();
    const std::vector<BasisTexture> layout = basis.textures();
    std::vector<float> probe(basis.floatsPerNode());
    try {
        lookup.channelValues(lattice.point(0, 0, 0), probe.data());  // FormatError before any allocation
    } catch (const FormatError&) {
        throw FormatError("volume kind '" + std::string(query.kind()) + "' exposes no channel values of basis '" +
                          basis.desc().kind + "'");
    }
    const std::size_t count = lattice.texelCount();
    std::vector<std::vector<float>> out(layout.size(), std::vector<float>(count * 4));
    const int nx = lattice.dims[0], ny = lattice.dims[1];
    tbb::parallel_for(tbb::blocked_range<int>(0, lattice.dims[2]), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> v(basis.floatsPerNode());
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    lookup.channelValues(lattice.point(i, j, k), v.data());
                    const std::size_t t = (std::size_t(k) * ny + j) * nx + i;
                    for (std::size_t tex = 0; tex < layout.size(); ++tex) {
                        float* texel = out[tex].data() + 4 * t;
                        for (int c = 0; c < 4; ++c) {
                            const int src = layout[tex].source[std::size_t(c)];
                            texel[c] = src >= 0 ? v[std::size_t(src)] : 0.0f;
                        }
                    }
                }
    });
    return out;
}

std::vector<std::vector<float>> sampleLayout(const IrradianceQuery& query, const TextureLattice& lattice,
                                             ExportLayout layout, int binResolution) {
    const VolumeLookup& lookup = query.lookup();
    if (layout == ExportLayout::Basis || layout == ExportLayout::Bins)
        throw FormatError(std::string("layout '") + layoutName(layout) + "' is sampled through its basis (sampleBasis)");
    const std::size_t textures = layoutTextures(layout, binResolution).size();
    const bool isSh = layoutIsSh(layout);
    // Probe once so that a layout that does not fit fails before any allocation.
    try {
        Rgb probe[9];
        float vectors[54];
        if (isSh) lookup.shRadiance(lattice.point(0, 0, 0), probe);
        else lookup.irradianceVectors(lattice.point(0, 0, 0), vectors);
    } catch (const FormatError&) {
        throw FormatError(std::string("layout '") + layoutName(layout) + "' does not fit volume kind '" + query.kind() +
                          (isSh ? "' (it stores no SH order-2 coefficients; try --layout vectors or compact)"
                                : "' (it stores no irradiance vectors; try --layout sh2, sh2-packed or sh1)"));
    }
    const std::size_t count = lattice.texelCount();
    std::vector<std::vector<float>> out(textures, std::vector<float>(count * 4));
    const int nx = lattice.dims[0], ny = lattice.dims[1];
    tbb::parallel_for(tbb::blocked_range<int>(0, lattice.dims[2]), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> texel(textures * 4);
        Rgb L[9];
        float v[54];
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < ny; ++j)
                for (int i = 0; i < nx; ++i) {
                    if (isSh) {
                        lookup.shRadiance(lattice.point(i, j, k), L);
                        packTexel(layout, L, texel.data());
                    } else {
                        lookup.irradianceVectors(lattice.point(i, j, k), v);
                        packVectorTexel(layout, v, texel.data());
                    }
                    const std::size_t t = (std::size_t(k) * ny + j) * nx + i;
                    for (std::size_t tex = 0; tex < textures; ++tex)
                        std::copy_n(texel.data() + 4 * tex, 4, out[tex].data() + 4 * t);
                }
    });
    return out;
}

double finestSpacing(const std::vector<VolumeLevel>& levels) {
    double finest = 0;
    for (const VolumeLevel& level : levels) finest = finest > 0 ? std::min(finest, level.grid.spacing) : level.grid.spacing;
    return finest;
}

}  // namespace exporter
}  // namespace vdblight
