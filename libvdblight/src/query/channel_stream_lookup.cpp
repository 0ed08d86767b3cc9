// ChannelLookup (channel_lookup.cpp) on a streamed volume: the same locate, descent, weights
// and summation order, with its brick tables replaced by the refined-cell masks of the file's
// topology and its node arrays by voxels read through StreamedVolume, so that the answers are
// the same bits as the in-memory lookup of an `sh:N` volume (ChannelLookup, or for `sh:4` on
// one level ShFourUniformLookup, which gives ChannelLookup's bits).
#include <algorithm>
#include <vector>

#include "depth_weights.h"
#include "lattice_locate.h"
#include "shared_cell.h"
#include "stream_lookups.h"
#include "basis/sh.h"

namespace vdblight::query_detail {

namespace {

class StreamingChannelLookup final : public VolumeLookup, public SharesCell {
public:
    StreamingChannelLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0, OutsidePolicy outside,
                           std::unique_ptr<Basis> basis)
        : volume_(std::move(volume)), basis_(std::move(basis)), grid_(grid0), outside_(outside) {
        const Volume& h = volume_->header();
        if (basis_->channelCount() != h.basis.channelCount())
            throw FormatError("basis '" + basis_->desc().kind + "' has " + std::to_string(basis_->channelCount()) +
                              " channels, the volume " + std::to_string(h.basis.channelCount()));
        if (basis_->maxTerms() > kMaxTerms)
            throw FormatError("basis '" + basis_->desc().kind + "' evaluates more than " + std::to_string(kMaxTerms) + " terms");
        K_ = h.refineFactor();
        levels_ = h.levels.size();
        // ChannelLookup builds no child tables (so never descends) on one level or a flat axis.
        descend_ = levels_ > 1 && grid_.nx >= 2 && grid_.ny >= 2 && grid_.nz >= 2;
        origin_ = Vec3f(grid_.origin);
        invSpacing_ = float(1.0 / grid_.spacing);
        floatsPerNode_ = std::size_t(basis_->floatsPerNode());
        hasDepth_ = depthWeights_ = volume_->hasDepth();
        // Offers its cell where the in-memory lookup does (ShFourUniformLookup: sh:4 on one
        // level), so that OcclusionLookup and its streamed twin blend the visibility alike.
        sharesCell_ = !h.basis.isSh2() && h.basis.shOrder() == 4 && levels_ == 1;
    }

    Rgb irradiance(const Vec3f& x, const Vec3f& d) const override { return blendIrradiance(x, d, nullptr); }
    Rgb irradianceSharingCell(const Vec3f& x, const Vec3f& d, SharedCell& cell) const override {
        return blendIrradiance(x, d, &cell);
    }
    bool sharesCell() const override { return sharesCell_; }

    Bounds bounds() const override { return grid_.nodeBounds(); }

    void channelValues(const Vec3d& x, float* out) const override {
        // In double, as ChannelLookup::channelValues: exact at a node position.
        const double g[3] = {(x.x - grid_.origin.x) / grid_.spacing, (x.y - grid_.origin.y) / grid_.spacing,
                             (x.z - grid_.origin.z) / grid_.spacing};
        blendChannels(g, basis_->channelCount(), out);
    }

    void shRadiance(const Vec3d& x, Rgb out[9]) const override {
        if (basis_->shCoefficients() < sh::kCoeffs) VolumeLookup::shRadiance(x, out);  // throws
        // The first nine channels of channelValues: each float is blended on its own, so
        // reading only those nine (and their leaves, a third of sh:4's) gives the same bits.
        const double g[3] = {(x.x - grid_.origin.x) / grid_.spacing, (x.y - grid_.origin.y) / grid_.spacing,
                             (x.z - grid_.origin.z) / grid_.spacing};
        float values[3 * sh::kCoeffs];
        blendChannels(g, sh::kCoeffs, values);
        for (int j = 0; j < sh::kCoeffs; ++j) out[j] = Rgb(values[3 * j], values[3 * j + 1], values[3 * j + 2]);
    }

    void setDepthWeights(bool on) override { depthWeights_ = on && hasDepth_; }
    bool depthWeighted() const override { return depthWeights_; }

private:
    static constexpr int kMaxTerms = 64;  // ChannelLookup::kMaxTerms

    /// The eight corner nodes' values (the channels read, 3 floats each, corner c = x bit 0,
    /// y bit 1, z bit 2) and their weights.
    struct Corners {
        std::vector<float> values;
        float weight[8];
    };

    /// irradiance, and in `cell` (if not null; one level only) the corners and weights blended.
    Rgb blendIrradiance(const Vec3f& x, const Vec3f& d, SharedCell* cell) const {
        int channels[kMaxTerms];
        float bw[kMaxTerms];
        const int nb = basis_->terms(d, channels, bw);
        const Vec3f gv = (x - origin_) * invSpacing_;
        checkInside(gv, grid_, x, outside_);
        const float g[3] = {gv.x, gv.y, gv.z};
        Corners corners;
        locate(g, corners, basis_->channelCount(), cell);
        // As ChannelLookup::sumTerms: each term's channel blended over the corners, then weighted.
        Rgb e{0, 0, 0};
        for (int b = 0; b < nb; ++b) {
            const std::size_t f = std::size_t(3 * channels[b]);
            Rgb t{0, 0, 0};
            for (int c = 0; c < 8; ++c) {
                const float* p = corners.values.data() + c * floatsPerNode_;
                t += Rgb(p[f], p[f + 1], p[f + 2]) * corners.weight[c];
            }
            e += t * bw[b];
        }
        return e;
    }

    /// ChannelLookup::channelValues for the first `channels` channels: located in double, each
    /// float summed over the corners in order.
    void blendChannels(const double g[3], int channels, float* out) const {
        Corners corners;
        locate(g, corners, channels);
        const std::size_t floats = std::size_t(channels) * 3;
        std::fill(out, out + floats, 0.0f);
        for (int c = 0; c < 8; ++c) {
            const float* p = corners.values.data() + c * floats;
            for (std::size_t f = 0; f < floats; ++f) out[f] += corners.weight[c] * p[f];
        }
    }

    /// ChannelLookup::locate: the cell of the level-0 lattice coordinate g (clamped into the
    /// box), the descent through refined cells, trilinear weights in T and, in cells of the
    /// finest level, the depth weights.
    template <class T>
    void locate(const T g[3], Corners& out, int channels, SharedCell* shared = nullptr) const {
        int cell[3] = {0, 0, 0};
        T f[3] = {0, 0, 0};
        const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
        for (int a = 0; a < 3; ++a)
            if (dims[a] >= 2) splitCell(g[a], dims[a], cell[a], f[a]);  // a flat axis: one node, no interpolation
        int level = 0;
        if (descend_)
            while (volume_->cellRefined(level, cell[0], cell[1], cell[2])) {
                ++level;
                for (int a = 0; a < 3; ++a) {
                    int local;
                    splitLocal(f[a], K_, local);
                    cell[a] = cell[a] * K_ + local;
                }
            }
        // Level 0 steps along an axis only if it has two nodes; finer levels always do.
        const int step[3] = {level > 0 || dims[0] > 1, level > 0 || dims[1] > 1, level > 0 || dims[2] > 1};
        int node[8][3];
        const std::size_t floats = std::size_t(channels) * 3;
        out.values.resize(8 * floats);
        for (int c = 0; c < 8; ++c) {
            for (int a = 0; a < 3; ++a) node[c][a] = cell[a] + ((c >> a) & 1) * step[a];
            volume_->readChannels(level, node[c][0], node[c][1], node[c][2], channels, out.values.data() + c * floats);
        }
        const T wx[2] = {1 - f[0], f[0]}, wy[2] = {1 - f[1], f[1]}, wz[2] = {1 - f[2], f[2]};
        for (int c = 0; c < 8; ++c) out.weight[c] = float(wx[c & 1] * wy[(c >> 1) & 1] * wz[c >> 2]);
        if (depthWeights_ && depthWeightsApplyAt(std::size_t(level), levels_)) {
            float d[8][depth::kFloatsPerNode];
            const float* depth[8];
            for (int c = 0; c < 8; ++c) {
                volume_->readDepth(level, node[c][0], node[c][1], node[c][2], d[c]);
                depth[c] = d[c];
            }
            weightByDepth(out.weight, depth, float(f[0]), float(f[1]), float(f[2]));
        }
        if (shared) {
            for (int a = 0; a < 3; ++a) {
                shared->lower[a] = cell[a];
                shared->step[a] = step[a];
            }
            for (int c = 0; c < 8; ++c) shared->weight[c] = out.weight[c];
        }
    }

    std::shared_ptr<const StreamedVolume> volume_;
    std::unique_ptr<Basis> basis_;
    GridSpec grid_;
    OutsidePolicy outside_;
    int K_ = 1;
    std::size_t levels_ = 1;
    bool descend_ = false;
    Vec3f origin_;
    float invSpacing_ = 1;
    std::size_t floatsPerNode_ = 0;
    bool hasDepth_ = false, depthWeights_ = false;
    bool sharesCell_ = false;
};

}  // namespace

std::unique_ptr<VolumeLookup> streamingChannelLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0,
                                                     OutsidePolicy outside, std::unique_ptr<Basis> basis) {
    return std::make_unique<StreamingChannelLookup>(std::move(volume), grid0, outside, std::move(basis));
}

}  // namespace vdblight::query_detail
