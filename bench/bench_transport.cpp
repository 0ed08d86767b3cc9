// vdblight_bench_transport: error and bake time of the point gather's transport options
// (issue 15: unbiased defaults, error-targeted budgets, probe-to-probe bounces), against a
// 256-bounce `reference` at 200 random free-space points with random unit normals.
//
//   vdblight_bench_transport SCENE [--resolution R] [--rays N | --target E --max-rays M]
//                            [--probe-passes P] [--bounces B] [--seed S] [--threads T]
// SCENE: cornell (the bundled default), rooms (leak_scenes.h makeThinWallScene: two rooms
// joined by a door, light in one), office (office_scene.h). Prints one line: RMS, p95 and max
// relative error (|E - Eref| / max(Eref, 0.05 mean Eref), luminance), signed bias
// (sum E / sum Eref - 1), bake seconds; for rooms also RMS and bias per room. The reference
// (32768 samples, 256 bounces) is cached under $VDBLIGHT_BENCH_CACHE (default
// /tmp/vdblight_bench_cache); its worst relative standard error is printed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/query/query.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

#include "support/leak_scenes.h"
#include "support/office_scene.h"

using namespace vdblight;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: vdblight_bench_transport cornell|rooms|office [options]\n");
        return 2;
    }
    const std::string which = argv[1];
    int resolution = 16, probePasses = 0, bounces = kSafetyBounces, threads = 0, points = 200;
    uint32_t rays = 256, maxRays = 8192, minRays = 64, refSamples = 32768;
    double target = 0;
    uint64_t seed = 1;
    for (int i = 2; i + 1 < argc; i += 2) {
        const std::string k = argv[i];
        const char* v = argv[i + 1];
        if (k == "--resolution") resolution = std::atoi(v);
        else if (k == "--rays") rays = uint32_t(std::atol(v));
        else if (k == "--target") target = std::atof(v);
        else if (k == "--max-rays") maxRays = uint32_t(std::atol(v));
        else if (k == "--min-rays") minRays = uint32_t(std::atol(v));
        else if (k == "--probe-passes") probePasses = std::atoi(v);
        else if (k == "--bounces") bounces = std::atoi(v);
        else if (k == "--seed") seed = std::strtoull(v, nullptr, 10);
        else if (k == "--threads") threads = std::atoi(v);
        else if (k == "--ref-samples") refSamples = uint32_t(std::atol(v));
        else {
            std::fprintf(stderr, "unknown option %s\n", k.c_str());
            return 2;
        }
    }
    Scene scene;
    if (which == "cornell") scene = loadScene(defaultScenePath());
    else if (which == "rooms") scene = makeThinWallScene().scene;
    else if (which == "office") scene = makeOfficeScene(1);
    else {
        std::fprintf(stderr, "unknown scene %s\n", which.c_str());
        return 2;
    }
    const Tracer tracer(scene);
    const Bounds box = scene.bounds();

    // Points: random in the scene box, kept if no axis ray from them sees a back face.
    std::vector<ReferencePoint> pts;
    Rng rng(2024);
    for (int tries = 0; int(pts.size()) < points && tries < 100 * points; ++tries) {
        const Vec3d t(0.03 + 0.94 * rng.uniform(), 0.03 + 0.94 * rng.uniform(), 0.03 + 0.94 * rng.uniform());
        const Vec3f p(box.lo + box.size() * t);
        const Vec3f n = uniformSphere(rng.uniform(), rng.uniform());
        if (bench::freeSpace(tracer, p)) pts.push_back({p, n});
    }

    // Reference: 256 bounces, cached.
    const char* env = std::getenv("VDBLIGHT_BENCH_CACHE");
    const fs::path dir = env ? fs::path(env) : fs::temp_directory_path() / "vdblight_bench_cache";
    fs::create_directories(dir);
    const fs::path file = dir / ("transport_" + scene.contentHash() + "_" + std::to_string(pts.size()) + "_" +
                                 std::to_string(refSamples) + "_b256.txt");
    std::vector<double> ref, se;
    if (std::ifstream in{file}) {
        double a, b;
        while (in >> a >> b) ref.push_back(a), se.push_back(b);
    }
    if (ref.size() != pts.size()) {
        ReferenceOptions o;
        o.samples = refSamples;
        o.transport.maxBounces = 256;
        const auto r = referenceIrradiance(scene, tracer, pts, o);
        ref.clear(), se.clear();
        for (const auto& x : r) ref.push_back(luminance(Rgb(x.irradiance))), se.push_back(luminance(Rgb(x.standardError)));
        std::ofstream out(file.string() + ".tmp");
        out.precision(17);
        for (std::size_t i = 0; i < ref.size(); ++i) out << ref[i] << ' ' << se[i] << '\n';
        out.close();
        fs::rename(file.string() + ".tmp", file);
    }
    double mean = 0;
    for (double r : ref) mean += r / ref.size();
    double worstSe = 0, rmsSe = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
        const double s = se[i] / std::max(ref[i], 0.05 * mean);
        worstSe = std::max(worstSe, s);
        rmsSe += s * s / ref.size();
    }

    GridPlacement placement;
    placement.resolution = resolution;
    const GridSpec grid = placeUniformGrid(box, placement, 1);
    TransportOptions transport;
    transport.maxBounces = bounces;
    Volume v;
    BakeStats stats;
    if (target > 0) {
        AdaptiveOptions a;
        a.targetError = target;
        a.maxRays = maxRays;
        a.minRays = minRays;
        a.seed = seed;
        a.threads = threads;
        a.transport = transport;
        a.probePasses = probePasses;
        AdaptiveStats as;
        v = bakeShGatherAdaptive(scene, tracer, grid, a, nullptr, &as);
        stats = as;
    } else {
        GatherOptions o;
        o.raysPerNode = rays;
        o.seed = seed;
        o.threads = threads;
        o.transport = transport;
        o.probePasses = probePasses;
        v = bakeShGather(scene, tracer, grid, o, nullptr, &stats);
    }

    const IrradianceQuery q(v);
    std::vector<double> rel;
    double s2 = 0, sumGot = 0, sumRef = 0;
    double roomS2[2] = {0, 0}, roomGot[2] = {0, 0}, roomRef[2] = {0, 0};
    int roomN[2] = {0, 0};
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double got = luminance(q.irradiance(pts[i].position, normalize(pts[i].normal)));
        const double e = (got - ref[i]) / std::max(ref[i], 0.05 * mean);
        rel.push_back(std::abs(e));
        s2 += e * e;
        sumGot += got;
        sumRef += ref[i];
        const int room = pts[i].position.x > 2.0f ? 1 : 0;
        roomS2[room] += e * e, roomGot[room] += got, roomRef[room] += ref[i], ++roomN[room];
    }
    std::sort(rel.begin(), rel.end());
    std::printf("%s res %d nodes %llu %s probe %d bounces %d: RMS %.2f %% p95 %.2f %% max %.1f %% bias %+.2f %%, bake %.2f s "
                "(%.1f M rays), node noise p50 %.2f %% p95 %.2f %% max %.2f %%; ref stderr rms %.2f %% worst %.2f %%",
                which.c_str(), resolution, (unsigned long long)grid.nodeCount(),
                target > 0 ? ("target " + std::to_string(target) + " max " + std::to_string(maxRays)).c_str()
                           : ("rays " + std::to_string(rays)).c_str(),
                probePasses, bounces, 100 * std::sqrt(s2 / pts.size()), 100 * rel[std::size_t(0.95 * rel.size())],
                100 * rel.back(), 100 * (sumGot / sumRef - 1), stats.seconds, stats.rays.total() / 1e6,
                100 * stats.errorQuantile(0.5), 100 * stats.errorQuantile(0.95), 100 * stats.errorQuantile(1.0),
                100 * std::sqrt(rmsSe), 100 * worstSe);
    if (which == "rooms")
        std::printf("; lit room RMS %.2f %% bias %+.2f %% (%d pts), unlit room RMS %.2f %% bias %+.2f %% (%d pts)",
                    100 * std::sqrt(roomS2[0] / std::max(1, roomN[0])), 100 * (roomGot[0] / roomRef[0] - 1), roomN[0],
                    100 * std::sqrt(roomS2[1] / std::max(1, roomN[1])), 100 * (roomGot[1] / roomRef[1] - 1), roomN[1]);
    std::printf("\n");
    return 0;
}
