// queryCsv (volume_query.h): `vdblight query`'s answers at points as CSV, and the counts of
// answers the command warns about.
#include <sstream>

#include "vdblight/query/volume_query.h"

namespace vdblight {

QueryCsv queryCsv(const Query& query, const std::vector<Vec3d>& world, const std::vector<Vec3f>& normals) {
    std::ostringstream out;
    out.precision(9);
    out << "x,y,z,nx,ny,nz,E_r,E_g,E_b\n";
    QueryCsv csv;
    for (std::size_t i = 0; i < world.size(); ++i) {
        const QueryAnswer a = query.at(world[i], normals[i], i);
        csv.clamped += a.outside;
        csv.culled += a.culled;
        csv.negative += a.negative;
        const Vec3d x = query.farFromOrigin() ? world[i] : Vec3d(Vec3f(world[i]));  // near the origin: printed as before
        const Vec3f& n = a.normal;
        const Rgb& e = a.irradiance;
        out << x.x << ',' << x.y << ',' << x.z << ',' << n.x << ',' << n.y << ',' << n.z
            << ',' << e.x << ',' << e.y << ',' << e.z << '\n';
    }
    csv.text = out.str();
    return csv;
}

}  // namespace vdblight
