// findShadowEdge (shadow_edge_search.h): where the centre ray towards a light changes from
// blocked to free around a node, and the penumbra's width there.

#include "shadow_edge_search.h"

#include <algorithm>
#include <cmath>

#include "basis/shadow_edges.h"
#include "bake/light_reach.h"
#include "vdblight/trace/trace.h"

namespace vdblight::bake_detail {

namespace {

constexpr int kDirections = 12;      // 30 degrees apart: the nearest is at most 3.5 % too far
constexpr float kStepCells = 0.25f;  // march step
constexpr int kBisections = 4;       // a quarter cell / 16 = 1/64 cell
constexpr float kMinBlockerCells = 2.0f;  // farSide: a strip's blockers beyond the cell's extent
constexpr float kShadowEnd = 1.0f - 1e-4f;  // as lightVisibility's rays: stop short of the light

/// Area centroid of a planar polygon light (loops signed around its normal).
Vec3d polygonCentroid(const DirectLight& l) {
    Vec3d sum(0, 0, 0);
    double area = 0;
    for (const std::vector<Vec3d>& loop : l.loops)
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
            const double a = 0.5 * dot(cross(loop[i] - loop[0], loop[i + 1] - loop[0]), l.normal);
            sum = sum + (loop[0] + loop[i] + loop[i + 1]) * (a / 3.0);
            area += a;
        }
    return area != 0 ? sum / area : (l.loops.empty() || l.loops[0].empty() ? l.position : l.loops[0][0]);
}

/// The light's extent along the unit direction e (its vertices' spread; 0 for a point).
double extentAlong(const DirectLight& l, const Vec3d& e) {
    double lo = 0, hi = 0;
    bool first = true;
    for (const std::vector<Vec3d>& loop : l.loops)
        for (const Vec3d& v : loop) {
            const double s = dot(v, e);
            lo = first ? s : std::min(lo, s);
            hi = first ? s : std::max(hi, s);
            first = false;
        }
    return hi - lo;
}

class CentreRay {
public:
    CentreRay(const Tracer& tracer, const SceneLight& light)
        : tracer_(tracer), light_(light.light), directional_(light_.kind == DirectLight::Kind::Directional),
          centre_(light_.kind == DirectLight::Kind::Polygon ? polygonCentroid(light_) : light_.position), reach_(light_) {}
    Ray ray(const Vec3f& p) const {
        if (directional_) return Ray{p, -Vec3f(light_.direction)};
        return Ray{p, Vec3f(centre_) - p, 0.0f, kShadowEnd};
    }
    /// Blocked towards the centre; a point the light cannot reach counts as free (bake_direct.h).
    bool blocked(const Vec3f& p, RayCount& rays) const {
        if (!reach_.reaches(Vec3d(p))) return false;
        ++rays.occluded;
        return tracer_.occluded(ray(p));
    }
    /// Distance from p to the first blocker towards the centre, and to the centre (metres).
    void distances(const Vec3f& p, double& blocker, double& centre, RayCount& rays) const {
        const Ray r = ray(p);
        ++rays.intersect;
        const Hit h = tracer_.intersect(r);
        centre = directional_ ? HUGE_VAL : double(length(r.direction));
        blocker = h.hit() ? double(h.t) * double(length(r.direction)) : centre;
    }
    Vec3f towards(const Vec3f& x) const { return directional_ ? -Vec3f(light_.direction) : Vec3f(centre_) - x; }

private:
    const Tracer& tracer_;
    const DirectLight& light_;
    bool directional_;
    Vec3d centre_;
    LightReach reach_;
};

/// True if the blocker in front of shadowed point p is at least kMinBlockerCells away along the
/// centre ray: the shadow's boundary there is the light's rays past a blocker's outline, which
/// runs through the cell along the light, as the strip's model assumes (shadow_edges.h). Next to
/// a blocker's own surface (a wall, a roof) the boundary is that surface instead.
bool blockerBeyondCell(const CentreRay& centre, const Vec3f& p, float spacing, RayCount& rays) {
    double blocker = 0, toCentre = 0;
    centre.distances(p, blocker, toCentre, rays);
    return blocker >= kMinBlockerCells * spacing;
}

/// Cells from x to where its own side (`blocked`) comes back along e, past the nearest change
/// (whose bisection ended at `across`, metres, and whose shadowed side is `nearShadow`), within
/// kMaxStrip cells of it; 0 if it does not, if a blocker of either edge is within
/// kMinBlockerCells (blockerBeyondCell), or if the strip's middle a quarter cell to either side (along
/// `side`, in the plane, across e) is not in the strip too: a search that cut across the corner of
/// a shadow (or of a lit region) found a tip, not a strip of two edges side by side, which is
/// what the lookup's model is. Eighth-cell steps: a strip a quarter of a cell wide is not stepped over.
float farSide(const CentreRay& centre, const Vec3f& x, const Vec3f& e, const Vec3f& side, bool blocked, float across,
              const Vec3f& nearShadow, float spacing, float nearCells, RayCount& rays) {
    const float step = 0.5f * kStepCells * spacing;
    const int steps = int(std::lround(shadow_edge::kMaxStrip / (0.5f * kStepCells)));
    const float limit = shadow_edge::kRange * spacing;
    for (int j = 1; j <= steps; ++j) {
        float lo = across + step * float(j - 1), hi = std::min(across + step * float(j), limit);
        if (lo >= limit) break;
        if (centre.blocked(x + e * hi, rays) != blocked) continue;
        for (int i = 0; i < kBisections; ++i) {  // keep lo in the strip, hi back on x's side
            const float mid = 0.5f * (lo + hi);
            (centre.blocked(x + e * mid, rays) != blocked ? lo : hi) = mid;
        }
        const Vec3f middle = x + e * (0.5f * (across + lo)), beside = side * (0.25f * spacing);
        if (centre.blocked(middle + beside, rays) == blocked || centre.blocked(middle - beside, rays) == blocked) return 0.0f;
        const Vec3f farShadow = x + e * (blocked ? hi : lo);
        if (!blockerBeyondCell(centre, nearShadow, spacing, rays) || !blockerBeyondCell(centre, farShadow, spacing, rays)) return 0.0f;
        // Past the stored near distance, so the strip keeps a width in the lookup's model.
        return std::max(0.5f * (lo + hi) / spacing, nearCells + 0.5f * shadow_edge::kMinWidth);
    }
    return 0.0f;
}

}  // namespace

void storeShadowEdge(const ShadowEdge& e, float* out) {
    out[shadow_edge::kDistance] = e.distance;
    out[shadow_edge::kWidth] = e.width;
    out[shadow_edge::kDirectionX] = e.direction.x;
    out[shadow_edge::kDirectionY] = e.direction.y;
    out[shadow_edge::kDirectionZ] = e.direction.z;
    out[shadow_edge::kFar] = e.far;
}

bool centreRayBlocked(const Tracer& tracer, const SceneLight& light, const Vec3f& x, RayCount& rays) {
    if (light.light.kind == DirectLight::Kind::Mesh) return false;  // findShadowEdge traces none
    return CentreRay(tracer, light).blocked(x, rays);
}

ShadowEdge findShadowEdge(const Scene& scene, const Tracer& tracer, const SceneLight& light, const Vec3f& x, double spacing,
                          RayCount& rays) {
    const DirectLight& l = light.light;
    if (l.kind == DirectLight::Kind::Mesh) return {0.0f, shadow_edge::kNoEdge};  // its centre is inside it
    (void)scene;
    const CentreRay centre(tracer, light);
    const Vec3f axis = centre.towards(x);
    if (!(dot(axis, axis) > 0)) return {shadow_edge::kRange, 0.0f};
    Vec3f t, b;
    orthonormalBasis(normalize(axis), t, b);
    const bool blocked = centre.blocked(x, rays);
    const float step = float(spacing) * kStepCells;
    const int steps = int(std::lround(shadow_edge::kRange / kStepCells));
    float best = float(spacing) * shadow_edge::kRange;  // metres
    float bestHi = best;  // the bisection's end across the nearest change
    Vec3f bestDir(0, 0, 0), shadowSide(0, 0, 0);
    bool found = false;
    for (int k = 0; k < kDirections; ++k) {
        const double angle = 2.0 * kPi * k / kDirections;
        const Vec3f e = t * float(std::cos(angle)) + b * float(std::sin(angle));
        for (int j = 1; j <= steps; ++j) {
            float lo = step * float(j - 1), hi = step * float(j);
            if (lo >= best) break;  // any change here is no nearer than the one found
            if (centre.blocked(x + e * hi, rays) == blocked) continue;
            for (int i = 0; i < kBisections; ++i) {  // keep lo on x's side, hi across
                const float mid = 0.5f * (lo + hi);
                (centre.blocked(x + e * mid, rays) == blocked ? lo : hi) = mid;
            }
            const float d = 0.5f * (lo + hi);
            if (d < best) {
                best = d;
                bestHi = hi;
                bestDir = e;
                shadowSide = x + e * (blocked ? lo : hi);
                found = true;
            }
            break;
        }
    }
    ShadowEdge edge;
    // At least half the smallest ramp width from the edge: a node's own ramp then gives its
    // own side exactly (0 or 1), so a hard light's node leaves no residual for the lookup to
    // blend over the cell (shadow_edges.h); the edge moves by at most 1/32 cell.
    const float cells = found ? std::clamp(best / float(spacing), 0.5f * shadow_edge::kMinWidth, shadow_edge::kRange)
                              : shadow_edge::kRange;  // exactly: what a skipped search stores (shadow_edge_lattice.h)
    edge.distance = blocked ? -cells : cells;
    if (found) {
        const Vec3f side = normalize(cross(axis, bestDir));
        edge.far = farSide(centre, x, bestDir, side, blocked, bestHi, shadowSide, float(spacing), cells, rays);
        // Only a strip's lookup reads the direction (shadow_edges.h): elsewhere 0, which the file
        // compresses to almost nothing.
        if (edge.far > 0.0f) edge.direction = bestDir;
    }
    if (found && l.kind == DirectLight::Kind::Polygon) {
        double blocker = 0, toCentre = 0;
        centre.distances(shadowSide, blocker, toCentre, rays);
        const double size = extentAlong(l, Vec3d(bestDir));
        const double width = size * blocker / std::max(toCentre - blocker, 1e-3 * toCentre) / spacing;
        edge.width = float(std::min(width, 4.0 * shadow_edge::kRange));
    }
    // A strip no wider than its penumbra has no edges side by side to hold: the two penumbrae
    // overlap into one dip, which the node's visibility and the residual already carry.
    if (edge.far > 0.0f && edge.width >= edge.far - cells) {
        edge.far = 0.0f;
        edge.direction = Vec3f(0, 0, 0);
    }
    return edge;
}

}  // namespace vdblight::bake_detail
