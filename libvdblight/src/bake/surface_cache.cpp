#include "surface_cache.h"

#include <algorithm>
#include <cmath>

#include "vdblight/trace.h"

namespace vdblight {
namespace bake_detail {

VolumeSurfaceCache::VolumeSurfaceCache(const Tracer& tracer, const GridSpec& grid, std::vector<Rgb> reflected)
    : tracer_(tracer), grid_(grid), coeffs_(std::move(reflected)) {
    for (std::size_t i = 0; i < coeffs_.size(); ++i)
        coeffs_[i] = coeffs_[i] * float(sh::kCosineLobe[sh::bandOf(int(i % sh::kCoeffs))]);
}

bool VolumeSurfaceCache::irradiance(const Vec3f& p, const Vec3f& n, Rgb& out, RayCount& rays) const {
    // Cell of p (clamped into the node box) and trilinear weights.
    const int dims[3] = {grid_.nx, grid_.ny, grid_.nz};
    int base[3];
    float frac[3];
    for (int a = 0; a < 3; ++a) {
        const double u = std::clamp((double(p[a]) - grid_.origin[a]) / grid_.spacing, 0.0, double(dims[a] - 1));
        base[a] = std::min(int(u), std::max(0, dims[a] - 2));
        frac[a] = dims[a] > 1 ? float(u - base[a]) : 0.0f;
    }
    float y[sh::kCoeffs];
    sh::evalUnrolled(n, y);
    Rgb sum{0, 0, 0};
    float weight = 0;
    for (int c = 0; c < 8; ++c) {
        int idx[3];
        float w = 1;
        for (int a = 0; a < 3; ++a) {
            const int bit = (c >> a) & 1;
            if (bit && dims[a] < 2) { w = 0; break; }
            idx[a] = base[a] + bit;
            w *= bit ? frac[a] : 1.0f - frac[a];
        }
        if (!(w > 0)) continue;
        const Vec3f node(grid_.node(idx[0], idx[1], idx[2]));
        const Vec3f d = node - p;
        if (!(dot(d, n) > 0)) continue;  // behind the surface: the other side's light
        ++rays.occluded;
        if (tracer_.occluded(Ray{p, d, 0.0f, 1.0f})) continue;
        const Rgb* c9 = coeffs_.data() + grid_.index(idx[0], idx[1], idx[2]) * sh::kCoeffs;
        Rgb e{0, 0, 0};
        for (int j = 0; j < sh::kCoeffs; ++j) e += c9[j] * y[j];
        sum += e * w;
        weight += w;
    }
    if (!(weight > 0)) return false;
    out = sum / weight;
    out = Rgb(std::max(0.0f, out.x), std::max(0.0f, out.y), std::max(0.0f, out.z));  // SH ringing
    return true;
}

}  // namespace bake_detail
}  // namespace vdblight
