#include "surface_cache.h"

#include <algorithm>
#include <cmath>

#include "pass_metadata.h"
#include "vdblight/core/errors.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/trace/trace.h"

namespace vdblight {
namespace bake_detail {

VolumeSurfaceCache::VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const float* reflected,
                                       std::size_t stride)
    : tracer_(tracer), grid_(grid), coeffs_(reflected), stride_(stride) {
    for (int j = 0; j < sh::kCoeffs; ++j) lobe_[j] = float(sh::kCosineLobe[sh::bandOf(j)]);
}

VolumeSurfaceCache::VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, const std::vector<Rgb>& reflected)
    : VolumeSurfaceCache(tracer, grid, nullptr) {
    own_.resize(reflected.size() * 3);
    for (std::size_t i = 0; i < reflected.size(); ++i)
        for (int c = 0; c < 3; ++c) own_[3 * i + std::size_t(c)] = reflected[i][c];
    coeffs_ = own_.data();
}

bool VolumeSurfaceCache::irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const {
    float y[sh::kCoeffs];
    sh::evalUnrolled(n, y);
    Rgb sum{0, 0, 0};
    const float weight = forEachVisibleNode(tracer_, grid_, p, n, rays, [&](std::size_t node, const Vec3f&, float w) {
        const float* c27 = coeffs_ + node * stride_;
        Rgb e{0, 0, 0};
        // (c A_l) y_l: the same float operations as multiplying by A_l first.
        for (int j = 0; j < sh::kCoeffs; ++j) e += (Rgb(c27[3 * j], c27[3 * j + 1], c27[3 * j + 2]) * lobe_[j]) * y[j];
        sum += e * w;
    });
    if (!(weight > 0)) return false;
    out = sum / weight;
    out = Rgb(std::max(0.0f, out.x), std::max(0.0f, out.y), std::max(0.0f, out.z));  // SH ringing
    return true;
}

PassRange stagePasses(int probePasses, int stage, const Volume* input, const GridSpec& grid, bool depthMoments) {
    if (stage < 0) return {0, probePasses};
    if (stage > probePasses)
        throw ValueError("stage " + std::to_string(stage) + " does not exist: the bake has " +
                         std::to_string(probePasses + 1) + " stages (0.." + std::to_string(probePasses) + ")");
    if ((stage > 0) != (input != nullptr))
        throw ValueError(stage > 0 ? "stage " + std::to_string(stage) + " needs the merged volume of stage " +
                                         std::to_string(stage - 1)
                                   : std::string("stage 0 reads no stage input"));
    if (input) {
        const VolumeLevel* level = input->levels.size() == 1 ? &input->levels[0] : nullptr;
        if (!input->basis.sameKind(probeStageBasis()) || !level || level->sparse() || level->grid.nx != grid.nx ||
            level->grid.ny != grid.ny || level->grid.nz != grid.nz || std::abs(level->grid.spacing - grid.spacing) > 1e-9 * grid.spacing)
            throw ValueError("the stage input is not a probe stage volume of this grid");
        if (metaNumber(input->meta, "probe_stage", -1) != stage - 1 || metaNumber(input->meta, "probe_passes", -1) != probePasses)
            throw ValueError("the stage input is stage " + std::to_string(int(metaNumber(input->meta, "probe_stage", -1))) +
                             " of a bake with " + std::to_string(int(metaNumber(input->meta, "probe_passes", -1))) +
                             " probe passes, not stage " + std::to_string(stage - 1) + " of " + std::to_string(probePasses));
        if (depthMoments && !level->hasDepth()) throw ValueError("the stage input has no depth moments");
    }
    return {stage, stage};
}


Volume stageVolume(const VolumeLevel& shape, const std::vector<Rgb>& reflected, std::vector<float> depth, Metadata meta,
                   int stage, int probePasses) {
    Volume v;
    v.basis = probeStageBasis();
    v.levels.resize(1);
    v.levels[0].grid = shape.grid;
    v.levels[0].windowFirst = shape.windowFirst;
    v.levels[0].windowNodes = shape.windowNodes;
    v.levels[0].data.resize(reflected.size() * 3);
    for (std::size_t i = 0; i < reflected.size(); ++i)
        for (int c = 0; c < 3; ++c) v.levels[0].data[3 * i + std::size_t(c)] = reflected[i][c];
    v.levels[0].depth = std::move(depth);
    v.meta = std::move(meta);
    PassMetadata(v.meta)
        .count("probe_stage", int64_t(stage))
        .count("probe_passes", int64_t(probePasses))
        .text("probe_stage_note",
              "the reflected light and sky of a probe-to-probe pass per node (reflected_sh_*), read by the next stage's "
              "tiles; not a volume to look up");
    return v;
}

}  // namespace bake_detail
}  // namespace vdblight
