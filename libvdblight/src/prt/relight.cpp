// Run time (Leonhardt & Bohn section 5): visibility -> direct light -> projection ->
// transfer -> indirect, plus the uncompressed references it is tested against.
#include <cmath>

#include "prt_internal.h"
#include "vdblight/errors.h"

namespace vdblight {

using namespace prt_detail;

std::vector<float> prtDirectUnit(const PrtData& prt, const Vec3f& l) {
    const SurfaceSamples& s = prt.samples;
    std::vector<float> out(s.size(), 0.0f);
    const int g = prt.visGrid;
    for (std::size_t i = 0; i < s.size(); ++i) {
        float dist = 0;
        const float e = unshadowedUnit(s.position[i], s.normal[i], l, &dist);
        if (e <= 0.0f) continue;
        Vec3f t1, t2;
        orthonormalBasis(s.normal[i], t1, t2);
        const Vec3f w = (l - s.position[i]) / dist;
        const Vec3f local{dot(w, t1), dot(w, t2), dot(w, s.normal[i])};
        int idx[4];
        float wt[4];
        visibilityNeighbours(g, local, idx, wt);
        const PcaBasis& basis = prt.visBasis[s.cluster[i]];
        const float* coeffs = prt.visCoeffs.data() + i * std::size_t(prt.visCoeffStride);
        float vis = 0;
        for (int k = 0; k < 4; ++k) {
            if (wt[k] <= 0.0f) continue;
            if (dist <= pcaReconstructAt(basis, coeffs, idx[k])) vis += wt[k];
        }
        out[i] = e * vis;
    }
    return out;
}

std::vector<Rgb> prtTransfer(const PrtData& prt, const std::vector<float>& direct) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t n = s.size();
    if (direct.size() != n) throw ValueError("direct lighting has the wrong number of samples");
    std::vector<Rgb> out(n, Rgb{0, 0, 0});
    std::vector<float> coeffs(std::size_t(prt.transferStride));
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const PcaBasis& b = prt.lightBasis[c];
        coeffs.assign(coeffs.size(), 0.0f);
        coeffs[0] = 1.0f;  // the mean vector
        pcaProject(b, direct.data() + s.clusterBegin[c], coeffs.data() + 1);
        const std::vector<Rgb>& t = prt.transfer[c];
        for (int k = 0; k < prt.transferStride; ++k) {
            const float a = coeffs[std::size_t(k)];
            if (a == 0.0f) continue;
            const Rgb* row = t.data() + std::size_t(k) * n;
            for (std::size_t r = 0; r < n; ++r) out[r] += row[r] * a;
        }
    }
    return out;
}

PrtLighting relightPrt(const PrtData& prt, const std::vector<PrtLight>& lights) {
    const std::size_t n = prt.samples.size();
    PrtLighting out;
    out.direct.assign(n, Rgb{0, 0, 0});
    out.indirect.assign(n, Rgb{0, 0, 0});
    for (const PrtLight& light : lights) {
        // An area light is a grid of point lights sharing its intensity (each facing -Y
        // with a cosine falloff would need per-sample orientation; kept isotropic).
        const int m = light.size > 0 ? std::max(1, light.areaSamples) : 1;
        std::vector<float> direct(n, 0.0f);
        for (int a = 0; a < m * m; ++a) {
            Vec3f p = light.position;
            if (m > 1) {
                p.x += light.size * ((float(a % m) + 0.5f) / float(m) - 0.5f);
                p.z += light.size * ((float(a / m) + 0.5f) / float(m) - 0.5f);
            }
            const std::vector<float> d = prtDirectUnit(prt, p);
            for (std::size_t i = 0; i < n; ++i) direct[i] += d[i] / float(m * m);
        }
        const std::vector<Rgb> ind = prtTransfer(prt, direct);
        for (std::size_t i = 0; i < n; ++i) {
            out.direct[i] += light.intensity * direct[i];
            out.indirect[i] += light.intensity * ind[i];
        }
    }
    return out;
}

std::vector<float> exactDirectUnit(const SurfaceSamples& s, const Tracer& tracer, const Vec3f& l, int threads) {
    std::vector<float> out(s.size(), 0.0f);
    parallelFor(s.size(), threads, [&](std::size_t i) {
        const float e = unshadowedUnit(s.position[i], s.normal[i], l);
        if (e > 0.0f && visibleToLight(tracer, s.position[i], s.normal[i], l)) out[i] = e;
    });
    return out;
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
            if (f <= 0.0f || !visibleBetween(tracer, s.position[r], s.normal[r], s.position[j], s.normal[j])) continue;
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
