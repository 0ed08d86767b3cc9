// Relightable SH volumes (beyond the paper): the nodes of a uniform grid are receivers of the
// same multi-bounce transfer as the samples (baked in multi_bounce.cpp), in SH order 2
// (radiance coefficients, the foundation's basis), so a new light position gives a new volume
// without a re-bake. The lights' direct radiance at the nodes is added at relight time with
// one exact shadow ray per node and light point.
#include <atomic>
#include <cmath>

#include "prt_internal.h"
#include "vdblight/errors.h"
#include "vdblight/sh.h"

namespace vdblight {

using namespace prt_detail;

namespace {

}  // namespace

namespace {

/// out (count Rgb) += scale * transfer(direct): the relight's GEMV.
void addVolumeTransfer(const PrtData& prt, const std::vector<float>& direct, float scale, Rgb* out) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t count = prt.volumeGrid.nodeCount() * sh::kCoeffs;
    std::vector<float> coeffs;
    projectLightBases(prt, direct, coeffs);
    // The non-zero columns (cluster, k) of the transfer matrix and their coefficients.
    const bool quantised = !prt.volumeTransferQ.empty();
    std::vector<const float*> cols;
    std::vector<const int16_t*> qcols;
    std::vector<float> a;
    const std::size_t stride = std::size_t(prt.transferStride);
    const std::size_t floats = count * 3;
    for (std::size_t c = 0; c < s.clusters(); ++c)
        for (std::size_t k = 0; k < stride; ++k) {
            const float w = coeffs[c * stride + k] * scale;
            if (w == 0.0f) continue;
            if (quantised) {
                if (prt.volumeTransferScale[c][k] == 0.0f) continue;
                qcols.push_back(prt.volumeTransferQ[c].data() + k * floats);
                a.push_back(w * prt.volumeTransferScale[c][k]);
            } else {
                cols.push_back(reinterpret_cast<const float*>(prt.volumeTransfer[c].data() + k * count));
                a.push_back(w);
            }
        }
    // GEMV in row blocks that stay in L1 while every column streams through once.
    float* o = reinterpret_cast<float*>(out);
    constexpr std::size_t kBlock = 2048;
    for (std::size_t r0 = 0; r0 < floats; r0 += kBlock) {
        const std::size_t r1 = std::min(floats, r0 + kBlock);
        for (std::size_t j = 0; j < a.size(); ++j) {
            const float w = a[j];
            if (quantised) {
                const int16_t* col = qcols[j];
                for (std::size_t r = r0; r < r1; ++r) o[r] += w * float(col[r]);
            } else {
                const float* col = cols[j];
                for (std::size_t r = r0; r < r1; ++r) o[r] += w * col[r];
            }
        }
    }
}

}  // namespace

std::vector<Rgb> prtVolumeTransfer(const PrtData& prt, const std::vector<float>& direct) {
    if (!prt.hasVolume()) throw ValueError("this PRT file has no volume (bake with --volume-resolution)");
    if (direct.size() != prt.samples.size()) throw ValueError("direct lighting has the wrong number of samples");
    std::vector<Rgb> out(prt.volumeGrid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    addVolumeTransfer(prt, direct, 1.0f, out.data());
    return out;
}

namespace {

/// Adds the lights' direct SH radiance to out (9 Rgb per node).
void addLightsAtNodes(const GridSpec& grid, const Tracer& tracer, const std::vector<PrtLight>& lights, Rgb* out) {
    std::vector<std::pair<PrtPointLight, Rgb>> points;
    for (const PrtLight& l : lights)
        for (const PrtPointLight& p : lightPoints(l)) points.push_back({p, l.intensity * p.weight});
    float y[sh::kCoeffs];
    for (std::size_t node = 0; node < grid.nodeCount(); ++node) {
        const Vec3f x(grid.node(node));
        Rgb* o = out + node * sh::kCoeffs;
        for (const auto& [p, intensity] : points) {
            const Vec3f toLight = p.position - x;
            const float d2 = dot(toLight, toLight);
            if (!(d2 > 0.0f)) continue;
            const Vec3f w = toLight / std::sqrt(d2);
            float scale = 1.0f / d2;
            if (dot(p.normal, p.normal) > 0.0f) {
                const float ce = -dot(p.normal, w);
                if (ce <= 0.0f) continue;
                scale *= ce;
            }
            if (tracer.occluded(Ray{x, toLight, 0.0f, kShadowEnd})) continue;
            sh::evalUnrolled(w, y);
            const Rgb e = intensity * scale;
            for (int m = 0; m < sh::kCoeffs; ++m) o[m] += e * y[m];
        }
    }
}

}  // namespace

std::vector<Rgb> lightsAtNodes(const GridSpec& grid, const Tracer& tracer, const std::vector<PrtLight>& lights) {
    std::vector<Rgb> out(grid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    addLightsAtNodes(grid, tracer, lights, out.data());
    return out;
}

Volume relightVolume(const PrtData& prt, const std::vector<PrtLight>& lights, const Tracer* tracer) {
    if (!prt.hasVolume()) throw ValueError("this PRT file has no volume (bake with --volume-resolution)");
    const std::size_t count = prt.volumeGrid.nodeCount() * sh::kCoeffs;
    Volume vol;
    vol.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid = prt.volumeGrid;
    level.data.assign(count * 3, 0.0f);
    static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb is three packed floats");
    Rgb* total = reinterpret_cast<Rgb*>(level.data.data());
    for (const PrtLight& light : lights) {
        const std::vector<float> direct = prtDirectLight(prt, light);
        const Rgb& I = light.intensity;
        if (I.x == I.y && I.y == I.z) {
            addVolumeTransfer(prt, direct, I.x, total);  // grey light: straight into the volume
        } else {
            const std::vector<Rgb> v = prtVolumeTransfer(prt, direct);
            for (std::size_t i = 0; i < count; ++i) total[i] += I * v[i];
        }
    }
    if (tracer) addLightsAtNodes(prt.volumeGrid, *tracer, lights, total);
    vol.levels.push_back(std::move(level));
    vol.meta["method"] = std::string("prt_relight");
    const std::string bounces = std::to_string(prt.bounces) + (prt.bounces == 1 ? " bounce" : " bounces");
    vol.meta["content"] = tracer ? std::string("direct radiance of the lights (shadow rays) + indirect radiance of ") +
                                       bounces + " from the PRT samples"
                                 : std::string("indirect radiance of ") + bounces +
                                       " from the PRT samples; no direct light";
    vol.meta["bounces"] = int64_t(prt.bounces);
    vol.meta["direct_light"] = tracer != nullptr;
    vol.meta["scene"] = prt.sceneName;
    vol.meta["scene_hash"] = prt.sceneHash;
    vol.meta["lights"] = int64_t(lights.size());
    return vol;
}

std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<float>& direct, int threads) {
    if (direct.size() != s.size()) throw ValueError("direct lighting has the wrong number of samples");
    std::vector<Rgb> out(grid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    parallelFor(grid.nodeCount(), threads, [&](std::size_t node) {
        const Vec3f x(grid.node(node));
        double acc[sh::kCoeffs][3] = {};
        float y[sh::kCoeffs];
        for (std::size_t j = 0; j < s.size(); ++j) {
            float omega;
            if (direct[j] == 0.0f || !senderShFromNode(s, tracer, x, j, y, omega)) continue;
            const Rgbd w = Rgbd(s.albedo[j]) * (kInvPi * direct[j]);
            for (int m = 0; m < sh::kCoeffs; ++m) {
                acc[m][0] += w.x * y[m];
                acc[m][1] += w.y * y[m];
                acc[m][2] += w.z * y[m];
            }
        }
        for (int m = 0; m < sh::kCoeffs; ++m)
            out[node * sh::kCoeffs + std::size_t(m)] = Rgb{float(acc[m][0]), float(acc[m][1]), float(acc[m][2])};
    });
    return out;
}

std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<Rgb>& senderIrradiance, int threads) {
    if (senderIrradiance.size() != s.size()) throw ValueError("sender irradiance has the wrong number of samples");
    std::vector<Rgb> out(grid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    parallelFor(grid.nodeCount(), threads, [&](std::size_t node) {
        const Vec3f x(grid.node(node));
        double acc[sh::kCoeffs][3] = {};
        float y[sh::kCoeffs];
        for (std::size_t j = 0; j < s.size(); ++j) {
            const Rgb& e = senderIrradiance[j];
            float omega;
            if ((e.x == 0.0f && e.y == 0.0f && e.z == 0.0f) || !senderShFromNode(s, tracer, x, j, y, omega)) continue;
            const Rgbd w = Rgbd(s.albedo[j]) * kInvPi;
            const Rgbd we{w.x * e.x, w.y * e.y, w.z * e.z};
            for (int m = 0; m < sh::kCoeffs; ++m) {
                acc[m][0] += we.x * y[m];
                acc[m][1] += we.y * y[m];
                acc[m][2] += we.z * y[m];
            }
        }
        for (int m = 0; m < sh::kCoeffs; ++m)
            out[node * sh::kCoeffs + std::size_t(m)] = Rgb{float(acc[m][0]), float(acc[m][1]), float(acc[m][2])};
    });
    return out;
}

}  // namespace vdblight
