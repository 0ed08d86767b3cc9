// What `vdblight prt relight` makes of a relighting besides the volume (prt.h): the per-sample
// table (CSV or ASCII PLY) and the errors against the uncompressed reference (--reference).
#include <iomanip>
#include <sstream>

#include "vdblight/prt/prt.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight {

std::string prtLightingTable(const PrtData& prt, const PrtLighting& lit, bool ply) {
    const SurfaceSamples& s = prt.samples;
    std::ostringstream out;
    out.precision(7);
    if (ply) {
        out << "ply\nformat ascii 1.0\ncomment vdblight prt relight: irradiance W/m^2, radiance W/(m^2 sr)\n"
            << "element vertex " << s.size() << "\n";
        for (const char* p : {"x", "y", "z", "nx", "ny", "nz"}) out << "property float " << p << "\n";
        out << "property int cluster\n";
        for (const char* p : {"direct", "indirect", "radiance"})
            for (const char* ch : {"_r", "_g", "_b"}) out << "property float " << p << ch << "\n";
        out << "end_header\n";
    } else {
        out << "x,y,z,nx,ny,nz,cluster,direct_r,direct_g,direct_b,indirect_r,indirect_g,indirect_b,radiance_r,"
               "radiance_g,radiance_b\n";
    }
    const char sep = ply ? ' ' : ',';
    // Far from the origin, positions need their double digits (near it, 7 as the values).
    const int positionDigits = prt.origin == Vec3d(0, 0, 0) ? 7 : 15;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const Vec3d p = prt.origin + Vec3d(s.position[i]);  // world position
        const Vec3f& n = s.normal[i];
        const Rgb& d = lit.direct[i];
        const Rgb& e = lit.indirect[i];
        const Rgb l = s.albedo[i] * (d + e) * float(kInvPi);
        out << std::setprecision(positionDigits) << p.x << sep << p.y << sep << p.z << std::setprecision(7) << sep << n.x << sep << n.y << sep << n.z << sep << s.cluster[i];
        for (const Rgb& v : {d, e, l}) out << sep << v.x << sep << v.y << sep << v.z;
        out << '\n';
    }
    return out.str();
}

PrtReferenceErrors prtReferenceErrors(const PrtData& prt, const PrtLighting& lit, const std::vector<DirectLight>& lights,
                                      const Scene& scene, const Tracer& tracer, int threads) {
    std::vector<Rgb> direct(prt.samples.size(), Rgb{0, 0, 0});
    for (const DirectLight& l : lights) {
        const std::vector<float> d = exactDirectLight(prt.samples, scene, tracer, l, threads);
        for (std::size_t i = 0; i < d.size(); ++i) direct[i] += l.value * d[i];
    }
    // Uncompressed bounces with the bake's form factors (closure-normalised as baked).
    const std::vector<float> F = sampleFormFactors(prt.samples, tracer, threads, nullptr, prt.closureNormalise);
    const std::vector<Rgb> indirect = bounceIndirect(prt.samples, F, direct, prt.bounces);
    return {rmsRelativeError(lit.direct, direct), rmsRelativeError(lit.indirect, indirect)};
}

}  // namespace vdblight
