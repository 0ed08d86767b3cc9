// readPointsCsv (reference.h): the points and normals `vdblight reference` and `query` read,
// one "x,y,z,nx,ny,nz" row each, with the positions also in double for worlds far from the
// origin (each row by parseNumberList, which the command line's number options share);
// referenceCsv: `vdblight reference`'s answers at them.
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "vdblight/core/errors.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"

namespace vdblight {

std::vector<double> parseNumberList(const std::string& text) {
    std::vector<double> values;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        std::size_t used = 0;
        double v;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            throw ValueError("'" + item + "' is not a number");
        }
        while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
        if (used != item.size()) throw ValueError("'" + item + "' is not a number");
        if (!std::isfinite(v)) throw ValueError("'" + item + "' is not a finite number");
        values.push_back(v);
    }
    return values;
}

std::vector<ReferencePoint> readPointsCsv(const std::string& path, std::vector<Vec3d>* worldPositions) {
    std::ifstream in(path);
    if (!in) throw IoError("cannot read points file '" + path + "'");
    std::vector<ReferencePoint> points;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        std::vector<double> v;
        try {
            v = parseNumberList(line);
        } catch (const ValueError& e) {
            if (points.empty() && lineNo == 1) continue;  // a header line
            throw ValueError(path + ":" + std::to_string(lineNo) + ": " + e.what());
        }
        if (v.size() != 6)
            throw ValueError(path + ":" + std::to_string(lineNo) + ": expected x,y,z,nx,ny,nz (6 numbers), got " +
                             std::to_string(v.size()));
        ReferencePoint p;
        p.position = Vec3f(float(v[0]), float(v[1]), float(v[2]));
        p.normal = Vec3f(float(v[3]), float(v[4]), float(v[5]));
        if (!(length(p.normal) > 0))
            throw ValueError(path + ":" + std::to_string(lineNo) + ": the normal is zero");
        points.push_back(p);
        if (worldPositions) worldPositions->emplace_back(v[0], v[1], v[2]);
    }
    if (points.empty()) throw ValueError("points file '" + path + "' has no rows");
    return points;
}

std::string referenceCsv(const Scene& scene, const std::vector<ReferencePoint>& points,
                         const std::vector<ReferenceResult>& results) {
    std::ostringstream out;
    out.precision(9);
    out << "x,y,z,nx,ny,nz,E_r,E_g,E_b,stderr_r,stderr_g,stderr_b\n";
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ReferencePoint& p = points[i];
        const Vec3f n = normalize(p.normal);
        const ReferenceResult& r = results[i];
        const Vec3d x = scene.toWorld(p.position);
        out << x.x << ',' << x.y << ',' << x.z << ',' << n.x << ',' << n.y << ',' << n.z
            << ',' << r.irradiance.x << ',' << r.irradiance.y << ',' << r.irradiance.z << ',' << r.standardError.x
            << ',' << r.standardError.y << ',' << r.standardError.z << '\n';
    }
    return out.str();
}

}  // namespace vdblight
