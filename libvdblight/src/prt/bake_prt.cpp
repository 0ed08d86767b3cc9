// The PRT bake: samples, compressed visibility, direct-light basis, transfer matrices.
#include <atomic>
#include <chrono>
#include <cmath>

#include "pca.h"
#include "prt_internal.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"
#include "vdblight/light/light.h"

namespace vdblight {

using namespace prt_detail;

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void checkCancel(Interrupter* in) {
    if (in && in->wasInterrupted()) throw Cancelled("PRT bake cancelled");
}

void validate(const PrtOptions& o) {
    if (o.sampleRadius < 0 || !std::isfinite(o.sampleRadius)) throw ValueError("--sample-radius must be positive");
    if (o.sampleRadius == 0 && (o.samples == 0 || o.samples > 2000000)) {
        throw ValueError("--samples must be in 1..2000000 (got " + std::to_string(o.samples) + ")");
    }
    if (o.clusterSize == 0) throw ValueError("--cluster-size must be positive");
    if (o.visDirs < 4 || o.visDirs > 65536) throw ValueError("--vis-dirs must be in 4..65536");
    if (o.visCoeffs == 0 || o.visCoeffs > o.visDirs) throw ValueError("--vis-coeffs must be in 1..--vis-dirs");
    if (o.trainLights == 0 || o.trainLights > 100000) throw ValueError("--train-lights must be in 1..100000");
    if (!(o.orientedTraining >= 0 && o.orientedTraining <= 16)) throw ValueError("--oriented-training must be in 0..16");
    if (o.orientedCoeffs > 256) throw ValueError("--oriented-coeffs must be in 0..256");
    if (o.transferCoeffs == 0 || o.transferCoeffs > o.trainLights) {
        throw ValueError("--transfer-coeffs must be in 1..--train-lights");
    }
    if (o.threads < 0) throw ValueError("thread count must be positive (0 = all cores)");
    if (o.formFactorRays == 0 || o.formFactorRays > 65536) throw ValueError("--form-factor-rays must be in 1..65536");
    if (o.bounces < 1 || o.bounces > 64) throw ValueError("--bounces must be in 1..64 (got " + std::to_string(o.bounces) + ")");
}

/// Whether the bake uses sampled form factors for n samples.
bool sampledFormFactors(double n, const PrtOptions& o) {
    return o.formFactors == PrtOptions::FormFactors::Sampled ||
           (o.formFactors == PrtOptions::FormFactors::Auto && n > PrtOptions::kDenseFormFactorLimit);
}

/// Refuses a bake whose transfer matrices, PCA or rays would not fit a machine (the
/// estimate is in the message).

void checkBudget(double n, const PrtOptions& o) {
    const double k = std::max(1.0, std::round(n / o.clusterSize));
    const double matrixBytes = k * double(o.transferCoeffs + o.orientedCoeffs + 1) * n * 12.0;
    const bool sampled = sampledFormFactors(n, o);
    // The sample-to-sample matrix during the bake: dense, or rays entries per row.
    const double formFactorBytes = sampled ? n * double(o.formFactorRays) * 8.0 : n * n * 4.0;
    const double rays = (sampled ? n * double(o.formFactorRays) : n * n / 2) + n * double(o.visDirs) +
                        n * double(o.trainLights) * (1.0 + o.orientedTraining);
    // Each cluster's PCA holds its samples x (directions or lights) in doubles, twice (SVD).
    const double clusterSamples = std::min(n, 1.5 * double(o.clusterSize));
    const double pcaBytes = clusterSamples * std::max(double(o.visDirs), o.trainLights * (1.0 + o.orientedTraining)) * 16.0;
    if (pcaBytes > 8e9) {
        throw ValueError("the per-cluster PCA would take " + std::to_string(uint64_t(pcaBytes / 1e6)) + " MB for " +
                         std::to_string(uint64_t(clusterSamples)) + " samples per cluster: use a smaller --cluster-size");
    }
    if (matrixBytes > 8e9) {
        throw ValueError("transfer matrices would take " + std::to_string(uint64_t(matrixBytes / 1e6)) +
                         " MB for " + std::to_string(uint64_t(n)) + " samples: use fewer samples or larger clusters");
    }
    if (rays > 2e11) {
        throw ValueError("the bake would trace " + std::to_string(uint64_t(rays / 1e9)) +
                         " billion rays: use fewer samples or directions");
    }
    if (formFactorBytes > 8e9) {
        throw ValueError("the form-factor matrix would take " + std::to_string(uint64_t(formFactorBytes / 1e6)) +
                         " MB for " + std::to_string(uint64_t(n)) + " samples: use fewer samples or --form-factors sampled");
    }
}

/// 4.2: per cluster, depth buffers (n_c x g^2), PCA, projected coefficients.
void bakeVisibility(PrtData& prt, const Tracer& tracer, const PrtOptions& o, Interrupter* in) {
    const SurfaceSamples& s = prt.samples;
    const int g = prt.visGrid, d = g * g;
    std::vector<Vec3f> local(static_cast<std::size_t>(d));
    for (int t = 0; t < d; ++t) local[std::size_t(t)] = visibilityDirection(g, t);
    prt.visCoeffStride = int(o.visCoeffs);
    prt.visCoeffs.assign(s.size() * std::size_t(prt.visCoeffStride), 0.0f);
    if (in) in->start("visibility", s.clusters());
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        checkCancel(in);
        const uint32_t b = s.clusterBegin[c], e = s.clusterBegin[c + 1];
        const int nc = int(e - b);
        std::vector<float> depth(std::size_t(nc) * std::size_t(d));
        parallelFor(std::size_t(nc), o.threads, [&](std::size_t li) {
            const std::size_t i = b + li;
            Vec3f t1, t2;
            orthonormalBasis(s.normal[i], t1, t2);
            for (int t = 0; t < d; ++t) {
                const Vec3f& l = local[std::size_t(t)];
                const Vec3f w = t1 * l.x + t2 * l.y + s.normal[i] * l.z;
                Ray ray{offsetRayOrigin(s.position[i], s.normal[i], w), w, 0.0f, prt.depthCap};
                const Hit h = tracer.intersect(ray);
                depth[li * std::size_t(d) + std::size_t(t)] = h.hit() ? std::min(h.t, prt.depthCap) : prt.depthCap;
            }
        });
        prt.visBasis[c] = fitPca(depth, nc, d, int(o.visCoeffs));
        for (int li = 0; li < nc; ++li) {
            pcaProject(prt.visBasis[c], depth.data() + std::size_t(li) * std::size_t(d),
                       prt.visCoeffs.data() + (b + std::size_t(li)) * std::size_t(prt.visCoeffStride));
        }
        if (in) in->progress(c + 1);
    }
    if (in) in->end();
}

/// 4.3.1: per cluster, PCA of the direct lighting of the example lights.
void bakeLightBasis(PrtData& prt, const Scene& scene, const Tracer& tracer, const PrtOptions& o, Interrupter* in) {
    const SurfaceSamples& s = prt.samples;
    // The paper's basis (eq. 7) is of isotropic point lights only.
    const float oriented = o.paperBasis || o.orientedCoeffs == 0 ? 0.0f : o.orientedTraining;
    const std::vector<PrtPointLight> lights = trainingLights(scene, tracer, o.trainLights, oriented);
    prt.trainLights = uint32_t(std::min<std::size_t>(o.trainLights, lights.size()));
    prt.orientedTraining = oriented;
    prt.orientedCoeffs = lights.size() > prt.trainLights ? int(o.orientedCoeffs) : 0;
    const std::size_t n = s.size(), l = lights.size();
    std::vector<float> direct(l * n);  // row = one light
    if (in) in->start("direct-light basis", l);
    for (std::size_t k = 0; k < l; ++k) {
        checkCancel(in);
        // The example's exact direct light: a unit point's (the shared shadowedIrradiance)
        // times the emitter's cosine for a one-sided example.
        const PrtPointLight& example = lights[k];
        DirectLight point;
        point.position = Vec3d(example.position);
        point.value = Rgb(1, 1, 1);
        const SceneLight light = freeLight(point);
        float* row = direct.data() + k * n;
        parallelFor(n, o.threads, [&](std::size_t i) {
            const float cosine = example.emission(normalize(s.position[i] - example.position));
            if (!(cosine > 0.0f)) return;
            RayCount rays;
            row[i] = cosine * shadowedIrradiance(scene, tracer, light, s.position[i], s.normal[i], 1, 0, rays, true).x;
        });
        if (in) in->progress(k + 1);
    }
    if (in) in->end();
    for (std::size_t c = 0; c < s.clusters(); ++c) {
        const uint32_t b = s.clusterBegin[c], e = s.clusterBegin[c + 1];
        const int nc = int(e - b);
        // Rows 0 .. iso - 1: the point lights; the one-sided examples follow.
        const std::size_t iso = prt.trainLights, oneSided = l - iso;
        std::vector<float> rows(iso * std::size_t(nc));
        for (std::size_t k = 0; k < iso; ++k)
            std::copy(direct.begin() + std::ptrdiff_t(k * n + b), direct.begin() + std::ptrdiff_t(k * n + e),
                      rows.begin() + std::ptrdiff_t(k * std::size_t(nc)));
        if (!o.paperBasis) {
            for (std::size_t k = 0; k < iso; ++k) {
                float* row = rows.data() + k * std::size_t(nc);
                double norm2 = 0;
                for (int j = 0; j < nc; ++j) norm2 += double(row[j]) * row[j];
                const double scale = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
                for (int j = 0; j < nc; ++j) row[j] = float(row[j] * scale);
            }
        }
        // The point lights' basis (the paper's), then the one-sided examples' residuals
        // after projecting them onto it, whose PCA adds up to orientedCoeffs more vectors
        // (orthogonal to the first: point lights project as before, or better).
        std::vector<float> residual(oneSided * std::size_t(nc));
        for (std::size_t k = 0; k < oneSided; ++k)
            std::copy(direct.begin() + std::ptrdiff_t((iso + k) * n + b), direct.begin() + std::ptrdiff_t((iso + k) * n + e),
                      residual.begin() + std::ptrdiff_t(k * std::size_t(nc)));
        PcaBasis basis = fitPca(rows, int(iso), nc, int(o.transferCoeffs), o.paperBasis);
        if (oneSided > 0) {
            for (std::size_t k = 0; k < oneSided; ++k) {
                float* x = residual.data() + k * std::size_t(nc);
                double norm2 = 0;
                for (int j = 0; j < nc; ++j) norm2 += double(x[j]) * x[j];
                const double scale = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
                for (int j = 0; j < nc; ++j) x[j] = float(x[j] * scale);
                for (int v = 0; v < basis.count; ++v) {  // minus its projection (Gram-Schmidt order)
                    const float* bv = basis.vectors.data() + std::size_t(v) * std::size_t(nc);
                    double d = 0;
                    for (int j = 0; j < nc; ++j) d += double(x[j]) * bv[j];
                    for (int j = 0; j < nc; ++j) x[j] = float(x[j] - d * bv[j]);
                }
            }
            const PcaBasis extra = fitPca(residual, int(oneSided), nc, int(o.orientedCoeffs), false);
            // Only directions the residuals really have (mean square along it > 1e-6 of a unit
            // example), and never more vectors than the cluster has samples: where the point
            // lights' basis already spans everything, the residuals are rounding noise.
            for (int k = 0; k < extra.count && basis.count < nc; ++k) {
                const double sv = extra.singularValues[std::size_t(k)];
                if (!(sv * sv > 1e-6 * double(oneSided))) break;
                basis.vectors.insert(basis.vectors.end(), extra.vectors.begin() + std::ptrdiff_t(k) * nc,
                                     extra.vectors.begin() + std::ptrdiff_t(k + 1) * nc);
                ++basis.count;
            }
        }
        prt.lightBasis[c] = std::move(basis);
    }
}

}  // namespace

PrtData bakePrt(const Scene& scene, const Tracer& tracer, const PrtOptions& o, Interrupter* in) {
    validate(o);
    PrtData prt;
    prt.sceneName = scene.name;
    prt.sceneHash = scene.contentHash();
    prt.seed = o.seed;
    prt.paperBasis = o.paperBasis;
    prt.bounds = scene.bounds();
    prt.origin = scene.origin;
    prt.depthCap = float(length(prt.bounds.size()) * 1.01 + 1e-3);
    if (o.volumeResolution < 0 || o.volumeResolution > 256) throw ValueError("--volume-resolution must be in 0..256");
    if (o.volumeResolution > 0) {
        GridPlacement placement;
        placement.resolution = o.volumeResolution;
        prt.volumeGrid = placeUniformGrid(prt.bounds, placement, sizeof(float) * 27);
    }
    prt.visGrid = std::max(2, int(std::lround(std::sqrt(double(o.visDirs)))));

    double area = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const Vec3d a(scene.vertex(t, 0)), b(scene.vertex(t, 1)), c(scene.vertex(t, 2));
        area += 0.5 * length(cross(b - a, c - a));
    }
    // Random sequential packing covers about 55% with disks of radius r/2 (as the sampler).
    checkBudget(o.sampleRadius > 0 ? 2.2 * area / (kPi * o.sampleRadius * o.sampleRadius) : double(o.samples), o);

    double t0 = now();
    prt.samples = generateSurfaceSamples(scene, o.sampleRadius, o.samples, o.clusterSize, o.seed);
    checkBudget(double(prt.samples.size()), o);
    prt.visBasis.resize(prt.samples.clusters());
    prt.lightBasis.resize(prt.samples.clusters());
    double t1 = now();
    prt.secondsSamples = t1 - t0;
    bakeVisibility(prt, tracer, o, in);
    double t2 = now();
    prt.secondsVisibility = t2 - t1;
    bakeLightBasis(prt, scene, tracer, o, in);
    double t3 = now();
    prt.secondsBasis = t3 - t2;
    prt.transferStride = int(o.transferCoeffs) + prt.orientedCoeffs + 1;
    prt.bounces = o.bounces;
    prt.closureNormalise = o.closureNormalise;
    prt.formFactorRays = sampledFormFactors(double(prt.samples.size()), o) ? o.formFactorRays : 0;
    bakeMultiBounceTransfer(prt, tracer, o.bounces, o.volumeResolution > 0, o.closureNormalise, prt.formFactorRays,
                            o.seed, o.threads, in);
    prt.secondsTransfer = now() - t3;
    prepareRelight(prt);
    return prt;
}

}  // namespace vdblight
