// Exact unshadowed irradiance of the lights a volume lists (direct_light.h), and the light's
// one-line text form. Everything in double: a lookup adds this to interpolated indirect light,
// and the polygon test compares it with numerical integration to 1e-4.

#include "vdblight/light/direct_light.h"

#include <cstdio>
#include <sstream>

#include "vdblight/core/errors.h"

namespace vdblight {

const char* directModeName(DirectMode mode) {
    switch (mode) {
        case DirectMode::Runtime: return "runtime";
        case DirectMode::Occlusion: return "occlusion";
        default: return "baked";
    }
}

DirectMode parseDirectMode(const std::string& name) {
    if (name == "baked") return DirectMode::Baked;
    if (name == "runtime") return DirectMode::Runtime;
    if (name == "occlusion") return DirectMode::Occlusion;
    throw ValueError("--direct must be baked, runtime or occlusion (got '" + name + "')");
}

void DirectLight::translate(const Vec3d& offset) {
    position += offset;
    for (auto& loop : loops)
        for (Vec3d& p : loop) p += offset;
}

Vec3d newellVector(const std::vector<Vec3d>& loop) {
    Vec3d sum;
    for (std::size_t i = 0; i < loop.size(); ++i) sum += cross(loop[i], loop[(i + 1) % loop.size()]);
    return sum;
}

double facingSide(const Vec3d& normal, const Vec3d& p, bool twoSided, const Vec3d& x) {
    const double side = dot(normal, x - p);
    if (side > 0) return 1;
    if (side < 0 && twoSided) return -1;
    return 0;
}

double DirectLight::area() const {
    double a = 0;
    for (const auto& loop : loops) {
        const Vec3d v = newellVector(loop);
        a += kind == Kind::Mesh ? 0.5 * length(v) : 0.5 * dot(v, normal);
    }
    return a;
}

DirectLight squareLight(const Vec3d& centre, const Vec3d& normal, double size, const Rgb& intensity) {
    if (!(length(normal) > 0)) throw ValueError("a square light's normal must not be zero");
    if (!(size > 0)) throw ValueError("a square light's size must be positive");
    DirectLight l;
    l.kind = DirectLight::Kind::Polygon;
    l.normal = normalize(normal);
    l.value = Rgb(Rgbd(intensity) / (size * size));
    Vec3f t1, t2;  // float tangents: the frame every user of a normal-only square shares
    orthonormalBasis(Vec3f(l.normal), t1, t2);
    const Vec3d a = Vec3d(t1) * (0.5 * size), b = Vec3d(t2) * (0.5 * size);
    l.loops = {{centre - a - b, centre + a - b, centre + a + b, centre - a + b}};
    l.position = centre;
    return l;
}

double spotFalloff(const DirectLight& s, const Vec3d& fromLight) {
    // The estimator's rule (radiance_estimator.cpp), in double.
    const double cosOuter = std::cos(s.outerCone), cosInner = std::cos(s.innerCone);
    const double c = dot(s.direction, fromLight);
    if (c <= cosOuter) return 0.0;
    if (cosInner - cosOuter <= 1e-6) return 1.0;
    const double t = std::min(1.0, (c - cosOuter) / (cosInner - cosOuter));
    return t * t;
}

namespace {

/// A loop's vertices during one evaluation: in place for up to kInline of them (every quad and
/// triangle light, clipped too), on the heap beyond. A query adds a light's exact irradiance at
/// every lookup (OcclusionLookup): it then allocates nothing and reads no thread-local state.
class Vertices {
public:
    explicit Vertices(std::size_t capacity) {
        if (capacity > kInline) {
            heap_.resize(capacity);
            data_ = heap_.data();
        }
    }
    Vertices(const Vertices&) = delete;
    Vertices& operator=(const Vertices&) = delete;
    void push_back(const Vec3d& v) { data_[size_++] = v; }
    std::size_t size() const { return size_; }
    const Vec3d& operator[](std::size_t i) const { return data_[i]; }

private:
    static constexpr std::size_t kInline = 16;
    Vec3d inline_[kInline];
    std::vector<Vec3d> heap_;
    Vec3d* data_ = inline_;
    std::size_t size_ = 0;
};

/// Sutherland-Hodgman clipping of a closed loop to the half-space dot(n, v) >= 0. For a
/// non-convex loop the result may run back and forth along the plane; those pieces lie on
/// one line through the receiver and their edge terms cancel, so the contour sum stays exact.
/// `out` holds at most 2 in.size() vertices (each edge adds at most two).
void clipToHemisphere(const Vertices& in, const Vec3d& n, Vertices& out) {
    const std::size_t m = in.size();
    for (std::size_t i = 0; i < m; ++i) {
        const Vec3d& a = in[i];
        const Vec3d& b = in[(i + 1) % m];
        const double da = dot(n, a), db = dot(n, b);
        if (da >= 0) out.push_back(a);
        if ((da >= 0) != (db >= 0)) {
            const double t = da / (da - db);
            out.push_back(a + (b - a) * t);
        }
    }
}

/// Signed solid angle of a loop seen from the origin (fan triangulation, Van Oosterom and
/// Strackee 1983); positive when the loop is counter-clockwise seen from the origin.
double loopSolidAngle(const Vertices& v) {
    double omega = 0;
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
        const Vec3d &a = v[0], &b = v[i], &c = v[i + 1];
        const double la = length(a), lb = length(b), lc = length(c);
        const double num = dot(a, cross(b, c));
        const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * std::atan2(num, den);
    }
    return omega;
}

/// The signed sum over the loops of `f(loop relative to x)` times the side each is seen from:
/// one side for a polygon (its normal), each triangle's own for a mesh.
template <typename F>
double sumOverLoops(const DirectLight& l, const Vec3d& x, F&& f) {
    double sum = 0;
    const double polygonSide =
        l.kind == DirectLight::Kind::Polygon && !l.loops.empty() && !l.loops[0].empty()
            ? facingSide(l.normal, l.loops[0][0], l.twoSided, x) : 0.0;
    for (const auto& loop : l.loops) {
        if (loop.empty()) continue;
        const double side = l.kind == DirectLight::Kind::Mesh ? facingSide(newellVector(loop), loop[0], l.twoSided, x) : polygonSide;
        if (side == 0) continue;
        Vertices rel(loop.size());
        for (const Vec3d& p : loop) rel.push_back(p - x);
        sum += side * f(rel);
    }
    return sum;
}

/// Lambert's formula for one closed loop of vertices relative to the receiver (v_i = p_i - x),
/// clipped to dot(n, v) >= 0: returns sum_i theta_i * dot(n, gamma_i) (signed; the loop's
/// orientation as seen from x decides the sign).
double lambertContour(const Vertices& relative, const Vec3d& n) {
    Vertices clipped(2 * relative.size());
    clipToHemisphere(relative, n, clipped);
    double sum = 0;
    const std::size_t m = clipped.size();
    if (m < 3) return 0;
    for (std::size_t i = 0; i < m; ++i) {
        const Vec3d c = cross(clipped[i], clipped[(i + 1) % m]);
        const double len = length(c);
        if (!(len > 0)) continue;  // an edge pointing at the receiver subtends no angle
        const double theta = std::atan2(len, dot(clipped[i], clipped[(i + 1) % m]));
        sum += theta * dot(n, c) / len;
    }
    return sum;
}

}  // namespace

Rgb exactIrradiance(const DirectLight& l, const Vec3d& x, const Vec3d& n) {
    switch (l.kind) {
        case DirectLight::Kind::Directional: {
            const double c = -dot(n, l.direction);
            return c > 0 ? Rgb(Rgbd(l.value) * c) : Rgb(0, 0, 0);
        }
        case DirectLight::Kind::Point:
        case DirectLight::Kind::Spot: {
            const Vec3d d = l.position - x;
            const double dist2 = dot(d, d);
            if (!(dist2 > 0)) return Rgb(0, 0, 0);
            const Vec3d w = d / std::sqrt(dist2);
            const double c = dot(n, w);
            if (!(c > 0)) return Rgb(0, 0, 0);
            const double falloff = l.kind == DirectLight::Kind::Spot ? spotFalloff(l, -w) : 1.0;
            return Rgb(Rgbd(l.value) * (c * falloff / dist2));
        }
        case DirectLight::Kind::Polygon:
        case DirectLight::Kind::Mesh: {
            // Loops run counter-clockwise around the front normal, i.e. clockwise as seen
            // from a receiver in front: the contour sum is then negative.
            const double sum = sumOverLoops(l, x, [&](const Vertices& rel) { return lambertContour(rel, n); });
            const double e = -0.5 * sum;
            return e > 0 ? Rgb(Rgbd(l.value) * e) : Rgb(0, 0, 0);
        }
    }
    return Rgb(0, 0, 0);
}

Rgb meanIrradiance(const DirectLight& l, const Vec3d& x) {
    switch (l.kind) {
        case DirectLight::Kind::Directional: return Rgb(Rgbd(l.value) * 0.25);
        case DirectLight::Kind::Point:
        case DirectLight::Kind::Spot: {
            const Vec3d d = x - l.position;
            const double dist2 = dot(d, d);
            if (!(dist2 > 0)) return Rgb(0, 0, 0);
            const double falloff = l.kind == DirectLight::Kind::Spot ? spotFalloff(l, d / std::sqrt(dist2)) : 1.0;
            return Rgb(Rgbd(l.value) * (0.25 * falloff / dist2));
        }
        case DirectLight::Kind::Polygon:
        case DirectLight::Kind::Mesh: {
            const double o = -sumOverLoops(l, x, [](const Vertices& rel) { return loopSolidAngle(rel); });
            return o > 0 ? Rgb(Rgbd(l.value) * (0.25 * o)) : Rgb(0, 0, 0);  // clockwise from the front, as above
        }
    }
    return Rgb(0, 0, 0);
}

// ---------------------------------------------------------------------------------------
// Text form: "kind=polygon;value=r g b;two_sided=0;normal=x y z;loop=x y z,x y z,..."

namespace {
const char* kindName(DirectLight::Kind k) {
    switch (k) {
        case DirectLight::Kind::Spot: return "spot";
        case DirectLight::Kind::Directional: return "directional";
        case DirectLight::Kind::Polygon: return "polygon";
        case DirectLight::Kind::Mesh: return "mesh";
        default: return "point";
    }
}

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
std::string vec(const Vec3d& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); }

Vec3d parseVec(const std::string& text, const std::string& where) {
    std::istringstream in(text);
    Vec3d v;
    if (!(in >> v.x >> v.y >> v.z) || !isFinite(v)) throw FormatError("light '" + where + "': bad vector '" + text + "'");
    std::string rest;
    if (in >> rest) throw FormatError("light '" + where + "': bad vector '" + text + "'");
    return v;
}
}  // namespace

std::string formatDirectLight(const DirectLight& l) {
    std::string s = std::string("kind=") + kindName(l.kind) + ";value=" + vec(Vec3d(l.value));
    switch (l.kind) {
        case DirectLight::Kind::Point: s += ";position=" + vec(l.position); break;
        case DirectLight::Kind::Spot:
            s += ";position=" + vec(l.position) + ";direction=" + vec(l.direction) + ";inner=" + num(l.innerCone) +
                 ";outer=" + num(l.outerCone);
            break;
        case DirectLight::Kind::Directional: s += ";direction=" + vec(l.direction); break;
        case DirectLight::Kind::Polygon:
        case DirectLight::Kind::Mesh:
            s += std::string(";two_sided=") + (l.twoSided ? "1" : "0");
            if (l.kind == DirectLight::Kind::Polygon) s += ";normal=" + vec(l.normal);
            for (const auto& loop : l.loops) {
                s += ";loop=";
                for (std::size_t i = 0; i < loop.size(); ++i) s += (i ? "," : "") + vec(loop[i]);
            }
            break;
    }
    return s;
}

DirectLight parseDirectLight(const std::string& text) {
    DirectLight l;
    bool haveKind = false, haveValue = false;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t end = std::min(text.find(';', start), text.size());
        const std::string item = text.substr(start, end - start);
        start = end + 1;
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos) throw FormatError("light '" + text.substr(0, 40) + "': item without '='");
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        if (key == "kind") {
            haveKind = true;
            if (value == "point") l.kind = DirectLight::Kind::Point;
            else if (value == "spot") l.kind = DirectLight::Kind::Spot;
            else if (value == "directional") l.kind = DirectLight::Kind::Directional;
            else if (value == "polygon") l.kind = DirectLight::Kind::Polygon;
            else if (value == "mesh") l.kind = DirectLight::Kind::Mesh;
            else throw FormatError("light kind '" + value + "' is not point, spot, directional, polygon or mesh");
        } else if (key == "value") {
            const Vec3d v = parseVec(value, key);
            if (v.x < 0 || v.y < 0 || v.z < 0) throw FormatError("light value must not be negative");
            l.value = Rgb(v);
            haveValue = true;
        } else if (key == "position") {
            l.position = parseVec(value, key);
        } else if (key == "direction") {
            const Vec3d d = parseVec(value, key);
            if (!(length(d) > 0)) throw FormatError("light direction must not be zero");
            l.direction = normalize(d);
        } else if (key == "normal") {
            const Vec3d d = parseVec(value, key);
            if (!(length(d) > 0)) throw FormatError("light normal must not be zero");
            l.normal = normalize(d);
        } else if (key == "inner" || key == "outer") {
            char* endp = nullptr;
            const double a = std::strtod(value.c_str(), &endp);
            if (endp == value.c_str() || *endp || !(a >= 0 && a <= kPi)) throw FormatError("light cone angle '" + value + "' is not in [0, pi]");
            (key == "inner" ? l.innerCone : l.outerCone) = a;
        } else if (key == "two_sided") {
            if (value != "0" && value != "1") throw FormatError("light two_sided must be 0 or 1");
            l.twoSided = value == "1";
        } else if (key == "loop") {
            std::vector<Vec3d> loop;
            std::size_t p = 0;
            while (p <= value.size()) {
                const std::size_t comma = std::min(value.find(',', p), value.size());
                loop.push_back(parseVec(value.substr(p, comma - p), key));
                p = comma + 1;
            }
            if (loop.size() < 3) throw FormatError("light loop has fewer than 3 vertices");
            l.loops.push_back(std::move(loop));
        } else {
            throw FormatError("light item '" + key + "' is unknown");
        }
    }
    if (!haveKind || !haveValue) throw FormatError("light '" + text.substr(0, 40) + "' lacks kind or value");
    if ((l.kind == DirectLight::Kind::Polygon || l.kind == DirectLight::Kind::Mesh) && l.loops.empty())
        throw FormatError("polygon or mesh light without loops");
    return l;
}

}  // namespace vdblight
