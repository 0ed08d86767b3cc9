// FastExactLights (fast_exact_lights.h): exactIrradiance's polygon term in float.
#include "fast_exact_lights.h"

#include <algorithm>
#include <cmath>

#include "float4.h"
#include "wide_vectors.h"

namespace vdblight::query_detail {

float atan2NonNegative(float y, float x) {
    // atan of t = min / max of (y, |x|) in [0, 1]; above tan(pi/8), of (t - 1) / (t + 1) plus
    // pi/4, so that the polynomial only sees |u| <= tan(pi/8).
    const float ax = std::fabs(x);
    const bool swap = y > ax;
    const float lo = swap ? ax : y, hi = swap ? y : ax;
    const bool upper = lo > 0.41421356f * hi;
    const float num = upper ? lo - hi : lo, den = upper ? lo + hi : hi;
    const float u = den > 0 ? num / den : 0.0f;
    // atan(u) = u + u^3 P(u^2): coefficients fitted here by least squares on the relative
    // error over |u| <= tan(pi/8); 7.7e-8 relative at most, evaluated in float.
    const float z = u * u;
    const float p = ((0.080687128f * z - 0.138829082f) * z + 0.199782744f) * z - 0.333329678f;
    float a = u + u * z * p;
    if (upper) a += 0.785398163f;  // pi/4
    if (swap) a = 1.57079633f - a;
    if (x < 0) a = 3.14159265f - a;
    return a;
}

namespace {
/// atan2NonNegative4's body, inlined into the contour (a call per four edges cost as much as
/// its arithmetic).
inline __attribute__((always_inline)) Float4 atan2Lanes(Float4 y, Float4 x) {
    // atan2NonNegative's operations, lane by lane, its branches as selects (a lane computes
    // both sides of a test and keeps the one the scalar code takes: the same bits).
    const Float4 zero = {0, 0, 0, 0};
    const Float4 ax = abs4(x);
    const auto swap = y > ax;
    const Float4 lo = swap ? ax : y, hi = swap ? y : ax;
    const auto upper = lo > 0.41421356f * hi;
    const Float4 num = upper ? lo - hi : lo, den = upper ? lo + hi : hi;
    const Float4 u = den > zero ? num / den : zero;
    const Float4 z = u * u;
    const Float4 p = ((0.080687128f * z - 0.138829082f) * z + 0.199782744f) * z - 0.333329678f;
    Float4 a = u + u * z * p;
    a = upper ? a + 0.785398163f : a;
    a = swap ? 1.57079633f - a : a;
    return x < zero ? 3.14159265f - a : a;
}
}  // namespace

Float4 atan2NonNegative4(Float4 y, Float4 x) { return atan2Lanes(y, x); }

FastExactLights::FastExactLights(const std::vector<DirectLight>& lights)
    : lights_(lights), punctual_(lights.size()), float_(lights.size(), 0), quad_(lights.size(), 0), triangleNormals_(lights.size()) {
    for (std::size_t i = 0; i < lights_.size(); ++i) {
        const DirectLight& l = lights_[i];
        if (l.kind == DirectLight::Kind::Point || l.kind == DirectLight::Kind::Spot || l.kind == DirectLight::Kind::Directional) {
            Punctual& p = punctual_[i];
            p.kind = int(l.kind);
            p.value = l.value;
            p.position = l.position;
            p.direction = Vec3f(l.direction);
            p.cosInner = float(std::cos(l.innerCone));  // as nanovdb_writer.cpp stores them
            p.cosOuter = float(std::cos(l.outerCone));
        }
        const bool mesh = l.kind == DirectLight::Kind::Mesh;
        bool small = (l.kind == DirectLight::Kind::Polygon || mesh) && !l.loops.empty() && !l.loops[0].empty();
        for (const auto& loop : l.loops) small = small && loop.size() <= kMaxVertices;
        float_[i] = small;
        quad_[i] = small && !mesh && l.loops.size() == 1 && l.loops[0].size() == 4;
        if (small && mesh)  // each triangle's front normal, as exactIrradiance takes it (once here)
            for (const auto& loop : l.loops) triangleNormals_[i].push_back(newellVector(loop));
    }
}

namespace {

/// A loop's vertices relative to the receiver, as plain floats (no per-call zeroing).
struct Points {
    float x[2 * FastExactLights::kMaxVertices], y[2 * FastExactLights::kMaxVertices], z[2 * FastExactLights::kMaxVertices];
    std::size_t size = 0;
    void push(float px, float py, float pz) {
        x[size] = px;
        y[size] = py;
        z[size] = pz;
        ++size;
    }
};

/// `sum` plus the terms theta_i dot(n, gamma_i) of the edges from a_k to b_k in the first
/// `edges` lanes (each lane the scalar formula's float operations, its term added in float in
/// lane order, as one edge at a time would: the order and precision of the NanoVDB shader's
/// sum, shaders/vdblight_nanovdb_lights.h, so that the two give the same bits; issue 33).
VDBLIGHT_ALWAYS_INLINE float addEdgeTerms(Float4 ax, Float4 ay, Float4 az, Float4 bx, Float4 by, Float4 bz, const Vec3f& n,
                                          std::size_t edges, float sum) {
    const Float4 gx = ay * bz - az * by, gy = az * bx - ax * bz, gz = ax * by - ay * bx;
    const Float4 squared = gx * gx + gy * gy + gz * gz;
    const Float4 len = sqrt4(squared);
    const Float4 theta = atan2Lanes(len, ax * bx + ay * by + az * bz);
    const Float4 zero = {0, 0, 0, 0};
    // An edge pointing at the receiver (len 0) subtends no angle: its term is +0, which
    // leaves the sum as skipping it would (but for the sign of a zero sum, which the
    // caller's e > 0 test does not see); so is a lane past the last edge.
    Float4 term = theta * (n.x * gx + n.y * gy + n.z * gz) / len;
    term = len > zero ? term : zero;
    if (edges < 4) term = Float4{0, 1, 2, 3} < float(edges) ? term : zero;
    sum += term[0];
    sum += term[1];
    sum += term[2];
    sum += term[3];
    return sum;
}

/// Lambert's contour term of one loop (vertices relative to the receiver) clipped to the
/// hemisphere dot(n, v) >= 0: sum_i theta_i dot(n, gamma_i), as exact_irradiance.cpp's
/// lambertContour, in float.
float contour(const Points& v, const Vec3f& n) {
    std::size_t m = v.size;
    float d[FastExactLights::kMaxVertices];
    bool allAbove = true;
    for (std::size_t i = 0; i < m; ++i) {
        d[i] = n.x * v.x[i] + n.y * v.y[i] + n.z * v.z[i];
        allAbove = allAbove && d[i] >= 0;
    }
    // Sutherland-Hodgman against the plane through the receiver (at most two vertices per edge).
    Points clipped;
    const Points* c = &v;
    if (!allAbove) {
        for (std::size_t i = 0; i < m; ++i) {
            const std::size_t j = i + 1 == m ? 0 : i + 1;
            if (d[i] >= 0) clipped.push(v.x[i], v.y[i], v.z[i]);
            if ((d[i] >= 0) != (d[j] >= 0)) {
                const float t = d[i] / (d[i] - d[j]);
                clipped.push(v.x[i] + (v.x[j] - v.x[i]) * t, v.y[i] + (v.y[j] - v.y[i]) * t, v.z[i] + (v.z[j] - v.z[i]) * t);
            }
        }
        c = &clipped;
        m = clipped.size;
    }
    if (m < 3) return 0;
    // The edges four at a time in the lanes of Float4 (edge i from vertex i to vertex i + 1,
    // the first vertex repeated at the end).
    float ex[2 * FastExactLights::kMaxVertices + 4], ey[2 * FastExactLights::kMaxVertices + 4],
        ez[2 * FastExactLights::kMaxVertices + 4];
    for (std::size_t i = 0; i < m; ++i) ex[i] = c->x[i], ey[i] = c->y[i], ez[i] = c->z[i];
    for (std::size_t i = m; i < m + 4; ++i) ex[i] = c->x[0], ey[i] = c->y[0], ez[i] = c->z[0];
    float sum = 0;
    for (std::size_t i = 0; i < m; i += 4)
        sum = addEdgeTerms(load4(ex + i), load4(ey + i), load4(ez + i), load4(ex + i + 1), load4(ey + i + 1), load4(ez + i + 1), n,
                           std::min<std::size_t>(4, m - i), sum);
    return sum;
}

/// contour() of a loop of four vertices (relative to the receiver, in the lanes of rx, ry, rz),
/// the same bits: where all four are above the receiver's plane (nothing to clip) its edges are
/// the lanes against their next lane, without going through memory (the general path stores
/// the vertices one float at a time and reads them back as vectors, which waits for the
/// stores); where all are below, 0 (what clipping leaves); else the general path.
VDBLIGHT_ALWAYS_INLINE float quadContour(Float4 rx, Float4 ry, Float4 rz, const Vec3f& n) {
    const Float4 d = n.x * rx + n.y * ry + n.z * rz;  // contour()'s d[i], the same operations
    const bool above[4] = {d[0] >= 0, d[1] >= 0, d[2] >= 0, d[3] >= 0};
    if (above[0] && above[1] && above[2] && above[3]) {
        const Float4 nx = {rx[1], rx[2], rx[3], rx[0]}, ny = {ry[1], ry[2], ry[3], ry[0]}, nz = {rz[1], rz[2], rz[3], rz[0]};
        return addEdgeTerms(rx, ry, rz, nx, ny, nz, n, 4, 0.0f);
    }
    if (!above[0] && !above[1] && !above[2] && !above[3]) return 0.0f;
    Points v;
    for (int k = 0; k < 4; ++k) v.push(rx[k], ry[k], rz[k]);
    return contour(v, n);
}

}  // namespace

Vec3f floatPathNormal(const Vec3f& n) {
    const float squared = dot(n, n);
    return std::fabs(1.0f - squared) <= kUnitSquaredLength ? n : Vec3f(normalize(Vec3d(n)));
}

Rgb FastExactLights::punctual(const Punctual& p, const Vec3d& x, const Vec3f& n) const {
    // vdblight_nano_light_irradiance's operations in their order (exactIrradiance's formulas;
    // dot and the vector products of core/math.h are the shader's vdblight_nano_dot and _scale).
    if (p.kind == int(DirectLight::Kind::Directional)) {
        const float c = -dot(n, p.direction);
        return c > 0.0f ? p.value * c : Rgb(0, 0, 0);
    }
    // The position minus x rounded once: the shader's float difference where both are floats.
    const Vec3f d(p.position - x);
    const float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return Rgb(0, 0, 0);
    const Vec3f w = d * (1.0f / std::sqrt(dist2));
    const float c = dot(n, w);
    if (!(c > 0.0f)) return Rgb(0, 0, 0);
    float falloff = 1.0f;
    if (p.kind == int(DirectLight::Kind::Spot)) {
        const float ca = -dot(p.direction, w);
        if (ca <= p.cosOuter) return Rgb(0, 0, 0);
        if (p.cosInner - p.cosOuter > 1e-6f) {
            const float t = std::min(1.0f, (ca - p.cosOuter) / (p.cosInner - p.cosOuter));
            falloff = t * t;
        }
    }
    return p.value * (c * falloff / dist2);
}

Rgb FastExactLights::irradiance(std::size_t i, const Vec3d& x, const Vec3d& n, const Vec3f& nf) const {
    const DirectLight& l = lights_[i];
    if (punctual_[i].kind >= 0) return punctual(punctual_[i], x, nf);
    if (!float_[i]) return exactIrradiance(l, x, n);
    const bool mesh = l.kind == DirectLight::Kind::Mesh;
    // The side of the plane x sees, in double as exactIrradiance decides it: the polygon's
    // plane, or (below) each of a mesh's triangles' own.
    const float side = mesh ? 0.0f : float(facingSide(l.normal, l.loops[0][0], l.twoSided, x));
    if (!mesh && side == 0) return Rgb(0, 0, 0);
    // The sums in float, as the shader's (above).
    float sum = 0;
    if (quad_[i]) {  // one loop of four vertices: the quads' path, the same bits
        const auto& q = l.loops[0];
        const Float4 rx = {float(q[0].x - x.x), float(q[1].x - x.x), float(q[2].x - x.x), float(q[3].x - x.x)},
                     ry = {float(q[0].y - x.y), float(q[1].y - x.y), float(q[2].y - x.y), float(q[3].y - x.y)},
                     rz = {float(q[0].z - x.z), float(q[1].z - x.z), float(q[2].z - x.z), float(q[3].z - x.z)};
        sum += side * quadContour(rx, ry, rz, nf);
        const float e = -0.5f * sum;
        return e > 0 ? l.value * e : Rgb(0, 0, 0);
    }
    for (std::size_t k = 0; k < l.loops.size(); ++k) {
        const auto& loop = l.loops[k];
        if (loop.empty()) continue;
        const float loopSide = mesh ? float(facingSide(triangleNormals_[i][k], loop[0], l.twoSided, x)) : side;
        if (loopSide == 0) continue;
        Points rel;
        for (const Vec3d& p : loop) rel.push(float(p.x - x.x), float(p.y - x.y), float(p.z - x.z));
        sum += loopSide * contour(rel, nf);
    }
    // Loops run counter-clockwise around the front normal: the contour sum is negative in front.
    const float e = -0.5f * sum;
    return e > 0 ? l.value * e : Rgb(0, 0, 0);
}

}  // namespace vdblight::query_detail
