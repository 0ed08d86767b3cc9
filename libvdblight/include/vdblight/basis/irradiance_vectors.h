// Irradiance vectors (Pacanowski et al. 2009, sections 3.1, 3.2 and 4.1).
//
// At every node, six irradiance vectors per colour channel, one per axis direction
// delta = +x, -x, +y, -y, +z, -z:
//   I_delta(p) = integral over the hemisphere around delta of L(p <- w) w dw
// where w points *towards* where the light comes from. <I_delta, delta> = E_delta is the
// irradiance on a surface facing delta.
//
// E(n), for a unit normal n, from the six vectors (the lookup's reconstruction, `Blend`):
//  - Quadratic: with V_a = (I_{+a} + I_{-a})_a = E_{+a} - E_{-a} and
//    G_ab = (I_{+a} - I_{-a})_b (so G_aa = E_{+a} + E_{-a}),
//      E(n) = 1/2 V.n + 1/4 n^T G n + 1/4 sum_a G_aa n_a^2.
//    Exact for every radiance made of SH bands 0, 1 and 2 (and any odd band, which the
//    clamped cosine sees only through band 1), so under uniform light (pi L for every n), and
//    for axis normals (E_delta). Derivation: the odd part of E is exactly V.n / 2; for the
//    even part, radiance w^T M w gives (I_{+a} - I_{-a})_b = pi M_ab (a != b),
//    E_{+a} + E_{-a} = pi/2 (M_aa + tr M), and E = pi/4 (tr M + n^T M n); G's two estimates
//    of each off-diagonal M_ab are averaged. Like SH order 2 it rings (slightly negative
//    facing away from a concentrated light), and even bands >= 4 alias into it.
//  - Bounded (default, issue 15 item 5): Quadratic clamped to what the six vectors prove for
//    non-negative radiance. E, extended to all n in R^3, is convex and homogeneous of degree
//    1 (the support function of the zonoid of the light), with gradient I_delta at delta, so
//      max(0, max_delta <I_delta, n>)  <=  E(n)  <=  sum_a |n_a| E_(a, sign n_a)
//    (tangent planes lie below a convex function; it is subadditive). Exact wherever Quadratic
//    is, and also for a single distant light along a diagonal or in an axis plane.
//  - Paper (section 4.1): per axis the vector of n_a's sign, blended by n_a^2:
//      I_n = I_x n_x^2 + I_y n_y^2 + I_z n_z^2,   E(n) = <I_n, n>.
//    Exact for axis normals and for light from within n's octant, but a convex combination of
//    tangent planes, so a lower bound everywhere: pi L sum |n_a|^3 under uniform light (3/4 of
//    the truth on average over normals).
// Quadratic and Paper are linear in the vectors; Bounded is piecewise linear. All of them are
// evaluated after the vectors are interpolated (what a GPU's filtering then a shader does).
//
// Channel c of a volume (docs/format.md) is direction d = c / 3 and colour c % 3; its three
// floats are the vector's world x, y, z components. Direction d is axis d / 2, negative if d
// is odd: 0 = +x, 1 = -x, 2 = +y, 3 = -y, 4 = +z, 5 = -z.
#pragma once

#include "vdblight/basis/basis.h"
#include "vdblight/core/math.h"

namespace vdblight {
namespace iv {

constexpr int kDirections = 6;
constexpr int kChannels = kDirections * 3;   ///< (direction, colour) pairs
constexpr int kFloatsPerNode = kChannels * 3;

/// How a lookup reconstructs E(n) from the six vectors (see above).
enum class Blend {
    Bounded,    ///< Quadratic clamped to the bounds the vectors prove; the library's default
    Quadratic,  ///< exact for SH bands 0-2 (uniform light included)
    Paper,      ///< Pacanowski et al. 4.1, n^2 blend of three vectors: a lower bound
};

/// What IrradianceQuery, `vdblight query` and the export manifests use.
constexpr Blend kDefaultBlend = Blend::Bounded;

/// Direction index of axis a (0..2) with the given sign.
constexpr int direction(int axis, bool negative) { return 2 * axis + (negative ? 1 : 0); }
/// Channel index of direction d and colour c (0 = red, 1 = green, 2 = blue).
constexpr int channel(int d, int colour) { return 3 * d + colour; }

/// The volume basis "irradiance_vectors": 18 channels named "iv_<axis><pos|neg>_<r|g|b>",
/// e.g. "iv_xpos_r", "iv_zneg_b", in channel order.
BasisDesc basis();

/// E(n) per colour channel from one node's (or one interpolated) set of vectors: `v` holds
/// kFloatsPerNode floats in channel order. Paper reads only the three directions of n's
/// signs; the others read all six.
Rgb irradiance(const float* v, const Vec3f& n, Blend blend = kDefaultBlend);

/// The same in double, written out term by term (the simple reference the float version
/// and the lookups are tested against).
Rgbd referenceIrradiance(const double* v, const Vec3d& n, Blend blend = kDefaultBlend);

/// "bounded", "quadratic" or "paper"; parseBlend throws ValueError for anything else.
const char* blendName(Blend blend);
Blend parseBlend(const std::string& name);

}  // namespace iv
}  // namespace vdblight
