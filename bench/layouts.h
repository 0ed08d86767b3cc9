// vdblight_bench_layouts (issue 4): what its parts share. bench_layouts.cpp says what the
// benchmark measures, and holds the table at one node budget, the paper's configuration, the
// lookup speed and main; the parts are split so that each reads in one sitting:
//  - layouts_probe.cpp: the layouts at a node budget, the error metric over the probe points,
//    the bakes in each basis and the basis' floor (projection at the points themselves);
//  - layouts_sweep.cpp: the node-budget sweep (`--sweep`), on the same points and metric.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "vdblight/basis/bins.h"
#include "vdblight/layout/layout.h"
#include "vdblight/reference/reference.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight::bench_layouts {

struct Config {
    const char* name;
    LevelLayout layout;
};

/// A layout for a first-level resolution (throws ValueError if it cannot be placed).
using LayoutMaker = std::function<LevelLayout(int resolution)>;

/// A layout of `kind` over the scene's bounds, `resolution` first-level nodes along the longest
/// axis; a cell is refined within `refineDistanceInH0` first-level spacings of a triangle
/// (0 = Greger's rule: the cell contains geometry).
LevelLayout makeLayout(const Scene& scene, LayoutKind kind, int resolution, int refine, int levels,
                       double refineDistanceInH0 = 0.0);

/// The same, then solid culling (solid_cull.h): totalNodes() counts only the kept nodes.
LevelLayout makeCulledLayout(const Scene& scene, const Tracer& tracer, LayoutKind kind, int resolution, int refine,
                             int levels);

/// The layout whose (baked, i.e. kept) node count is closest to `target`, over first-level resolutions.
LevelLayout closestLayout(const LayoutMaker& make, uint64_t target);
LevelLayout closestLayout(const Scene& scene, LayoutKind kind, int refine, int levels, uint64_t target);

/// RMS and maximum of the relative errors added.
struct ErrorStats {
    double rms = 0, max = 0;
    int count = 0;
    void add(double e) { rms += e * e, max = std::max(max, e), ++count; }
    double rmsValue() const { return count ? std::sqrt(rms / count) : 0.0; }
};

/// Noise-free RMS extrapolated from RMS errors at N and 4N rays per node, assuming the
/// Monte Carlo part of the squared error falls as 1/N: e_N^2 = b^2 + n^2, e_4N^2 = b^2 + n^2/4.
inline double noiseFree(double eN, double e4N) { return std::sqrt(std::max(0.0, (4 * e4N * e4N - eN * eN) / 3)); }

struct LayoutBenchOptions {
    int firstLevel = 0;   ///< first-level resolution of the bilevel layout that sets the node budget (0 = default)
    uint32_t rays = 0;    ///< rays per node (0 = default)
    bool decompose = true;  ///< also bake at 4x rays and project SH at the points (noise / interpolation split)
    int binsResolution = 0;  ///< R of the low-floor basis bins:R compared beside SH2 (0 = none; main sets the default)
    std::vector<int> sweep;  ///< first-level resolutions of the node-budget sweep (empty = no sweep)
    bool sweepOnly = false;  ///< skip the tables at the --first-level budget (same points and reference)
};

/// A directional basis the layouts are compared in: SH order 2 (bakeShGatherLevels, read by
/// IrradianceQuery) or Greger bins (bakeBins, read by BinsLookup with blended bins, its
/// default). The layout, i.e. where the nodes go, does not depend on it.
struct BasisChoice {
    std::string name;
    bool sh = true;
    bins::BasisSpec spec;  ///< for bins
    /// Samples per bin for about `rays` rays per node (at least one per bin).
    uint32_t samplesPerBin(uint32_t rays) const {
        const uint32_t b = uint32_t(spec.binCount());
        return std::max<uint32_t>(1, (rays + b - 1) / b);
    }
    uint32_t raysPerNode(uint32_t rays) const { return sh ? rays : samplesPerBin(rays) * uint32_t(spec.binCount()); }
};

BasisChoice shBasis();
BasisChoice binsBasis(int resolution);

/// The random free-space points, their reference irradiance and the error metric shared by
/// every table of one scene (relative error of luminance against max(E_ref, 5 % of the mean)).
struct Probe {
    const Scene& scene;
    const Tracer& tracer;
    std::vector<ReferencePoint> points;
    std::vector<ReferenceResult> ref;
    double meanRef = 0;
    double relError(std::size_t i, const Rgb& e) const {
        const double r = luminance(Rgb(ref[i].irradiance));
        return std::abs(double(luminance(e)) - r) / std::max(r, 0.05 * meanRef);
    }
};

/// Which points are "near geometry": in cells that `bilevel` refines.
std::vector<char> nearPoints(const Probe& probe, const LevelLayout& bilevel);

/// RMS of the relative error over the near points.
double rmsNearOf(const Probe& probe, const std::vector<Rgb>& e, const std::vector<char>& near, double* maxNear = nullptr,
                 double* rmsAll = nullptr);

/// 5 % and 95 % quantiles of the ratio RMS(b) / RMS(a) over the near points, by a bootstrap
/// (2000 resamples of the near points with replacement, fixed seed): how much of a ratio is
/// the luck of the 1000 random points (a few points near walls carry most of the RMS).
std::pair<double, double> bootstrapRatio(const Probe& probe, const std::vector<Rgb>& a, const std::vector<Rgb>& b,
                                         const std::vector<char>& near);

/// Bakes `layout` in `basis` with about `rays` rays per node and returns E(x, n) at the probe points.
std::vector<Rgb> bakeAndQuery(const Probe& probe, const LevelLayout& layout, const BasisChoice& basis, uint32_t rays,
                              int threads, double* seconds);

/// E(x, n) of the basis projected at each probe point itself (no spatial interpolation):
/// what a layout with a node exactly at every query point would return, i.e. the floor of
/// the basis (truncation / bin discretisation + Monte Carlo noise at this ray count). SH2:
/// projectIncidentRadiance at x. Bins: the bake's gather and quadrature at x, stored in a
/// 2 x 2 x 2 volume whose eight nodes all hold those values and read by the same BinsLookup
/// (blended bins) as a baked volume, so the direction lookup is the real one.
std::vector<Rgb> projectAtPoints(const Probe& probe, const BasisChoice& basis, uint32_t rays);

/// Node-budget sweep: for each first-level resolution r, the budget is the node count of the
/// bilevel K=3 layout on an r-grid (as in the table); uniform and the refined layouts are
/// matched to it, "near" is re-evaluated for that bilevel, and for each basis the best
/// refined layout's RMS near geometry is printed against uniform's, with the basis' point
/// floor (projection at the query points, same near set) for comparison. Same points,
/// reference and metric as the table.
void benchSweep(const Probe& probe, const LayoutBenchOptions& lo, uint32_t rays, int threads, bool quick);

}  // namespace vdblight::bench_layouts
