// The photon pass's walk of a path segment through the node lattice (photons.h): the face
// crossings of a 3-D DDA through the cells. Internal to the bake module (photon_pass.cpp;
// tests include it as "../libvdblight/src/bake/face_crossing.h").
#pragma once

#include <algorithm>
#include <utility>

#include "vdblight/core/math.h"

namespace vdblight {

namespace detail {
/// The crossings of forEachFaceCrossing with the planes normal to axis A, for the clipped
/// parameter range [t0, t1]; B and C are the other two axes.
template <int A, typename F>
inline void crossPlanesOfAxis(const double g0[3], const double d[3], double t0, double t1, const int dims[3],
                              F& onCrossing) {
    constexpr int B = (A + 1) % 3, C = (A + 2) % 3;
    if (d[A] == 0.0) return;
    // Inside [t0, t1] every coordinate lies in the padded node box, so the planes crossed are
    // ceil(lo) .. floor(hi) and the nearest node indices need only a clamp against rounding.
    const double ea = g0[A] + t0 * d[A], fa = g0[A] + t1 * d[A];
    const double lo = std::min(ea, fa), hi = std::max(ea, fa);
    if (hi < 0.0) return;
    int mlo = 0;
    if (lo > 0.0) {
        mlo = int(lo);
        mlo += double(mlo) < lo ? 1 : 0;
    }
    const int mhi = std::min(dims[A] - 1, int(hi));
    if (mlo > mhi) return;
    const double inv = 1.0 / d[A];
    const double sb = d[B] * inv, sc = d[C] * inv;
    const int hb = dims[B] - 1, hc = dims[C] - 1;
    for (int m = mlo; m <= mhi; ++m) {
        const double s = m - g0[A];
        const double pb = g0[B] + s * sb, pc = g0[C] + s * sc;
        int idx[3];
        idx[A] = m;
        idx[B] = std::min(hb, std::max(0, int(pb + 0.5)));
        idx[C] = std::min(hc, std::max(0, int(pc + 0.5)));
        onCrossing(A, idx[0], idx[1], idx[2]);
    }
}
}  // namespace detail

/// Calls onCrossing(axis, i, j, k) for every crossing of the segment g0 -> g1 (lattice
/// coordinates: node (i, j, k) sits at (i, j, k)) with a plane of nodes x_axis = m,
/// 0 <= m < dims[axis], at a point inside the closed node box; (i, j, k) is the node of that
/// plane nearest to the crossing. Planes through an end point count. The crossings are
/// visited axis by axis: they are the faces a 3-D DDA through the cells would visit.
template <typename F>
void forEachFaceCrossing(const Vec3d& from, const Vec3d& to, const int dims[3], F&& onCrossing) {
    const double g0[3] = {from.x, from.y, from.z};
    const double d[3] = {to.x - from.x, to.y - from.y, to.z - from.z};
    // Clip to the node box, padded by a hair so that crossings on its faces survive rounding.
    double t0 = 0.0, t1 = 1.0;
    constexpr double kPad = 1e-9;
    for (int a = 0; a < 3; ++a) {
        const double lo = -kPad, hi = dims[a] - 1 + kPad;
        if (d[a] == 0.0) {
            if (g0[a] < lo || g0[a] > hi) return;
            continue;
        }
        double ta = (lo - g0[a]) / d[a], tb = (hi - g0[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (t0 > t1) return;
    detail::crossPlanesOfAxis<0>(g0, d, t0, t1, dims, onCrossing);
    detail::crossPlanesOfAxis<1>(g0, d, t0, t1, dims, onCrossing);
    detail::crossPlanesOfAxis<2>(g0, d, t0, t1, dims, onCrossing);
}

}  // namespace vdblight
