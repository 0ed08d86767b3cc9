// The lights of `vdblight prt relight` given as text (prt.h: parsePointLightSpec,
// parseAreaLightSpec) in world coordinates, and the warning for a light placed where the
// compressed basis was not trained (prtLightWarning).
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>

#include "vdblight/core/errors.h"
#include "vdblight/prt/prt.h"

namespace vdblight {

namespace {
/// The comma-separated numbers of `option` '`text`': one of `counts` of them, all finite.
std::vector<double> parseNumbers(const std::string& text, const std::string& option, const std::string& form,
                                 std::initializer_list<std::size_t> counts) {
    const std::string what = option + " '" + text + "': ";
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            v.push_back(std::stod(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw ValueError(what + "expected " + form + " numbers");
        }
    }
    if (std::find(counts.begin(), counts.end(), v.size()) == counts.end()) throw ValueError(what + "expected " + form);
    for (double x : v)
        if (!std::isfinite(x)) throw ValueError(what + "numbers must be finite");
    return v;
}

/// The optional r,g,b at v[first..first+2] (W/sr, not negative); white without them.
Rgb parseIntensity(const std::vector<double>& v, std::size_t first, const std::string& option, const std::string& text) {
    if (v.size() < first + 3) return Rgb{1, 1, 1};
    if (v[first] < 0 || v[first + 1] < 0 || v[first + 2] < 0) {
        throw ValueError(option + " '" + text + "': intensity must not be negative");
    }
    return Rgb(Vec3d{v[first], v[first + 1], v[first + 2]});
}

/// An isotropic square of side `size` in the XZ plane (--area-size): samples x samples point
/// lights at its cell centres sharing `intensity`.
std::vector<DirectLight> squarePointLights(const Vec3d& centre, double size, int samples, const Rgb& intensity) {
    DirectLight point;
    point.kind = DirectLight::Kind::Point;
    const int m = std::max(1, samples);
    point.value = Rgb(Rgbd(intensity) / double(m * m));
    std::vector<DirectLight> lights;
    for (int a = 0; a < m * m; ++a) {
        const double u = size * ((double(a % m) + 0.5) / m - 0.5), w = size * ((double(a / m) + 0.5) / m - 0.5);
        point.position = centre + Vec3d{u, 0, w};
        lights.push_back(point);
    }
    return lights;
}

}  // namespace

/// --area-light x,y,z,nx,ny,nz,size[,r,g,b]: a square emitting on the side of the normal, the
/// intensity along the normal (a polygon light: squareLight).
PrtLightSpec parseAreaLightSpec(const std::string& text) {
    const std::vector<double> v =
        parseNumbers(text, "--area-light", "x,y,z,nx,ny,nz,size or x,y,z,nx,ny,nz,size,r,g,b", {7, 10});
    const Vec3d centre{v[0], v[1], v[2]}, normal{v[3], v[4], v[5]};
    if (!(length(normal) > 0)) throw ValueError("--area-light '" + text + "': the normal must not be zero");
    if (!(v[6] > 0)) throw ValueError("--area-light '" + text + "': size must be positive");
    return {{squareLight(centre, normal, v[6], parseIntensity(v, 7, "--area-light", text))}, centre};
}

/// --light x,y,z[,r,g,b]: a point light, or, with --area-size > 0, an isotropic square of that
/// side in the XZ plane: samples x samples point lights at its cell centres sharing the intensity.
PrtLightSpec parsePointLightSpec(const std::string& text, double size, int samples) {
    const std::vector<double> v = parseNumbers(text, "--light", "x,y,z or x,y,z,r,g,b", {3, 6});
    const Vec3d centre{v[0], v[1], v[2]};
    const Rgb intensity = parseIntensity(v, 3, "--light", text);
    if (!(size > 0)) {
        DirectLight point;
        point.kind = DirectLight::Kind::Point;
        point.value = intensity;
        point.position = centre;
        return {{point}, centre};
    }
    return {squarePointLights(centre, size, samples, intensity), centre};
}


std::string prtLightWarning(const PrtData& prt, const Tracer* tracer, const Vec3d& world) {
    std::ostringstream at;
    at.precision(10);
    at << world.x << "," << world.y << "," << world.z;
    const Vec3f local = prtLocal(prt, world);
    if (!prt.bounds.contains(Vec3d(local)))
        return at.str() + " is outside the scene bounds (lit as given; the basis was trained inside)";
    if (tracer ? insideSolid(*tracer, local) : prtInsideSolid(prt, local))
        return at.str() + " is inside a solid (lit as given" +
               (tracer ? "" : "; judged from the samples, give --scene for the exact test") + ")";
    return {};
}

}  // namespace vdblight
