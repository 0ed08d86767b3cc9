// Relightable SH volumes (beyond the paper): the nodes of a uniform grid are receivers of the
// same one-bounce transfer as the samples, in SH order 2 (radiance coefficients, the
// foundation's basis), so a new light position gives a new volume without a re-bake.
#include <atomic>
#include <cmath>

#include "prt_internal.h"
#include "vdblight/errors.h"
#include "vdblight/sh.h"

namespace vdblight {

using namespace prt_detail;

namespace {

/// Adds to `acc` (9 x 3 doubles) the SH radiance sender j sends to node x per unit `weight`.
inline bool senderToNode(const SurfaceSamples& s, const Tracer& tracer, const Vec3f& x, std::size_t j,
                         float sh[sh::kCoeffs], float& omega) {
    omega = diskSolidAngle(x, s.position[j], s.normal[j], s.area[j]);
    if (omega <= 0.0f) return false;
    const Vec3f q = offsetRayOrigin(s.position[j], s.normal[j], x - s.position[j]);
    if (tracer.occluded(Ray{x, q - x, 0.0f, 0.9999f})) return false;
    sh::evalUnrolled(normalize(q - x), sh);
    return true;
}

}  // namespace

void bakeVolumeTransfer(PrtData& prt, const Tracer& tracer, int threads) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t nodes = prt.volumeGrid.nodeCount();
    const int stride = prt.transferStride;
    prt.volumeTransfer.assign(s.clusters(), std::vector<Rgb>(std::size_t(stride) * nodes * sh::kCoeffs, Rgb{0, 0, 0}));
    parallelFor(nodes, threads, [&](std::size_t node) {
        const Vec3f x(prt.volumeGrid.node(node));
        std::vector<double> acc(std::size_t(stride) * sh::kCoeffs * 3);
        float y[sh::kCoeffs];
        for (std::size_t c = 0; c < s.clusters(); ++c) {
            const PcaBasis& basis = prt.lightBasis[c];
            std::fill(acc.begin(), acc.end(), 0.0);
            const uint32_t b = s.clusterBegin[c], e = s.clusterBegin[c + 1];
            const std::size_t nc = e - b;
            for (uint32_t j = b; j < e; ++j) {
                float omega;
                if (!senderToNode(s, tracer, x, j, y, omega)) continue;
                const Rgb w = s.albedo[j] * float(omega * kInvPi);
                const std::size_t lj = j - b;
                for (int k = 0; k < stride; ++k) {
                    const float v = k == 0 ? basis.mean[lj] : (k - 1 < basis.count ? basis.vectors[std::size_t(k - 1) * nc + lj] : 0.0f);
                    if (v == 0.0f) continue;
                    for (int m = 0; m < sh::kCoeffs; ++m) {
                        double* a = acc.data() + (std::size_t(k) * sh::kCoeffs + std::size_t(m)) * 3;
                        const double f = double(v) * y[m];
                        a[0] += w.x * f;
                        a[1] += w.y * f;
                        a[2] += w.z * f;
                    }
                }
            }
            for (int k = 0; k < stride; ++k)
                for (int m = 0; m < sh::kCoeffs; ++m) {
                    const double* a = acc.data() + (std::size_t(k) * sh::kCoeffs + std::size_t(m)) * 3;
                    prt.volumeTransfer[c][(std::size_t(k) * nodes + node) * sh::kCoeffs + std::size_t(m)] =
                        Rgb{float(a[0]), float(a[1]), float(a[2])};
                }
        }
    });
}

std::vector<Rgb> prtVolumeTransfer(const PrtData& prt, const std::vector<float>& direct) {
    if (!prt.hasVolume()) throw ValueError("this PRT file has no volume (bake with --volume-resolution)");
    const SurfaceSamples& s = prt.samples;
    if (direct.size() != s.size()) throw ValueError("direct lighting has the wrong number of samples");
    const std::size_t count = prt.volumeGrid.nodeCount() * sh::kCoeffs;
    std::vector<Rgb> out(count, Rgb{0, 0, 0});
    std::vector<float> coeffs(std::size_t(prt.transferStride));
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        coeffs.assign(coeffs.size(), 0.0f);
        coeffs[0] = 1.0f;
        pcaProject(prt.lightBasis[c], direct.data() + s.clusterBegin[c], coeffs.data() + 1);
        for (int k = 0; k < prt.transferStride; ++k) {
            const float a = coeffs[std::size_t(k)];
            if (a == 0.0f) continue;
            const Rgb* row = prt.volumeTransfer[c].data() + std::size_t(k) * count;
            for (std::size_t i = 0; i < count; ++i) out[i] += row[i] * a;
        }
    }
    return out;
}

Volume relightVolume(const PrtData& prt, const std::vector<PrtLight>& lights) {
    if (!prt.hasVolume()) throw ValueError("this PRT file has no volume (bake with --volume-resolution)");
    const std::size_t n = prt.samples.size();
    std::vector<Rgb> total(prt.volumeGrid.nodeCount() * sh::kCoeffs, Rgb{0, 0, 0});
    for (const PrtLight& light : lights) {
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
        const std::vector<Rgb> v = prtVolumeTransfer(prt, direct);
        for (std::size_t i = 0; i < v.size(); ++i) total[i] += light.intensity * v[i];
    }
    Volume vol;
    vol.basis = BasisDesc::sh2();
    VolumeLevel level;
    level.grid = prt.volumeGrid;
    level.data.resize(total.size() * 3);
    for (std::size_t i = 0; i < total.size(); ++i) {
        level.data[i * 3 + 0] = total[i].x;
        level.data[i * 3 + 1] = total[i].y;
        level.data[i * 3 + 2] = total[i].z;
    }
    vol.levels.push_back(std::move(level));
    vol.meta["method"] = std::string("prt_relight");
    vol.meta["content"] = std::string("one-bounce indirect radiance from the PRT samples; no direct light");
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
            if (direct[j] == 0.0f || !senderToNode(s, tracer, x, j, y, omega)) continue;
            const Rgbd w = Rgbd(s.albedo[j]) * (double(omega) * kInvPi * direct[j]);
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

}  // namespace vdblight
