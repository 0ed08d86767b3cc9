// vdblight_bench_accuracy: the points, the ground truth at them (reference.h, cached) and the
// statistics of relative errors.
#include "accuracy.h"

#include <cstring>
#include <fstream>

#include <tbb/parallel_for.h>

#include "vdblight/reference/reference.h"

namespace vdblight::accuracy {

namespace {
/// True if no surface lies within `clearance` of x along 26 directions (axes, face and body
/// diagonals): the point is not in a crevice (under a book, between a board and the floor),
/// where a relative error measures nothing any volume could hold.
bool clearOfSurfaces(const Tracer& tracer, const Vec3f& x, float clearance) {
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dz = -1; dz <= 1; ++dz) {
                if (!dx && !dy && !dz) continue;
                const Hit h = tracer.intersect(Ray{x, normalize(Vec3f(float(dx), float(dy), float(dz))), 0.0f, clearance});
                if (h.hit()) return false;
            }
    return true;
}
}  // namespace

/// `count` free-space points uniformly in the scene box (inset by 0.1 % of its size), at least
/// 1 % of the box diagonal from every surface (clearOfSurfaces), with uniformly random unit
/// normals, from a fixed seed.
Points freeSpacePoints(const Scene& s, const Tracer& tracer, int count) {
    Rng rng(2026, 15);
    const Bounds box = s.bounds();
    const float clearance = float(0.01 * length(box.size()));
    Points p;
    for (int tries = 0; int(p.x.size()) < count && tries < 1000 * count; ++tries) {
        const Vec3d t(0.001 + 0.998 * rng.uniform(), 0.001 + 0.998 * rng.uniform(), 0.001 + 0.998 * rng.uniform());
        const Vec3f x(box.lo + box.size() * t);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        if (!bench::freeSpace(tracer, x) || !clearOfSurfaces(tracer, x, clearance)) continue;
        p.x.push_back(x);
        p.n.push_back(n);
    }
    return p;
}

namespace {
std::string pointsHash(const Points& p) {
    uint64_t h = 0x15ull;
    for (std::size_t i = 0; i < p.x.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const float fx = p.x[i][k], fn = p.n[i][k];
            uint32_t a, b;
            std::memcpy(&a, &fx, 4);
            std::memcpy(&b, &fn, 4);
            h = hashCombine(hashCombine(h, a), b);
        }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}
}  // namespace

Truth groundTruth(const Scene& s, const Tracer& tracer, const Points& p, const Settings& st, uint32_t samples) {
    fs::create_directories(st.cache);
    const fs::path file = st.cache / (s.contentHash() + "_" + pointsHash(p) + "_" + std::to_string(samples) + "s_" +
                                      std::to_string(st.refBounces) + "b_seed1.txt");
    Truth t;
    if (std::ifstream in{file}) {
        double a, b;
        while (in >> a >> b) t.e.push_back(a), t.se.push_back(b);
    }
    if (t.e.size() != p.x.size()) {
        std::vector<ReferencePoint> rp;
        for (std::size_t i = 0; i < p.x.size(); ++i) rp.push_back({p.x[i], p.n[i]});
        ReferenceOptions o;
        o.samples = samples;
        o.transport.maxBounces = st.refBounces;
        const double t0 = bench::now();
        const auto r = referenceIrradiance(s, tracer, rp, o);
        t.e.clear(), t.se.clear();
        for (const auto& x : r) t.e.push_back(luminance(Rgb(x.irradiance))), t.se.push_back(luminance(Rgb(x.standardError)));
        const fs::path tmp = file.string() + ".tmp";
        {
            std::ofstream out(tmp);
            out.precision(17);
            for (std::size_t i = 0; i < t.e.size(); ++i) out << t.e[i] << ' ' << t.se[i] << '\n';
        }
        fs::rename(tmp, file);
        std::printf("  ground truth: %zu points x %u samples, %d bounces, computed in %.1f s, cached in %s\n", p.x.size(),
                    samples, st.refBounces, bench::now() - t0, file.c_str());
    } else {
        std::printf("  ground truth: read from %s\n", file.c_str());
    }
    for (double e : t.e) t.mean += e / double(t.e.size());
    return t;
}

/// Statistics of per-point relative errors (signed).
Errors summarise(const std::vector<double>& rel) {
    Errors e;
    std::vector<double> a;
    for (double r : rel) {
        const double x = std::isfinite(r) ? r : 1e30;
        a.push_back(std::abs(x));
        e.rms += x * x;
        e.bias += x;
    }
    std::sort(a.begin(), a.end());
    e.rms = std::sqrt(e.rms / double(a.size()));
    e.bias /= double(a.size());
    e.p95 = a[std::size_t(std::ceil(0.95 * double(a.size()))) - 1];
    e.max = a.back();
    return e;
}

std::vector<double> values(const std::function<Rgb(const Vec3f&, const Vec3f&)>& f, const Points& p) {
    std::vector<double> v(p.x.size());
    for (std::size_t i = 0; i < p.x.size(); ++i) v[i] = luminance(f(p.x[i], p.n[i]));
    return v;
}

std::vector<double> relative(const std::vector<double>& got, const std::vector<double>& want, const Truth& t) {
    std::vector<double> r(got.size());
    for (std::size_t i = 0; i < got.size(); ++i) r[i] = (got[i] - want[i]) / t.denominator(i);
    return r;
}

}  // namespace vdblight::accuracy
