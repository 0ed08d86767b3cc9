// The SH order-2 lookups on a streamed volume (stream_lookups.h). The arithmetic is
// ShUniformLookup's or ShLevelsLookup's, operation for operation (sh_uniform_lookup.cpp,
// sh_levels_lookup.cpp), with the corner nodes read through StreamedVolume instead of a node
// array, so that the answers are the same bits; query_stream_test checks that they are.
#include "stream_lookups.h"

#include <cmath>

#include "depth_weights.h"
#include "lattice_locate.h"
#include "sh_trilinear.h"
#include "vdblight/core/errors.h"
#include "basis/sh.h"

namespace vdblight {

namespace {
constexpr int kFloatsPerNode = sh::kCoeffs * 3;

class StreamingShLookup final : public VolumeLookup {
public:
    StreamingShLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid, OutsidePolicy outside)
        : volume_(std::move(volume)), grid_(grid), outside_(outside) {
        origin_ = Vec3f(grid_.origin);
        invSpacing_ = float(1.0 / grid_.spacing);
        depthWeights_ = volume_->hasDepth();
    }

    Bounds bounds() const override { return grid_.nodeBounds(); }
    void setDepthWeights(bool on) override { depthWeights_ = on && volume_->hasDepth(); }
    bool depthWeighted() const override { return depthWeights_; }

    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override {
        int i, j, k;
        float fx, fy, fz;
        locate(x, i, j, k, fx, fy, fz);
        float y[sh::kCoeffs];
        sh::evalUnrolled(n, y);
        const int di = grid_.nx > 1 ? 1 : 0, dj = grid_.ny > 1 ? 1 : 0, dk = grid_.nz > 1 ? 1 : 0;
        float p[8][kFloatsPerNode];
        float d[8][depth::kFloatsPerNode];
        const float* corners[8];
        const float* depth[8];
        for (int c = 0; c < 8; ++c) {
            const int ci = (c & 1) * di, cj = ((c >> 1) & 1) * dj, ck = (c >> 2) * dk;
            node(i + ci, j + cj, k + ck, p[c]);
            if (depthWeights_) volume_->readDepth(i + ci, j + cj, k + ck, d[c]);
            corners[c] = p[c];
            depth[c] = d[c];
        }
        return query_detail::interpolateShCorners(corners, depthWeights_ ? depth : nullptr, fx, fy, fz, y);
    }

    void shRadiance(const Vec3d& x, Rgb out[9]) const override {
        query_detail::TrilinearCorners corners = query_detail::trilinearCorners(grid_, x, outside_);
        float p[8][kFloatsPerNode];
        float d[8][depth::kFloatsPerNode];
        for (int c = 0; c < 8; ++c) {
            const std::size_t linear = corners.node[c];
            const int i = int(linear % std::size_t(grid_.nx)), j = int((linear / std::size_t(grid_.nx)) % std::size_t(grid_.ny)),
                      k = int(linear / (std::size_t(grid_.nx) * std::size_t(grid_.ny)));
            node(i, j, k, p[c]);
            if (depthWeights_) volume_->readDepth(i, j, k, d[c]);
        }
        if (depthWeights_) {
            const float* depth[8];
            for (int c = 0; c < 8; ++c) depth[c] = d[c];
            query_detail::weightCornersByDepth(corners, depth, grid_, x, outside_);
        }
        double sum[kFloatsPerNode] = {};
        for (int c = 0; c < 8; ++c) {
            const double w = corners.weight[c];
            if (w == 0.0) continue;
            for (int f = 0; f < kFloatsPerNode; ++f) sum[f] += w * p[c][f];
        }
        for (int c = 0; c < sh::kCoeffs; ++c) {
            const double a = sh::kCosineLobe[sh::bandOf(c)];
            out[c] = Rgb(float(sum[3 * c] / a), float(sum[3 * c + 1] / a), float(sum[3 * c + 2] / a));
        }
    }

private:
    // The node's 27 coefficients with the cosine-lobe constants folded in, as ShUniformLookup
    // stores them (float product).
    void node(int i, int j, int k, float* out) const {
        volume_->readNode(i, j, k, out);
        for (int f = 0; f < kFloatsPerNode; ++f) out[f] = out[f] * float(sh::kCosineLobe[sh::bandOf(f / 3)]);
    }

    void locate(const Vec3f& x, int& i, int& j, int& k, float& fx, float& fy, float& fz) const {
        const Vec3f g = (x - origin_) * invSpacing_;
        query_detail::checkInside(g, grid_, x, outside_);
        query_detail::splitCell(g.x, grid_.nx, i, fx);
        query_detail::splitCell(g.y, grid_.ny, j, fy);
        query_detail::splitCell(g.z, grid_.nz, k, fz);
    }

    std::shared_ptr<const StreamedVolume> volume_;
    GridSpec grid_;
    OutsidePolicy outside_;
    Vec3f origin_;
    float invSpacing_;
    bool depthWeights_ = false;
};

// The multi-level lookup on a streamed volume: ShLevelsLookup's descent and arithmetic
// (sh_levels_lookup.cpp), with its child tables replaced by the refined-cell masks and the
// nodes' presence (culled volumes) read from the grids' topology, and its node bricks by
// voxels of each level's grids.
class StreamingLevelsLookup final : public VolumeLookup {
public:
    StreamingLevelsLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0, OutsidePolicy outside)
        : volume_(std::move(volume)), grid_(grid0), outside_(outside) {
        const Volume& h = volume_->header();
        K_ = h.refineFactor();
        levels_ = int(h.levels.size());
        culled_ = metaString(h.meta, "culling") == "solid-regions";
        origin_ = Vec3f(grid_.origin);
        invSpacing_ = float(1.0 / grid_.spacing);
        depthWeights_ = volume_->hasDepth();
    }

    Bounds bounds() const override { return grid_.nodeBounds(); }
    void setDepthWeights(bool on) override { depthWeights_ = on && volume_->hasDepth(); }
    bool depthWeighted() const override { return depthWeights_; }

    Rgb irradiance(const Vec3f& x, const Vec3f& n) const override {
        float y[sh::kCoeffs];
        sh::evalUnrolled(n, y);
        const Vec3f g = (x - origin_) * invSpacing_;
        query_detail::checkInside(g, grid_, x, outside_);
        int cell[3];
        float f[3];
        query_detail::splitCell(g.x, grid_.nx, cell[0], f[0]);
        query_detail::splitCell(g.y, grid_.ny, cell[1], f[1]);
        query_detail::splitCell(g.z, grid_.nz, cell[2], f[2]);
        int level = 0;
        while (volume_->cellRefined(level, cell[0], cell[1], cell[2])) {
            ++level;
            for (int a = 0; a < 3; ++a) {
                int local;
                query_detail::splitLocal(f[a], K_, local);
                cell[a] = cell[a] * K_ + local;
            }
        }
        if (leafCulled(level, cell)) return Rgb(0, 0, 0);
        const bool weighted = depthWeights_ && query_detail::depthWeightsApplyAt(std::size_t(level), std::size_t(levels_));
        float p[8][kFloatsPerNode];
        float d[8][depth::kFloatsPerNode];
        const float* corners[8];
        const float* depth[8];
        for (int c = 0; c < 8; ++c) {
            node(level, cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2), p[c]);
            if (weighted) volume_->readDepth(level, cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2), d[c]);
            corners[c] = p[c];
            depth[c] = d[c];
        }
        // As ShLevelsLookup's interpolation (sh_levels_lookup.cpp).
        return query_detail::interpolateShCorners(corners, weighted ? depth : nullptr, f[0], f[1], f[2], y);
    }

    void shRadiance(const Vec3d& x, Rgb out[9]) const override {
        const auto snap = [](double g) { return std::fabs(g - std::round(g)) < 1e-9 ? std::round(g) : g; };
        int cell[3];
        double frac[3];
        query_detail::locateExact(grid_, x, outside_, cell, frac);  // snapped onto nodes within 1e-9
        int level = 0;
        while (volume_->cellRefined(level, cell[0], cell[1], cell[2])) {
            ++level;
            for (int a = 0; a < 3; ++a) {
                const double g = snap(frac[a] * K_);
                const int local = std::min(int(g), K_ - 1);
                frac[a] = g - local;
                cell[a] = cell[a] * K_ + local;
            }
        }
        if (leafCulled(level, cell)) {
            for (int c = 0; c < sh::kCoeffs; ++c) out[c] = Rgb(0, 0, 0);
            return;
        }
        const bool weighted = depthWeights_ && query_detail::depthWeightsApplyAt(std::size_t(level), std::size_t(levels_));
        float p[8][kFloatsPerNode];
        float d[8][depth::kFloatsPerNode];
        for (int c = 0; c < 8; ++c) {
            node(level, cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2), p[c]);
            if (weighted) volume_->readDepth(level, cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2), d[c]);
        }
        float weights[8];
        for (int corner = 0; corner < 8; ++corner) {
            double w = 1.0;
            for (int a = 0; a < 3; ++a) w *= ((corner >> a) & 1) ? frac[a] : 1.0 - frac[a];
            weights[corner] = float(w);
        }
        if (weighted) {
            const float* depth[8];
            for (int c = 0; c < 8; ++c) depth[c] = d[c];
            query_detail::weightByDepth(weights, depth, float(frac[0]), float(frac[1]), float(frac[2]));
        }
        double sum[kFloatsPerNode] = {};
        for (int corner = 0; corner < 8; ++corner) {
            const int b[3] = {corner & 1, (corner >> 1) & 1, corner >> 2};
            double w = weighted ? double(weights[corner]) : 1.0;
            if (!weighted)
                for (int a = 0; a < 3; ++a) w *= b[a] ? frac[a] : 1.0 - frac[a];
            if (w == 0.0) continue;
            for (int f = 0; f < kFloatsPerNode; ++f) sum[f] += w * p[corner][f];
        }
        for (int c = 0; c < sh::kCoeffs; ++c) {
            const double a = sh::kCosineLobe[sh::bandOf(c)];
            out[c] = Rgb(float(sum[3 * c] / a), float(sum[3 * c + 1] / a), float(sum[3 * c + 2] / a));
        }
    }

private:
    // A leaf cell of a culled volume with a corner that is not stored (ShLevelsLookup's kCulled;
    // its level 0 is sparse only when culled).
    bool leafCulled(int level, const int cell[3]) const {
        if (!culled_ && level > 0) return false;
        for (int c = 0; c < 8; ++c)
            if (!volume_->nodeStored(level, cell[0] + (c & 1), cell[1] + ((c >> 1) & 1), cell[2] + (c >> 2))) return true;
        return false;
    }
    void node(int level, int i, int j, int k, float* out) const {
        volume_->readNode(level, i, j, k, out);
        for (int f = 0; f < kFloatsPerNode; ++f) out[f] = out[f] * float(sh::kCosineLobe[sh::bandOf(f / 3)]);
    }

    std::shared_ptr<const StreamedVolume> volume_;
    GridSpec grid_;
    OutsidePolicy outside_;
    int K_ = 1, levels_ = 1;
    bool culled_ = false;
    Vec3f origin_;
    float invSpacing_ = 1;
    bool depthWeights_ = false;
};
}  // namespace

namespace query_detail {

std::unique_ptr<VolumeLookup> streamingShLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0,
                                                OutsidePolicy outside) {
    if (volume->header().levels.size() > 1) return std::make_unique<StreamingLevelsLookup>(std::move(volume), grid0, outside);
    return std::make_unique<StreamingShLookup>(std::move(volume), grid0, outside);
}

}  // namespace query_detail
}  // namespace vdblight
