// Run time (Leonhardt & Bohn section 5): visibility -> direct light -> projection ->
// transfer -> indirect, plus the uncompressed references it is tested against.
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "pca.h"
#include "prt_internal.h"
#include "vdblight/core/errors.h"
#include "vdblight/light/light.h"

namespace vdblight {

using namespace prt_detail;

namespace {

/// depth[k] = r_k[0] + sum over c (in order) of coeffs[c] * r_k[c + 1], for the four rows:
/// four independent chains, each with the same adds in the same order as a loop of its own
/// (so the same bits; no FMA). With SSE the four chains are the lanes of one register.
inline void reconstructFour(const float* r0, const float* r1, const float* r2, const float* r3, const float* coeffs,
                            int count, float depth[4]) {
#if defined(__SSE2__)
    __m128 d = _mm_setr_ps(r0[0], r1[0], r2[0], r3[0]);
    int c = 0;
    for (; c + 4 <= count; c += 4) {
        __m128 a0 = _mm_loadu_ps(r0 + c + 1), a1 = _mm_loadu_ps(r1 + c + 1);
        __m128 a2 = _mm_loadu_ps(r2 + c + 1), a3 = _mm_loadu_ps(r3 + c + 1);
        _MM_TRANSPOSE4_PS(a0, a1, a2, a3);  // a_j = (r0[c+1+j], r1[c+1+j], r2[c+1+j], r3[c+1+j])
        d = _mm_add_ps(d, _mm_mul_ps(_mm_set1_ps(coeffs[c]), a0));
        d = _mm_add_ps(d, _mm_mul_ps(_mm_set1_ps(coeffs[c + 1]), a1));
        d = _mm_add_ps(d, _mm_mul_ps(_mm_set1_ps(coeffs[c + 2]), a2));
        d = _mm_add_ps(d, _mm_mul_ps(_mm_set1_ps(coeffs[c + 3]), a3));
    }
    for (; c < count; ++c)
        d = _mm_add_ps(d, _mm_mul_ps(_mm_set1_ps(coeffs[c]), _mm_setr_ps(r0[c + 1], r1[c + 1], r2[c + 1], r3[c + 1])));
    _mm_storeu_ps(depth, d);
#else
    float d0 = r0[0], d1 = r1[0], d2 = r2[0], d3 = r3[0];
    for (int c = 0; c < count; ++c) {
        const float a = coeffs[c];
        d0 += a * r0[c + 1];
        d1 += a * r1[c + 1];
        d2 += a * r2[c + 1];
        d3 += a * r3[c + 1];
    }
    depth[0] = d0, depth[1] = d1, depth[2] = d2, depth[3] = d3;
#endif
}

/// Adds weight * emission * compressed direct unit irradiance of a point emitter to out.
void addDirectPoint(const PrtData& prt, const PrtPointLight& pl, float* out) {
    const SurfaceSamples& s = prt.samples;
    const int g = prt.visGrid;
    const Vec3f& l = pl.position;
    const bool isotropic = !(dot(pl.normal, pl.normal) > 0.0f) && !pl.spot;
    for (std::size_t i = 0; i < s.size(); ++i) {
        float dist = 0;
        float e = unshadowedUnit(s.position[i], s.normal[i], l, &dist);
        if (e <= 0.0f) continue;
        const Vec3f w = (l - s.position[i]) / dist;
        if (!isotropic) {
            const float ce = pl.emission(w * -1.0f);
            if (ce <= 0.0f) continue;
            e *= ce;
        }
        Vec3f t1, t2;
        orthonormalBasis(s.normal[i], t1, t2);
        const Vec3f local{dot(w, t1), dot(w, t2), dot(w, s.normal[i])};
        int idx[4];
        float wt[4];
        visibilityNeighbours(g, local, idx, wt);
        const PcaBasis& basis = prt.visBasis[s.cluster[i]];
        const float* coeffs = prt.visCoeffs.data() + i * std::size_t(prt.visCoeffStride);
        float vis = 0;
        if (!prt.visByDirection.empty()) {
            const std::size_t row = std::size_t(basis.count) + 1;
            const float* byDir = prt.visByDirection[s.cluster[i]].data();
            // The four depth reconstructions as four independent chains in one loop (each in
            // the same order as a loop of its own, so the same bits): one dependent chain of
            // 4 * count adds was the cost.
            const float* r0 = byDir + std::size_t(idx[0]) * row;
            const float* r1 = byDir + std::size_t(idx[1]) * row;
            const float* r2 = byDir + std::size_t(idx[2]) * row;
            const float* r3 = byDir + std::size_t(idx[3]) * row;
            float depth[4];
            reconstructFour(r0, r1, r2, r3, coeffs, basis.count, depth);
            for (int k = 0; k < 4; ++k)
                if (wt[k] > 0.0f && dist <= depth[k]) vis += wt[k];
        } else {
            for (int k = 0; k < 4; ++k) {
                if (wt[k] <= 0.0f) continue;
                if (dist <= pcaReconstructAt(basis, coeffs, idx[k])) vis += wt[k];
            }
        }
        out[i] += pl.weight * e * vis;
    }
}

}  // namespace

/// The light-basis coefficients of every cluster for a direct unit irradiance (stride
/// values per cluster, [0] = 1 for the mean vector).
void projectLightBases(const PrtData& prt, const std::vector<float>& direct, std::vector<float>& coeffs) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t stride = std::size_t(prt.transferStride);
    coeffs.assign(s.clusters() * stride, 0.0f);
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const std::vector<float>& mean = prt.lightBasis[c].mean;
        // The mean vector's row is zero with the default (uncentred) basis: skip it.
        coeffs[c * stride] = std::any_of(mean.begin(), mean.end(), [](float v) { return v != 0.0f; }) ? 1.0f : 0.0f;
        pcaProject(prt.lightBasis[c], direct.data() + s.clusterBegin[c], coeffs.data() + c * stride + 1);
    }
}


void prepareRelight(PrtData& prt) {
    prt.volumeTransferQ.assign(prt.volumeTransfer.size(), {});
    prt.volumeTransferScale.assign(prt.volumeTransfer.size(), {});
    const std::size_t stride = std::size_t(prt.transferStride);
    for (std::size_t c = 0; c < prt.volumeTransfer.size(); ++c) {
        const float* v = reinterpret_cast<const float*>(prt.volumeTransfer[c].data());
        const std::size_t col = prt.volumeTransfer[c].size() * 3 / stride;
        std::vector<int16_t>& q = prt.volumeTransferQ[c];
        std::vector<float>& scale = prt.volumeTransferScale[c];
        q.resize(col * stride);
        scale.resize(stride);
        for (std::size_t k = 0; k < stride; ++k) {
            float m = 0;
            for (std::size_t r = 0; r < col; ++r) m = std::max(m, std::abs(v[k * col + r]));
            scale[k] = m > 0 ? m / 32767.0f : 0.0f;
            const float inv = m > 0 ? 32767.0f / m : 0.0f;
            for (std::size_t r = 0; r < col; ++r) q[k * col + r] = int16_t(std::lround(v[k * col + r] * inv));
        }
    }
    prt.visByDirection.assign(prt.visBasis.size(), {});
    for (std::size_t c = 0; c < prt.visBasis.size(); ++c) {
        const PcaBasis& b = prt.visBasis[c];
        const std::size_t row = std::size_t(b.count) + 1;
        std::vector<float>& out = prt.visByDirection[c];
        out.resize(std::size_t(b.dim) * row);
        for (int t = 0; t < b.dim; ++t) {
            out[std::size_t(t) * row] = b.mean[std::size_t(t)];
            for (int k = 0; k < b.count; ++k)
                out[std::size_t(t) * row + std::size_t(k) + 1] = b.vectors[std::size_t(k) * std::size_t(b.dim) + std::size_t(t)];
        }
    }
}

float PrtPointLight::emission(const Vec3f& w) const {
    float e = 1.0f;
    if (dot(normal, normal) > 0.0f) {
        e = dot(normal, w);
        if (twoSided) e = std::abs(e);
        if (e <= 0.0f) return 0.0f;
    }
    if (spot) e *= float(spotFalloff(*spot, Vec3d(w)));
    return e;
}

std::vector<PrtPointLight> pointEmitters(const DirectLight& light, int areaSamples) {
    using Kind = DirectLight::Kind;
    if (light.kind == Kind::Directional)
        throw ValueError("PRT relighting takes point, spot, polygon and mesh lights, not directional ones: its "
                         "compressed visibility knows the depth to points at a finite distance, not to infinity");
    PrtPointLight p;
    p.position = Vec3f(light.position);
    if (light.kind == Kind::Spot) p.spot = &light;
    if (light.kind == Kind::Point || light.kind == Kind::Spot) return {p};
    const int m = std::max(1, areaSamples);
    const float cells = float(m * m);
    std::vector<PrtPointLight> out;
    p.twoSided = light.twoSided;
    if (light.kind == Kind::Polygon && light.loops.size() == 1 && light.loops[0].size() == 4) {
        // A parallelogram (a square panel): the cell centres of an m x m grid on it.
        const std::vector<Vec3d>& q = light.loops[0];
        const Vec3d e1 = q[1] - q[0], e3 = q[3] - q[0];
        const double area = dot(cross(e1, e3), light.normal);
        if (length(q[0] + q[2] - q[1] - q[3]) <= 1e-9 * (length(e1) + length(e3)) && area > 0) {
            p.normal = Vec3f(light.normal);
            p.weight = float(area / double(cells));
            for (int a = 0; a < m * m; ++a) {
                p.position = Vec3f(q[0] + e1 * ((double(a % m) + 0.5) / m) + e3 * ((double(a / m) + 0.5) / m));
                out.push_back(p);
            }
            return out;
        }
    }
    // Any other shape: the grid's cell centres through the light's own sampling map.
    const SceneLight free = freeLight(light);
    for (int a = 0; a < m * m; ++a) {
        const PolygonLightPoint lp =
            samplePolygonLight(free, nullptr, (float(a % m) + 0.5f) / float(m), (float(a / m) + 0.5f) / float(m));
        p.position = lp.position;
        p.normal = lp.normal;
        p.weight = float(double(lp.sign) * free.sampledArea / double(cells));
        out.push_back(p);
    }
    return out;
}

std::vector<float> prtDirectLight(const PrtData& prt, const DirectLight& light, int areaSamples) {
    std::vector<float> out(prt.samples.size(), 0.0f);
    for (const PrtPointLight& p : pointEmitters(light, areaSamples)) addDirectPoint(prt, p, out.data());
    return out;
}

std::vector<float> prtDirectUnit(const PrtData& prt, const Vec3f& l) {
    DirectLight point;
    point.position = Vec3d(l);
    point.value = Rgb(1, 1, 1);
    return prtDirectLight(prt, point);
}

std::vector<Rgb> prtTransfer(const PrtData& prt, const std::vector<float>& direct) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t n = s.size();
    if (direct.size() != n) throw ValueError("direct lighting has the wrong number of samples");
    std::vector<Rgb> out(n, Rgb{0, 0, 0});
    std::vector<float> coeffs;
    projectLightBases(prt, direct, coeffs);
    const std::size_t stride = std::size_t(prt.transferStride);
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const std::vector<Rgb>& t = prt.transfer[c];
        for (std::size_t k = 0; k < stride; ++k) {
            const float a = coeffs[c * stride + k];
            if (a == 0.0f) continue;
            const Rgb* row = t.data() + k * n;
            for (std::size_t r = 0; r < n; ++r) out[r] += row[r] * a;
        }
    }
    return out;
}

std::vector<std::pair<Rgb, std::vector<float>>> directByColour(const PrtData& prt, const std::vector<DirectLight>& lights,
                                                                 int areaSamples) {
    std::vector<std::pair<Rgb, std::vector<float>>> groups;
    for (const DirectLight& light : lights) {
        const std::vector<float> direct = prtDirectLight(prt, light, areaSamples);
        auto same = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == light.value; });
        if (same == groups.end()) {
            groups.push_back({light.value, direct});
        } else {
            for (std::size_t i = 0; i < direct.size(); ++i) same->second[i] += direct[i];
        }
    }
    return groups;
}

PrtLighting relightPrt(const PrtData& prt, const std::vector<DirectLight>& lights, const PrtRelightOptions& options) {
    const std::size_t n = prt.samples.size();
    PrtLighting out;
    out.direct.assign(n, Rgb{0, 0, 0});
    out.indirect.assign(n, Rgb{0, 0, 0});
    for (const auto& [colour, direct] : directByColour(prt, lights, options.areaSamples)) {
        const std::vector<Rgb> ind = prtTransfer(prt, direct);
        for (std::size_t i = 0; i < n; ++i) {
            out.direct[i] += colour * direct[i];
            out.indirect[i] += colour * ind[i];
        }
    }
    return out;
}

namespace {
constexpr uint64_t kExactStream = 0x9e7d1ec7ull;  // shadow-ray points of the exact reference
}  // namespace

std::vector<float> exactDirectLight(const SurfaceSamples& s, const Scene& scene, const Tracer& tracer,
                                    const DirectLight& light, int threads, uint32_t samples) {
    DirectLight unit = light;
    unit.value = Rgb(1, 1, 1);
    const SceneLight free = freeLight(unit);
    std::vector<float> out(s.size(), 0.0f);
    parallelFor(s.size(), threads, [&](std::size_t i) {
        RayCount rays;
        out[i] = shadowedIrradiance(scene, tracer, free, s.position[i], s.normal[i], samples, hashCombine(kExactStream, i),
                                    rays, true).x;
    });
    return out;
}

std::vector<float> exactDirectUnit(const SurfaceSamples& s, const Scene& scene, const Tracer& tracer, const Vec3f& l,
                                   int threads) {
    DirectLight point;
    point.position = Vec3d(l);
    return exactDirectLight(s, scene, tracer, point, threads, 1);
}

std::vector<Rgb> referenceIndirect(const SurfaceSamples& s, const Tracer& tracer, const std::vector<float>& direct,
                                   int threads) {
    if (direct.size() != s.size()) throw ValueError("direct lighting has the wrong number of samples");
    std::vector<Rgb> out(s.size(), Rgb{0, 0, 0});
    parallelFor(s.size(), threads, [&](std::size_t r) {
        Rgbd acc{0, 0, 0};
        for (std::size_t j = 0; j < s.size(); ++j) {
            if (j == r || direct[j] == 0.0f) continue;
            const float f = diskTransfer(s.position[r], s.normal[r], s.position[j], s.normal[j], s.area[j]);
            if (f <= 0.0f || !pairVisible(s, tracer, r, j)) continue;
            acc += Rgbd(s.albedo[j]) * (double(f) * kInvPi * direct[j]);
        }
        out[r] = Rgb(acc);
    });
    return out;
}

double rmsRelativeError(const std::vector<Rgb>& a, const std::vector<Rgb>& b) {
    if (a.size() != b.size()) throw ValueError("rmsRelativeError: size mismatch");
    double num = 0, den = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const Vec3d d = Vec3d(a[i]) - Vec3d(b[i]);
        num += dot(d, d);
        den += dot(Vec3d(b[i]), Vec3d(b[i]));
    }
    return den > 0 ? std::sqrt(num / den) : std::sqrt(num);
}

}  // namespace vdblight
