// Relightable SH volumes (beyond the paper): the nodes of a uniform grid are receivers of the
// same multi-bounce transfer as the samples (baked in multi_bounce.cpp), in SH order 2
// (radiance coefficients, the foundation's basis), so a new light position gives a new volume
// without a re-bake. The lights' direct radiance at the nodes is added at relight time with
// one exact shadow ray per node and light point.
#include <atomic>
#include <cstdint>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif
#include <cmath>

#include "prt_internal.h"
#include "vdblight/errors.h"
#include "vdblight/scene_origin.h"
#include "vdblight/sh.h"

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

namespace {

/// Adds the lights' direct SH radiance to out (9 Rgb per node). Light point by light point,
/// the nodes' shadow rays go in blocks of consecutive nodes (coherent 16-ray packets); each
/// node still adds its points in the same order, so the result does not depend on the blocks.
void addLightsAtNodes(const GridSpec& grid, const Tracer& tracer, const std::vector<PrtLight>& lights, Rgb* out) {
    std::vector<std::pair<PrtPointLight, Rgb>> points;
    for (const PrtLight& l : lights)
        for (const PrtPointLight& p : lightPoints(l)) points.push_back({p, l.intensity * p.weight});
    constexpr std::size_t kBlock = 256;
    Ray rays[kBlock];
    bool blocked[kBlock];
    uint32_t which[kBlock];
    float scales[kBlock];
    float y[sh::kCoeffs];
    const std::size_t nodes = grid.nodeCount();
    for (const auto& [p, intensity] : points) {
        const bool cosine = dot(p.normal, p.normal) > 0.0f;
        for (std::size_t n0 = 0; n0 < nodes; n0 += kBlock) {
            const std::size_t n1 = std::min(nodes, n0 + kBlock);
            std::size_t count = 0;
            for (std::size_t node = n0; node < n1; ++node) {
                const Vec3f x(grid.node(node));
                const Vec3f toLight = p.position - x;
                const float d2 = dot(toLight, toLight);
                if (!(d2 > 0.0f)) continue;
                float scale = 1.0f / d2;
                if (cosine) {
                    const float ce = -dot(p.normal, toLight / std::sqrt(d2));
                    if (ce <= 0.0f) continue;
                    scale *= ce;
                }
                rays[count] = Ray{x, toLight, 0.0f, kShadowEnd};
                which[count] = uint32_t(node - n0);
                scales[count] = scale;
                ++count;
            }
            tracer.occluded(rays, count, blocked);
            for (std::size_t i = 0; i < count; ++i) {
                if (blocked[i]) continue;
                const Vec3f& toLight = rays[i].direction;
                const Vec3f w = toLight / std::sqrt(dot(toLight, toLight));
                sh::evalUnrolled(w, y);
                const Rgb e = intensity * scales[i];
                Rgb* o = out + (n0 + which[i]) * sh::kCoeffs;
                for (int m = 0; m < sh::kCoeffs; ++m) o[m] += e * y[m];
            }
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
    placeVolumeInWorld(vol, prt.origin);  // relit in the scene's local frame (scene_origin.h)
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
