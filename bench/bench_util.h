// Small helpers the benchmark programs share: wall-clock time, the uniform grid of a given
// resolution over a box, the free-space test for evaluation points, and lookup throughput.
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstddef>
#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/trace/trace.h"

namespace vdblight::bench {

/// Wall-clock seconds (steady clock).
inline double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// CPU seconds of the calling thread (CLOCK_THREAD_CPUTIME_ID): what the single-thread lookup
/// rates are timed with, so that the time the thread waits for a core on a shared machine does
/// not count (wall-clock rates of the same binary varied by 2x between runs there: issue 33).
inline double threadSeconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// placeUniformGrid over `box` with `resolution` nodes along its longest axis.
inline GridSpec uniformGrid(const Bounds& box, int resolution) {
    GridPlacement p;
    p.resolution = resolution;
    return placeUniformGrid(box, p, 1);
}

/// A point is in free space if rays along the six axis directions first hit front faces
/// (or nothing): inside a closed solid some ray meets a back face first.
inline bool freeSpace(const Tracer& tracer, const Vec3f& x) {
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3f& d : dirs) {
        Ray r;
        r.origin = x;
        r.direction = d;
        const Hit h = tracer.intersect(r);
        if (h.hit() && dot(h.geometricNormal, d) > 0) return false;
    }
    return true;
}

/// Inputs of a lookup-throughput run: random points in a box and random unit vectors.
struct LookupInputs {
    std::vector<Vec3f> points, normals;
};

/// `n` uniform points in `box` and directions on the sphere, from Rng(123).
inline LookupInputs randomLookups(const Bounds& box, std::size_t n) {
    LookupInputs in{std::vector<Vec3f>(n), std::vector<Vec3f>(n)};
    Rng rng(123);
    for (std::size_t i = 0; i < n; ++i) {
        in.points[i] = Vec3f(box.lo + box.size() * Vec3d(rng.uniform(), rng.uniform(), rng.uniform()));
        in.normals[i] = uniformSphere(rng.uniform(), rng.uniform());
    }
    return in;
}

/// Lookups per timed stretch: the rates are the best over stretches of this many lookups (a few
/// ms each), because on a shared machine a quiet stretch of a few ms comes far more often than
/// a quiet second: the other processes' cache and memory traffic only ever slow a stretch down.
constexpr std::size_t kTimedStretch = 100'000;

/// The best rate of lookup.irradiance over the inputs on this thread, in lookups per second of
/// the thread's CPU time, over stretches of kTimedStretch lookups in `repeats` passes. Every
/// result is added to `sink` (print it: the lookups must not be optimised away).
template <class Lookup>
double lookupRate(const Lookup& lookup, const LookupInputs& in, int repeats, Rgb& sink) {
    double best = 0;
    for (int r = 0; r < repeats; ++r)
        for (std::size_t begin = 0; begin < in.points.size(); begin += kTimedStretch) {
            const std::size_t end = std::min(in.points.size(), begin + kTimedStretch);
            const double t0 = threadSeconds();
            for (std::size_t i = begin; i < end; ++i) sink += lookup.irradiance(in.points[i], in.normals[i]);
            best = std::max(best, double(end - begin) / (threadSeconds() - t0));
        }
    return best;
}

}  // namespace vdblight::bench
