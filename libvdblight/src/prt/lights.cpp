// Example light positions for the direct-light basis (4.3.1) and the inside-a-solid test.
#include <algorithm>
#include <cmath>
#include <limits>

#include "prt_internal.h"
#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

bool insideSolid(const Tracer& tracer, const Vec3f& p) {
    static const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    int back = 0;
    for (const Vec3f& d : dirs) {
        const Hit h = tracer.intersect(Ray{p, d});
        if (h.hit() && dot(h.geometricNormal, d) > 0.0f) ++back;
    }
    return back >= 4;
}

std::vector<Vec3f> trainingLightPositions(const Scene& scene, const Tracer& tracer, uint32_t count) {
    const Bounds b = scene.bounds();
    const Vec3d lo = b.lo + b.size() * 0.02, size = b.size() * 0.96;
    std::vector<Vec3f> out;
    const uint64_t limit = uint64_t(count) * 64 + 64;
    for (uint64_t i = 1; out.size() < count && i <= limit; ++i) {
        const Vec3f p(Vec3d{lo.x + size.x * radicalInverse(2, i), lo.y + size.y * radicalInverse(3, i),
                            lo.z + size.z * radicalInverse(5, i)});
        if (!insideSolid(tracer, p)) out.push_back(p);
    }
    if (out.empty()) throw SceneError("no example light position outside solids: is the scene closed inside out?");
    return out;
}

std::vector<PrtPointLight> trainingLights(const Scene& scene, const Tracer& tracer, uint32_t count,
                                          float orientedFraction) {
    const double f = std::clamp(double(orientedFraction), 0.0, 16.0);
    const uint32_t extra = uint32_t(std::lround(double(count) * f));
    const std::vector<Vec3f> positions = trainingLightPositions(scene, tracer, count + extra);
    static const Vec3f axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<PrtPointLight> out;
    for (std::size_t k = 0; k < positions.size(); ++k) {
        Vec3f n{0, 0, 0};
        if (k >= count) {
            // Facing away from the nearest surface along the six axes (a lamp mounted on it),
            // else (nothing hit) a Halton-random direction.
            n = uniformSphere(float(radicalInverse(7, k + 1)), float(radicalInverse(11, k + 1)));
            float nearest = std::numeric_limits<float>::infinity();
            for (const Vec3f& d : axes) {
                const Hit h = tracer.intersect(Ray{positions[k], d});
                if (h.hit() && h.t < nearest) nearest = h.t, n = d * -1.0f;
            }
        }
        out.push_back(PrtPointLight{positions[k], n, 1.0f});
    }
    return out;
}

bool prtInsideSolid(const PrtData& prt, const Vec3f& p) {
    const SurfaceSamples& s = prt.samples;
    const std::size_t k = std::min<std::size_t>(8, s.size());
    if (k == 0) return false;
    std::vector<std::pair<float, std::size_t>> d(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) d[i] = {dot(s.position[i] - p, s.position[i] - p), i};
    std::partial_sort(d.begin(), d.begin() + std::ptrdiff_t(k), d.end());
    std::size_t behind = 0;
    for (std::size_t a = 0; a < k; ++a)
        if (dot(s.normal[d[a].second], p - s.position[d[a].second]) < 0.0f) ++behind;
    return behind * 4 >= k * 3;
}

}  // namespace vdblight
