// Greger's directional bins (Greger et al. 1998, sections 3.2.1-3.2.3) and higher moments
// (section 5.2).
//
// The sphere of directions is split into 2 R^2 equal-area bins: each hemisphere (h = 0:
// z >= 0, h = 1: z < 0) is the image of the unit square under the Shirley-Chiu concentric
// map (square -> disk) followed by the equal-area lift disk -> hemisphere
//   (dx, dy) -> (dx sqrt(2 - r^2), dy sqrt(2 - r^2), +-(1 - r^2)),   r^2 = dx^2 + dy^2,
// and the square is cut into R x R cells. Every map in the chain has a constant Jacobian,
// so every bin has the solid angle 4 pi / (2 R^2). Bin (h, iu, iv) is channel
// c = h R^2 + iv R + iu; its centre direction is the image of ((iu + 1/2) / R, (iv + 1/2) / R).
//
// What a node stores (eq. 4 / eq. 5): for every bin j, the moment of order n of the
// incident radiance about the bin's centre direction w_j,
//   H^n(w_j) = (n + 1) / 2 * integral of L(w) max(0, w . w_j)^n dw,
// n = 1 being the irradiance of a surface facing w_j. The radiance is estimated per bin as
// its average over the bin (stratified samples inside the bin) and the integral is the
// quadrature H^n_j = sum_i W_ji Lbar_i, where W_ji = (n + 1)/2 * integral over bin i of
// max(0, w . w_j)^n (integrated accurately once per (R, n)). With W_ji = (n+1)/2 cos^n * 4pi/(2R^2)
// at the bin centres this is exactly the paper's eq. 4 / 5; integrating the weight over the
// bin removes the paper's footnote-2 error for bins that straddle the horizon of w_j, so a
// constant environment L gives pi L in every bin for every n.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vdblight/basis/basis.h"
#include "vdblight/core/math.h"

namespace vdblight {
namespace bins {

/// The `--basis` choices: SH order 2, irradiance bins, or a higher moment over bins.
struct BasisSpec {
    enum class Kind { Sh2, Bins, Moment } kind = Kind::Sh2;
    int resolution = 17;  ///< R: 2 R^2 bins (bins, moment)
    int order = 1;        ///< n: moment order (1 for bins)
    int binCount() const { return 2 * resolution * resolution; }
    bool isSh2() const { return kind == Kind::Sh2; }  ///< not a bins basis: the bins passes refuse it
};

/// Parses "sh2", "bins:R" (R >= 1) or "moment:n" / "moment:n:R" (n >= 1, R >= 1, default
/// R = 17, the paper's). Throws ValueError with one line naming the text otherwise.
BasisSpec parseBasisSpec(const std::string& text);
/// The BasisDesc kind string: "bins:R" or "moment:n" (the resolution follows from the
/// channel count, 2 R^2).
std::string kindName(const BasisSpec& spec);
/// True if `kind` is a bins or moment basis kind; fills `spec` from it and the channel count.
bool specFromVolume(const BasisDesc& basis, BasisSpec& spec);
/// True if the basis stores a view-dependent quantity: a moment basis ("moment:n"), looked
/// up along the view vector mirrored about the normal (reflectView).
bool viewDependent(const BasisDesc& basis);

/// The BasisDesc: 2 R^2 channels named "bin_h<h>_u<iu>_v<iv>" in channel order.
BasisDesc basis(const BasisSpec& spec);
std::string channelName(int resolution, int channel);

/// Channel of bin (h, iu, iv).
inline int channel(int resolution, int h, int iu, int iv) { return (h * resolution + iv) * resolution + iu; }

/// Direction of the square point (u, v) in [0, 1]^2 of hemisphere h (float: bake sampling).
Vec3f squareToDirection(int h, float u, float v);
/// The same map in double (precomputation and tests).
Vec3d squareToDirection(int h, double u, double v);
/// Inverse map: hemisphere and square point of unit direction w.
void directionToSquare(const Vec3f& w, int& h, float& u, float& v);
/// The bin containing unit direction w (its channel index).
int binOf(int resolution, const Vec3f& w);
/// Centre direction of a bin (double).
Vec3d binCentre(int resolution, int channel);
/// Solid angle of every bin, 4 pi / (2 R^2).
inline double binSolidAngle(int resolution) { return 4.0 * kPi / (2.0 * resolution * resolution); }

/// Quadrature weights W (row-major, bins x bins; see the header comment): H_j = sum_i W[j * bins + i] Lbar_i.
/// Each bin is integrated with `sub` x `sub` midpoint samples (0 = chosen from R).
std::vector<float> quadratureWeights(const BasisSpec& spec, int sub = 0);

/// Default of the lookups' bin blending (measured in bench_bins: see docs/methods.md).
constexpr bool kInterpolateBinsDefault = true;
/// The lookup's bins for unit direction d: with `interpolate`, the four bins whose centres
/// surround d in the square, blended bilinearly (across the square's border into the other
/// hemisphere, whose border bins share the equator), which makes the result continuous in d;
/// otherwise the bin of d alone. Writes (channel, weight) pairs, returns their count (1 or 4).
int lookupWeights(int resolution, bool interpolate, const Vec3f& d, int channels[4], float weights[4]);

/// The Basis (basis/basis.h) of a bins / moment spec; `interpolateBins` as for lookupWeights.
std::unique_ptr<Basis> makeBinsBasis(const BasisSpec& spec, bool interpolateBins = kInterpolateBinsDefault);

/// Mirror of the view vector v (pointing from the surface to the eye) about the unit
/// normal n: the direction a moment volume is queried in (section 5.2).
inline Vec3f reflectView(const Vec3f& v, const Vec3f& n) { return n * (2.0f * dot(n, v)) - v; }

}  // namespace bins
}  // namespace vdblight
