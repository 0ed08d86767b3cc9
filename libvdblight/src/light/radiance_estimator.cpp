#include "vdblight/light/light.h"

#include <algorithm>
#include <type_traits>

#include "light_tree.h"
#include "punctual_sampler.h"
#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

namespace {
// Shadow rays stop just short of the light so that the emitter itself does not occlude.
constexpr float kShadowEnd = 1.0f - 1e-4f;
// The emitter tree is used when the emitters' common box is this many times their mean size.
constexpr double kEmitterSpread = 8.0;

float spotFalloff(const SpotLight& s, const Vec3f& fromLight) {
    // glTF KHR_lights_punctual: smooth (squared linear) ramp between the cone cosines.
    const float cosOuter = std::cos(s.outerConeAngle), cosInner = std::cos(s.innerConeAngle);
    const float c = dot(s.direction, fromLight);
    if (c <= cosOuter) return 0.0f;
    if (cosInner - cosOuter <= 1e-6f) return 1.0f;
    const float t = std::min(1.0f, (c - cosOuter) / (cosInner - cosOuter));
    return t * t;
}
}  // namespace

RadianceEstimator::RadianceEstimator(const Scene& scene, const Tracer& tracer, TransportOptions options)
    : scene_(scene), tracer_(tracer), options_(options) {
    const std::size_t n = scene.triangleCount();
    unitNormals_.resize(n);
    emitterOf_.assign(n, -1);
    double total = 0.0;
    std::vector<double> power;
    std::vector<LightBounds> emitterBounds;
    for (std::size_t t = 0; t < n; ++t) {
        const Vec3f a = scene.vertex(t, 0), b = scene.vertex(t, 1), c = scene.vertex(t, 2);
        const Vec3f ng = cross(b - a, c - a);
        const float len = length(ng);
        unitNormals_[t] = len > 0 ? ng / len : Vec3f(0, 0, 1);
        const Material& m = scene.material(t);
        if (!m.isEmissive() || !(len > 0)) continue;
        const float area = 0.5f * len;
        // Choose emitters in proportion to emitted power (area x luminance x sides).
        const double p = double(area) * std::max(1e-6f, luminance(m.emission)) * (m.twoSidedEmission ? 2.0 : 1.0);
        emitterOf_[t] = int32_t(emitters_.size());
        emitters_.push_back(uint32_t(t));
        emitterArea_.push_back(area);
        power.push_back(p);
        total += p;
        LightBounds lb;  // around the front normal; two-sided emitters on both sides
        lb.box.extend(Vec3d(a));
        lb.box.extend(Vec3d(b));
        lb.box.extend(Vec3d(c));
        lb.power = p;
        lb.axis = Vec3d(unitNormals_[t]);
        lb.thetaO = 0.0;
        lb.thetaE = 0.5 * kPi;
        lb.twoSided = m.twoSidedEmission;
        emitterBounds.push_back(lb);
    }
    double running = 0.0;
    for (std::size_t e = 0; e < emitters_.size(); ++e) {
        running += power[e];
        emitterCdf_.push_back(float(running / total));
        emitterPmf_.push_back(float(power[e] / total));
    }
    if (!emitterCdf_.empty()) emitterCdf_.back() = 1.0f;
    for (std::size_t e = 0; e < emitters_.size(); ++e) {
        const uint32_t t = emitters_[e];
        const Vec3f a = scene.vertex(t, 0), b = scene.vertex(t, 1), c = scene.vertex(t, 2);
        const Material& m = scene.material(t);
        emitterData_.push_back({a, b - a, c - a, unitNormals_[t], m.emission, emitterArea_[e], emitterPmf_[e],
                                m.twoSidedEmission});
    }
    if (options_.orientedLightTree && emitters_.size() > options_.emitterTreeMin) {
        // Only for emitters spread out relative to their size: one compact tessellated emitter
        // (a disk fan, a panel) is better served by the power CDF, whose stratified choice
        // keeps the triangles' nearly equal contributions balanced (measured on a 512-triangle
        // disk: 2 % error in the SH x-term with the tree at 2^15 rays, within 1 % with the CDF).
        Bounds all;
        double meanDiag = 0;
        for (const LightBounds& lb : emitterBounds) {
            all.extend(lb.box.lo);
            all.extend(lb.box.hi);
            meanDiag += length(lb.box.size()) / double(emitterBounds.size());
        }
        if (length(all.size()) > kEmitterSpread * meanDiag)
            emitterTree_ = std::make_shared<const LightTree>(emitterBounds);
    }
    if (scene.pointLights.size() + scene.spotLights.size() > options_.exactLightLimit) {
        if (!options_.orientedLightTree) {
            punctualSampler_ = std::make_shared<const PunctualLightSampler>(scene);
        } else {
            std::vector<LightBounds> lights;
            for (const PointLight& l : scene.pointLights) {
                LightBounds lb;  // emits everywhere
                lb.box.extend(Vec3d(l.position));
                lb.power = std::max(0.0f, luminance(l.intensity));
                lb.thetaO = kPi;
                lights.push_back(lb);
            }
            for (const SpotLight& s : scene.spotLights) {
                LightBounds lb;  // emits inside its outer cone only
                lb.box.extend(Vec3d(s.position));
                lb.power = std::max(0.0f, luminance(s.intensity));
                const float len = length(s.direction);
                lb.axis = len > 0 ? Vec3d(s.direction / len) : Vec3d(0, 0, -1);
                lb.thetaO = std::min(double(std::max(s.outerConeAngle, 0.0f)), kPi);
                lb.thetaE = 0.0;
                lights.push_back(lb);
            }
            punctualTree_ = std::make_shared<const LightTree>(lights);
        }
    }
}

double RadianceEstimator::emitterChoicePmf(std::size_t e, const Vec3f& x) const {
    return emitterTree_ ? emitterTree_->pmf(Vec3d(x), nullptr, uint32_t(e)) : double(emitterPmf_[e]);
}

std::size_t RadianceEstimator::pointAndSpotLightCount() const {
    return scene_.pointLights.size() + scene_.spotLights.size();
}

bool RadianceEstimator::samplePunctualLight(const Vec3f& x, double u, LightSample& out, RayCount& rays,
                                            const Vec3f* normal) const {
    if (!samplesPunctualLights()) return false;
    double pmf = 0;
    uint32_t l;
    if (punctualTree_) {
        const Vec3d n = normal ? Vec3d(*normal) : Vec3d();
        l = punctualTree_->sample(Vec3d(x), normal ? &n : nullptr, u, pmf);
    } else {
        l = punctualSampler_->sample(x, u, pmf);
    }
    if (!(pmf > 0)) return false;
    Vec3f pos;
    Rgb intensity;
    if (l < scene_.pointLights.size()) {
        pos = scene_.pointLights[l].position;
        intensity = scene_.pointLights[l].intensity;
    } else {
        const SpotLight& s = scene_.spotLights[l - scene_.pointLights.size()];
        pos = s.position;
        const Vec3f d = x - s.position;
        const float len = length(d);
        if (!(len > 0)) return false;
        intensity = s.intensity * spotFalloff(s, d / len);
    }
    const Vec3f toLight = pos - x;
    const float dist2 = dot(toLight, toLight);
    if (!(dist2 > 0) || maxComponent(intensity) <= 0) return false;
    ++rays.occluded;
    if (tracer_.occluded(Ray{x, toLight, 0.0f, kShadowEnd})) return false;
    out.direction = toLight / std::sqrt(dist2);
    out.weight = intensity * float(1.0 / (double(dist2) * pmf));
    out.pdf = 0.0f;
    out.source = int32_t(l);  // points then spots: the punctual order
    out.punctual = true;
    return true;
}

bool RadianceEstimator::emissiveCandidate(const Vec3f& x, float u, float v, double w, LightSample& out, Ray& shadow,
                                          const Vec3f* facing) const {
    if (emitters_.empty()) return false;
    double choicePmf = 0;
    std::size_t e;
    if (emitterTree_) {
        e = emitterTree_->sample(Vec3d(x), nullptr, w, choicePmf);
        if (!(choicePmf > 0)) return false;
    } else {
        e = std::min<std::size_t>(upperBoundIndex(emitterCdf_.data(), emitterCdf_.size(), float(w)),
                                  emitters_.size() - 1);
        choicePmf = emitterPmf_[e];
    }
    const EmitterData& d = emitterData_[e];  // the triangle's data, in one place
    float b1, b2;
    uniformTriangle(u, v, b1, b2);
    const Vec3f q = d.a + d.ab * b1 + d.ac * b2;
    const Vec3f toLight = q - x;
    const float dist2 = dot(toLight, toLight);
    if (!(dist2 > 0)) return false;
    // Behind the emitter's face, or behind the receiver, by far more than rounding: the tests
    // below on the normalised direction would say so too. Decided before the square root and
    // the divisions, whose latency was most of this function's time (issue 32: in the two
    // rooms, every vertex in the bedroom and behind the panel is behind a one-sided emitter).
    const float kClearly = 1e-6f * dist2;  // (1e-3 of the distance)^2: far above float rounding
    if (const float back = dot(d.normal, toLight); !d.twoSided && back > 0 && back * back > kClearly) return false;
    if (facing)
        if (const float front = dot(*facing, toLight); front < 0 && front * front > kClearly) return false;
    const float dist = std::sqrt(dist2);
    const Vec3f wi = toLight / dist;
    float cosLight = -dot(d.normal, wi);  // > 0 when x sees the front face
    if (d.twoSided) cosLight = std::abs(cosLight);
    if (cosLight <= 0) return false;
    if (facing && !(dot(*facing, wi) > 0.0f)) return false;  // behind the receiver: no shadow ray needed
    shadow = Ray{x, toLight, 0.0f, kShadowEnd};
    // pdf over solid angle = pmf / area * dist^2 / cosLight.
    const float invPdf = emitterTree_ ? float(double(d.area) * cosLight / (choicePmf * dist2))
                                      : d.area * cosLight / (d.pmf * dist2);
    out.direction = wi;
    out.weight = d.emission * invPdf;
    out.pdf = 1.0f / invPdf;
    out.source = int32_t(emitters_[e]);
    out.punctual = false;
    return true;
}

bool RadianceEstimator::sampleEmissiveTriangles(const Vec3f& x, float u, float v, double w, LightSample& out,
                                                RayCount& rays, const Vec3f* facing) const {
    LightSample s;
    Ray shadow;
    if (!emissiveCandidate(x, u, v, w, s, shadow, facing)) return false;
    ++rays.occluded;
    if (tracer_.occluded(shadow)) return false;
    out = s;
    return true;
}

float RadianceEstimator::emitterPdf(uint32_t tri, float t, const Vec3f& dir, const Vec3f* x) const {
    const int32_t e = emitterOf_[tri];
    if (e < 0) return 0.0f;
    float cosLight = std::abs(dot(unitNormals_[tri], dir));
    if (!(cosLight > 0)) return 0.0f;
    if (emitterTree_) {
        if (!x) throw ValueError("emitterPdf: the emitter tree needs the point the ray left");
        return float(emitterChoicePmf(std::size_t(e), *x) * double(t) * t / (double(emitterArea_[e]) * cosLight));
    }
    return emitterPmf_[e] * t * t / (emitterArea_[e] * cosLight);
}

Rgb RadianceEstimator::emittedRadiance(uint32_t tri, const Vec3f& dir) const {
    const Material& m = scene_.material(tri);
    if (!m.isEmissive()) return Rgb(0, 0, 0);
    if (m.twoSidedEmission || dot(unitNormals_[tri], dir) < 0) return m.emission;
    return Rgb(0, 0, 0);
}

void RadianceEstimator::punctualLights(const Vec3f& x, std::vector<LightSample>& out, RayCount& rays,
                                       bool skipSampled) const {
    int32_t index = 0;  // the punctual order: points, spots, directionals (LightSample::source)
    auto addPoint = [&](const Vec3f& pos, const Rgb& intensity) {
        const Vec3f toLight = pos - x;
        const float dist2 = dot(toLight, toLight);
        if (!(dist2 > 0) || maxComponent(intensity) <= 0) return;
        ++rays.occluded;
        if (tracer_.occluded(Ray{x, toLight, 0.0f, kShadowEnd})) return;
        out.push_back({toLight / std::sqrt(dist2), intensity / dist2, 0.0f, index, true});
    };
    const bool exact = !(skipSampled && samplesPunctualLights());
    if (exact) {
        for (const PointLight& l : scene_.pointLights) {
            addPoint(l.position, l.intensity);
            ++index;
        }
        for (const SpotLight& s : scene_.spotLights) {
            const Vec3f d = x - s.position;
            const float len = length(d);
            if (len > 0) addPoint(s.position, s.intensity * spotFalloff(s, d / len));
            ++index;
        }
    }
    index = int32_t(pointAndSpotLightCount());
    for (const DirectionalLight& l : scene_.directionalLights) {
        const Vec3f toLight = -normalize(l.direction);
        const int32_t source = index++;
        ++rays.occluded;
        if (tracer_.occluded(Ray{x, toLight})) continue;
        out.push_back({toLight, l.irradiance, 0.0f, source, true});
    }
}

void RadianceEstimator::drawEmitterSample(Rng& rng, float& u, float& v, double& w) const {
    u = rng.uniform();
    v = rng.uniform();
    if (emitterTree_) {  // 53 bits: a tree over thousands of triangles splits u many times
        const double hi = double(rng.next() >> 5), lo = double(rng.next() >> 6);
        w = (hi * 67108864.0 + lo) * (1.0 / 9007199254740992.0);
    } else {
        w = rng.uniform();
    }
}

Rgb RadianceEstimator::directAtSurface(const Vec3f& p, const Vec3f& n, Rng& rng, RayCount& rays, float emitterScale,
                                       bool punctualToo) const {
    // Irradiance from emitters at a surface point (one NEE sample + all punctual lights).
    Rgb e{0, 0, 0};
    LightSample s;
    if (!emitters_.empty()) {
        float u, v;
        double w;
        drawEmitterSample(rng, u, v, w);
        // A light point behind the surface adds exactly 0 (cosine 0): skip its shadow ray.
        if (sampleEmissiveTriangles(p, u, v, w, s, rays, &n)) {
            const float cosine = std::max(0.0f, dot(n, s.direction));
            // The continuation ray is cosine-distributed: pdf cos / pi.
            e += s.weight * (cosine * misWeight(s.pdf, cosine * float(kInvPi))) * emitterScale;
        }
    }
    if (punctualToo && (!scene_.pointLights.empty() || !scene_.spotLights.empty() || !scene_.directionalLights.empty())) {
        thread_local std::vector<LightSample> punctual;
        punctual.clear();
        punctualLights(p, punctual, rays, true);
        for (const LightSample& l : punctual) e += l.weight * std::max(0.0f, dot(n, l.direction));
        if (samplesPunctualLights()) {
            // 53-bit u: the pmf of a light among thousands is below float resolution.
            const double hi = double(rng.next() >> 5), lo = double(rng.next() >> 6);
            const double u = (hi * 67108864.0 + lo) * (1.0 / 9007199254740992.0);
            if (samplePunctualLight(p, u, s, rays, &n)) e += s.weight * std::max(0.0f, dot(n, s.direction));
        }
    }
    return e;
}

namespace {
/// walkPath's sink for gatherRadiance: every term added at once, NEE traced at once.
struct ImmediateSink {
    Rgb radiance{0, 0, 0};
    Rgb emitted{0, 0, 0};
    void add(const Rgb& term) { radiance += term; }
};
}  // namespace

/// walkPath's sink for gatherRadianceDeferred: terms recorded, NEE shadow rays deferred.
struct RadianceEstimator::DeferredSink {
    DeferredPaths& paths;
    Rgb emitted{0, 0, 0};
    DeferredPaths::FirstVertex first{};
    void add(const Rgb& term) { paths.terms_.push_back({term, Rgb(), DeferredPaths::kNoShadowRay, false}); }
};

template <typename Sink>
void RadianceEstimator::walkPath(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng, RayCount& rays,
                                 const Hit* firstHit, Sink& sink) const {
    Rgb throughput{1, 1, 1};
    Ray ray{origin, dir};
    float pdf = dirPdf;  // pdf of the direction of the current ray
    for (int reflection = 1;; ++reflection) {
        Hit hit;
        if (reflection == 1 && firstHit) {
            hit = *firstHit;  // traced and counted by the caller
        } else {
            ++rays.intersect;
            hit = tracer_.intersect(ray);
        }
        if (!hit.hit()) {
            sink.add(throughput * scene_.sky.radiance(ray.direction));
            break;
        }
        if (emitterOf_[hit.triangle] >= 0 &&
            !(reflection == 1 && options_.skipAtReceiver && options_.skipAtReceiver->skipsTriangle(hit.triangle))) {
            const float lightPdf = emitterPdf(hit.triangle, hit.t, ray.direction, &ray.origin);
            const Rgb e = throughput * emittedRadiance(hit.triangle, ray.direction) * misWeight(pdf, lightPdf);
            if (reflection == 1) sink.emitted = e;
            if constexpr (!std::is_same_v<Sink, ImmediateSink>)
                if (reflection == 2) sink.first.skip = uint32_t(sink.paths.terms_.size());
            sink.add(e);
        }
        if (reflection > options_.maxBounces) break;
        const Material& m = scene_.material(hit.triangle);
        throughput = throughput * m.albedo;
        if (maxComponent(throughput) <= 0) break;
        // Two-sided Lambertian: shade the side the ray arrived on.
        Vec3f n = unitNormals_[hit.triangle];
        if (dot(n, ray.direction) > 0) n = -n;
        const Vec3f p = offsetRayOrigin(ray.origin + ray.direction * hit.t, n, n);
        // With a surface cache the path ends at its first hit (light.h): NEE there as usual,
        // one direction sample for the emitters' other MIS share, the rest from the cache.
        Rgb cached;
        const bool ends = reflection == 1 && cache_ && cache_->irradiance(p, n, cached, rays);
        // Where the cache ends the path, options_.cacheEndLightSamples emitter samples, each a
        // term of its own weighted 1 / n (the punctual lights with the first): one ray's worth of
        // path, whose light sample is a large share of its variance (TransportOptions).
        const int lightSamples = ends && !emitters_.empty() ? std::max(1, options_.cacheEndLightSamples) : 1;
        const float emitterScale = 1.0f / float(lightSamples);
        for (int k = 0; k < lightSamples; ++k) {
            // Lambertian BRDF albedo / pi; albedo is in the throughput already.
            if constexpr (std::is_same_v<Sink, ImmediateSink>) {
                sink.add(throughput * directAtSurface(p, n, rng, rays, emitterScale, k == 0) * float(kInvPi));
            } else if (!scene_.pointLights.empty() || !scene_.spotLights.empty() ||
                       !scene_.directionalLights.empty()) {
                sink.paths.terms_.push_back({throughput * directAtSurface(p, n, rng, rays, emitterScale, k == 0) * float(kInvPi),
                                             Rgb(), DeferredPaths::kNoShadowRay, false});
            } else {
                // directAtSurface's emitter sample, its shadow ray deferred (DeferredPaths::radiance).
                DeferredPaths::Term term{Rgb(), throughput, DeferredPaths::kNoShadowRay, true};
                if (!emitters_.empty()) {
                    float u, v;
                    double w;
                    drawEmitterSample(rng, u, v, w);
                    LightSample s;
                    Ray shadow;
                    if (emissiveCandidate(p, u, v, w, s, shadow, &n)) {
                        const float cosine = std::max(0.0f, dot(n, s.direction));
                        term.value = s.weight * (cosine * misWeight(s.pdf, cosine * float(kInvPi))) * emitterScale;
                        ++rays.occluded;
                        term.shadow = sink.paths.addShadowRay(shadow);
                    }
                }
                sink.paths.terms_.push_back(term);
            }
        }

        if (ends) {
            Vec3f t, b;
            orthonormalBasis(n, t, b);
            const Vec3f local = cosineHemisphere(rng.uniform(), rng.uniform());
            const Ray next{p, t * local.x + b * local.y + n * local.z};
            ++rays.intersect;
            const Hit h = tracer_.intersect(next);
            if (h.hit() && emitterOf_[h.triangle] >= 0) {
                const float lightPdf = emitterPdf(h.triangle, h.t, next.direction, &next.origin);
                sink.add(throughput * emittedRadiance(h.triangle, next.direction) *
                         misWeight(local.z * float(kInvPi), lightPdf));
            }
            sink.add(throughput * cached * float(kInvPi));
            break;
        }
        if constexpr (!std::is_same_v<Sink, ImmediateSink>) {
            if (reflection == 1 && sink.paths.recordFirst_) {  // DeferredPaths::firstVertexIrradiance
                sink.first.p = p;
                sink.first.n = n;
                sink.first.albedo = m.albedo;
                sink.first.from = uint32_t(sink.paths.terms_.size());
            }
        }
        if (reflection >= options_.rouletteStart) {
            const float q = std::min(kRouletteMaxSurvival, maxComponent(throughput));
            if (rng.uniform() >= q) break;
            throughput *= 1.0f / q;
        }
        Vec3f t, b;
        orthonormalBasis(n, t, b);
        const Vec3f local = cosineHemisphere(rng.uniform(), rng.uniform());
        ray = Ray{p, t * local.x + b * local.y + n * local.z};
        pdf = local.z * float(kInvPi);
    }
}

Rgb RadianceEstimator::gatherRadiance(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng,
                                      RayCount& rays, const Hit* firstHit, Rgb* firstEmission) const {
    ImmediateSink sink;
    walkPath(origin, dir, dirPdf, rng, rays, firstHit, sink);
    if (firstEmission) *firstEmission = sink.emitted;
    return sink.radiance;
}

void RadianceEstimator::gatherRadianceDeferred(const Vec3f& origin, const Vec3f& dir, float dirPdf, Rng& rng,
                                               RayCount& rays, const Hit& firstHit, DeferredPaths& out) const {
    DeferredSink sink{out};
    walkPath(origin, dir, dirPdf, rng, rays, &firstHit, sink);
    out.pathEnd_.push_back(uint32_t(out.terms_.size()));
    out.firstEmission_.push_back(sink.emitted);
    if (out.recordFirst_) out.first_.push_back(sink.first);
}

}  // namespace vdblight
