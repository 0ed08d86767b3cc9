// The textures of one streaming cell (cell_textures.h).
#include "cell_textures.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "basis/shadow_edges.h"
#include "vdblight/basis/depth_moments.h"

namespace vdblight::exporter {

namespace {
/// Calls texel(whole lattice point, cell texel index) for every texel of the cell, slices in parallel.
template <class Texel>
void forEachTexel(const TextureLattice& whole, const CellRange& cell, const Texel& texel) {
    tbb::parallel_for(tbb::blocked_range<int>(0, cell.dims[2]), [&](const tbb::blocked_range<int>& r) {
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < cell.dims[1]; ++j)
                for (int i = 0; i < cell.dims[0]; ++i)
                    texel(whole.point(cell.first[0] + i, cell.first[1] + j, cell.first[2] + k),
                          (std::size_t(k) * cell.dims[1] + j) * cell.dims[0] + i);
    });
}
}  // namespace

std::vector<std::vector<float>> cellLayoutTextures(const VolumeLookup& lookup, const TextureLattice& whole,
                                                   const CellRange& cell, ExportLayout layout, const Basis* basis,
                                                   std::size_t textures) {
    std::vector<std::vector<float>> out(textures, std::vector<float>(cell.texels() * 4));
    if (layout == ExportLayout::Basis) {  // as sampleBasis: the texture components' source channels
        const std::vector<BasisTexture> sources = basis->textures();
        const std::size_t floats = basis->floatsPerNode();
        forEachTexel(whole, cell, [&](const Vec3d& x, std::size_t t) {
            thread_local std::vector<float> v;
            v.resize(floats);
            lookup.channelValues(x, v.data());
            for (std::size_t tex = 0; tex < sources.size(); ++tex)
                for (int c = 0; c < 4; ++c) {
                    const int src = sources[tex].source[std::size_t(c)];
                    out[tex][4 * t + std::size_t(c)] = src >= 0 ? v[std::size_t(src)] : 0.0f;
                }
        });
        return out;
    }
    forEachTexel(whole, cell, [&](const Vec3d& x, std::size_t t) {  // as sampleLayout: shRadiance, then packTexel
        Rgb L[9];
        float texel[4 * 9];  // at most the 9 textures of layout sh2
        lookup.shRadiance(x, L);
        packTexel(layout, L, texel);
        for (std::size_t tex = 0; tex < textures; ++tex) std::copy_n(texel + 4 * tex, 4, out[tex].data() + 4 * t);
    });
    return out;
}

std::vector<std::vector<float>> cellVisibilityTextures(const LightVisibility& visibility, const TextureLattice& whole,
                                                       const CellRange& cell, std::size_t lights) {
    std::vector<std::vector<float>> out((lights + 3) / 4, std::vector<float>(cell.texels() * 4, 0.0f));
    forEachTexel(whole, cell, [&](const Vec3d& x, std::size_t t) {
        std::vector<float> v(lights);
        visibility.visibility(x, v.data());
        for (std::size_t l = 0; l < lights; ++l) out[l / 4][t * 4 + l % 4] = v[l];
    });
    return out;
}

bool depthOnFinestNodes(const GridSpec& g, const TextureLattice& lattice) {
    if (lattice.dims[0] != g.nx || lattice.dims[1] != g.ny || lattice.dims[2] != g.nz) return false;
    const double tol = 1e-9 * std::max(1.0, g.spacing * std::max({g.nx, g.ny, g.nz}));
    for (int a = 0; a < 3; ++a)
        if (std::fabs(lattice.lo[a] - g.origin[a]) > tol) return false;
    return true;
}

std::vector<std::vector<float>> cellDepthTextures(const FinestNodeDepth& depth, const CellRange& cell) {
    // As depthTextures: per axis a, RGBA = (mean +a, mean -a, sigma +a, sigma -a); a texel
    // that is no node of the finest level holds a free face (mean 1, sigma 0).
    constexpr float kFree[4] = {1.0f, 1.0f, 0.0f, 0.0f};
    std::vector<std::vector<float>> out(3, std::vector<float>(cell.texels() * 4));
    tbb::parallel_for(tbb::blocked_range<int>(0, cell.dims[2]), [&](const tbb::blocked_range<int>& r) {
        float d[depth::kFloatsPerNode];
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < cell.dims[1]; ++j)
                for (int i = 0; i < cell.dims[0]; ++i) {
                    const std::size_t t = (std::size_t(k) * cell.dims[1] + j) * cell.dims[0] + i;
                    const bool stored = depth(cell.first[0] + i, cell.first[1] + j, cell.first[2] + k, d);
                    for (int a = 0; a < 3; ++a) {
                        float* texel = &out[std::size_t(a)][t * 4];
                        if (!stored) {
                            std::copy_n(kFree, 4, texel);
                            continue;
                        }
                        texel[0] = d[depth::kMeanPositive * 3 + a];
                        texel[1] = d[depth::kMeanNegative * 3 + a];
                        texel[2] = d[depth::kSigmaPositive * 3 + a];
                        texel[3] = d[depth::kSigmaNegative * 3 + a];
                    }
                }
    });
    return out;
}

std::vector<std::vector<float>> cellEdgeTextures(const NodeShadowEdges& edges, const CellRange& cell, std::size_t lights,
                                                 bool withRamp, bool withStrips) {
    const std::size_t textures = (withRamp ? 3 : 2) * ((lights + 3) / 4) + (withStrips ? lights : 0);
    std::vector<std::vector<float>> out(textures, std::vector<float>(cell.texels() * 4, 0.0f));
    tbb::parallel_for(tbb::blocked_range<int>(0, cell.dims[2]), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> e(lights * shadow_edge::kFloatsPerLight);
        for (int k = r.begin(); k < r.end(); ++k)
            for (int j = 0; j < cell.dims[1]; ++j)
                for (int i = 0; i < cell.dims[0]; ++i) {
                    edges(cell.first[0] + i, cell.first[1] + j, cell.first[2] + k, e.data());
                    packEdgeTexel(e.data(), lights, withRamp, withStrips, (std::size_t(k) * cell.dims[1] + j) * cell.dims[0] + i, out);
                }
    });
    return out;
}

}  // namespace vdblight::exporter
