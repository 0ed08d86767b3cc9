// Relightable SH volumes (beyond the paper): the nodes of a uniform grid are receivers of the
// same multi-bounce transfer as the samples (baked in multi_bounce.cpp), in SH order 2
// (radiance coefficients, the foundation's basis), so a new light position gives a new volume
// without a re-bake. The lights' direct light is not in the SH: a relit volume with the scene
// is a `--direct occlusion` volume (visibility channels by the shared bake_direct.h).
#include <atomic>
#include <cstdint>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif
#include <cmath>

#include "prt_internal.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/core/errors.h"
#include "vdblight/light/light.h"
#include "scene/scene_origin.h"
#include "basis/sh.h"

namespace vdblight {

using namespace prt_detail;

namespace {

#if defined(__x86_64__) && defined(__GNUC__)
/// o[r] += a[j] * cols[j][r] for r in [0, rows), j = 0, 1, ... in that order for every r (the
/// same adds in the same order as the portable loop, so the same bits), 32 rows at a time
/// held in AVX2 registers while every column passes once: no per-column load/store of o.
/// Multiplies and adds stay separate (no FMA).
__attribute__((target("avx2"))) void gemvQ16Avx2(const int16_t* const* cols, const float* a, std::size_t ncols,
                                                 std::size_t rows, float* o) {
    std::size_t r = 0;
    for (; r + 32 <= rows; r += 32) {
        __m256 s0 = _mm256_loadu_ps(o + r), s1 = _mm256_loadu_ps(o + r + 8);
        __m256 s2 = _mm256_loadu_ps(o + r + 16), s3 = _mm256_loadu_ps(o + r + 24);
        for (std::size_t j = 0; j < ncols; ++j) {
            const __m256 w = _mm256_set1_ps(a[j]);
            const int16_t* c = cols[j] + r;
            const __m256i q01 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c));
            const __m256i q23 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c + 16));
            const __m256 v0 = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_castsi256_si128(q01)));
            const __m256 v1 = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_extracti128_si256(q01, 1)));
            const __m256 v2 = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_castsi256_si128(q23)));
            const __m256 v3 = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_extracti128_si256(q23, 1)));
            s0 = _mm256_add_ps(s0, _mm256_mul_ps(w, v0));
            s1 = _mm256_add_ps(s1, _mm256_mul_ps(w, v1));
            s2 = _mm256_add_ps(s2, _mm256_mul_ps(w, v2));
            s3 = _mm256_add_ps(s3, _mm256_mul_ps(w, v3));
        }
        _mm256_storeu_ps(o + r, s0);
        _mm256_storeu_ps(o + r + 8, s1);
        _mm256_storeu_ps(o + r + 16, s2);
        _mm256_storeu_ps(o + r + 24, s3);
    }
    for (; r < rows; ++r) {
        float acc = o[r];
        for (std::size_t j = 0; j < ncols; ++j) acc += a[j] * float(cols[j][r]);
        o[r] = acc;
    }
}

bool haveAvx2() {
    static const bool yes = __builtin_cpu_supports("avx2");
    return yes;
}
#endif

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
    float* o = reinterpret_cast<float*>(out);
#if defined(__x86_64__) && defined(__GNUC__)
    if (quantised && haveAvx2()) {
        gemvQ16Avx2(qcols.data(), a.data(), a.size(), floats, o);
        return;
    }
#endif
    // GEMV in row blocks that stay in L1 while every column streams through once.
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

Volume relightVolume(const PrtData& prt, const std::vector<DirectLight>& lights, const Scene* scene,
                     const Tracer* tracer, const PrtRelightOptions& options) {
    if (!prt.hasVolume()) throw ValueError("this PRT file has no volume (bake with --volume-resolution)");
    if ((scene == nullptr) != (tracer == nullptr))
        throw ValueError("relightVolume: give both the baked scene and its tracer, or neither");
    const std::size_t count = prt.volumeGrid.nodeCount() * sh::kCoeffs;
    Volume vol;
    vol.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid = prt.volumeGrid;
    level.data.assign(count * 3, 0.0f);
    static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb is three packed floats");
    Rgb* total = reinterpret_cast<Rgb*>(level.data.data());
    for (const auto& [I, direct] : directByColour(prt, lights, options.areaSamples)) {
        if (I.x == I.y && I.y == I.z) {
            addVolumeTransfer(prt, direct, I.x, total);  // grey light: straight into the volume
        } else {
            const std::vector<Rgb> v = prtVolumeTransfer(prt, direct);
            for (std::size_t i = 0; i < count; ++i) total[i] += I * v[i];
        }
    }
    vol.levels.push_back(std::move(level));
    if (scene) {
        // The lights' direct light as a baked occlusion volume holds it: listed, with per-node
        // visibility channels from the shared visibility code (bake_direct.h).
        DirectPlan plan;
        plan.mode = DirectMode::Occlusion;
        for (const DirectLight& l : lights) plan.lights.push_back(freeLight(l));
        DirectOptions direct;
        direct.mode = DirectMode::Occlusion;
        direct.visibilitySamples = options.visibilitySamples;
        direct.seed = options.seed;
        direct.threads = options.threads;
        bakeLightVisibility(*scene, *tracer, plan, direct, vol);
    }
    placeVolumeInWorld(vol, prt.origin);  // relit in the scene's local frame (scene_origin.h); lights too
    vol.meta["method"] = std::string("prt_relight");
    const std::string bounces = std::to_string(prt.bounces) + (prt.bounces == 1 ? " bounce" : " bounces");
    vol.meta["content"] = scene ? "indirect radiance of " + bounces +
                                      " from the PRT samples; the lights' direct light is added at lookup (direct "
                                      "occlusion: exact irradiance times the visibility channels)"
                                : std::string("indirect radiance of ") + bounces +
                                      " from the PRT samples; no direct light";
    vol.meta["bounces"] = int64_t(prt.bounces);
    vol.meta["direct_light"] = scene != nullptr;
    vol.meta["scene"] = prt.sceneName;
    vol.meta["scene_hash"] = prt.sceneHash;
    vol.meta["lights"] = int64_t(lights.size());
    return vol;
}

namespace {

/// The uncompressed gather at the nodes: sender j adds weight(j) * Y(w) * solid angle, where
/// weight(j, we) sets the sender's outgoing RGB radiance (double) and returns false for a
/// dark sender (skipped before its ray).
template <typename Weight>
std::vector<Rgb> gatherSenders(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer, int threads,
                               Weight&& weight) {
    std::vector<Rgb> out(grid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    parallelFor(grid.nodeCount(), threads, [&](std::size_t node) {
        const Vec3f x(grid.node(node));
        double acc[sh::kCoeffs][3] = {};
        float y[sh::kCoeffs];
        for (std::size_t j = 0; j < s.size(); ++j) {
            Rgbd w;
            float omega;
            if (!weight(j, w) || !senderShFromNode(s, tracer, x, j, y, omega)) continue;
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

}  // namespace

std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<float>& direct, int threads) {
    if (direct.size() != s.size()) throw ValueError("direct lighting has the wrong number of samples");
    return gatherSenders(s, grid, tracer, threads, [&](std::size_t j, Rgbd& w) {
        if (direct[j] == 0.0f) return false;
        w = Rgbd(s.albedo[j]) * (kInvPi * direct[j]);
        return true;
    });
}

std::vector<Rgb> referenceVolume(const SurfaceSamples& s, const GridSpec& grid, const Tracer& tracer,
                                 const std::vector<Rgb>& senderIrradiance, int threads) {
    if (senderIrradiance.size() != s.size()) throw ValueError("sender irradiance has the wrong number of samples");
    return gatherSenders(s, grid, tracer, threads, [&](std::size_t j, Rgbd& w) {
        const Rgb& e = senderIrradiance[j];
        if (e.x == 0.0f && e.y == 0.0f && e.z == 0.0f) return false;
        const Rgbd a = Rgbd(s.albedo[j]) * kInvPi;
        w = Rgbd{a.x * e.x, a.y * e.y, a.z * e.z};
        return true;
    });
}

}  // namespace vdblight
