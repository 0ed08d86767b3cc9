// The pass loop of the point gathers with probe-to-probe bounces (GatherOptions::probePasses,
// AdaptiveOptions::probePasses): pass 0 traces full paths, pass k > 0 ends them at their first
// hit with pass k - 1's reflected light (surface_cache.h) and has its own seed. One loop for
// the fixed and the error-targeted gather, whole or one stage of a staged bake (tiles.h).
// (Internal to the bake module.)
#pragma once

#include <memory>
#include <vector>

#include "node_sampler.h"
#include "parallel_nodes.h"
#include "surface_bins.h"
#include "surface_cache.h"
#include "vdblight/sampling/sampling.h"

namespace vdblight::bake_detail {

struct ProbePass {
    int index = 0;
    uint64_t seed = 0;           ///< the bake's seed for pass 0, hashCombine(seed, index) after
    bool keepReflected = false;  ///< a later pass reads this pass's reflected light
};

/// Runs passes range.first .. range.last of a bake with passes 0 .. `passes` (all of them, or
/// one stage of a staged bake: stagePasses, surface_cache.h). runPass(const ProbePass&) bakes
/// the nodes (one forEachItemInParallel) and, with keepReflected, fills `reflected` (nine
/// coefficients per node of `grid`), which then becomes the estimator's surface cache for the
/// next pass of the range. A range starting after pass 0 reads `startReflected` (the previous
/// stage's reflected light: the probe stage volume's data, 27 floats per node) as the cache of its first pass; otherwise it is
/// ignored; `startStride` floats per node (stage_carry.h may follow the 27). Returns the ray
/// counts and times of the passes run, summed.
template <typename RunPass>
ParallelRun runProbePasses(RadianceEstimator& estimator, const Tracer& tracer, const GridSpec& grid, uint64_t seed,
                           int passes, const PassRange& range, const float* startReflected,
                           const std::vector<Rgb>& reflected, RunPass&& runPass, SurfaceBins* bins = nullptr,
                           std::size_t startStride = 27) {
    std::unique_ptr<VolumeSurfaceCache> cache;
    if (range.first > 0 && bins) {
        estimator.setSurfaceCache(bins);  // the stage input's bins (surface_bins.h)
    } else if (range.first > 0) {
        cache = std::make_unique<VolumeSurfaceCache>(tracer, grid, startReflected, startStride);  // in place, not copied
        estimator.setSurfaceCache(cache.get());
    }
    ParallelRun run;
    for (int p = range.first; p <= range.last; ++p) {
        const ProbePass pass{p, p == 0 ? seed : hashCombine(seed, uint64_t(p)), p < passes};
        const ParallelRun passRun = runPass(pass);
        run.rays += passRun.rays;
        run.seconds += passRun.seconds;
        run.threads = passRun.threads;
        if (pass.keepReflected && p < range.last) {
            estimator.setSurfaceCache(nullptr);
            if (bins) {
                estimator.setSurfaceCache(bins);
            } else {
                cache = std::make_unique<VolumeSurfaceCache>(tracer, grid, reflected);
                estimator.setSurfaceCache(cache.get());
            }
        }
    }
    estimator.setSurfaceCache(nullptr);  // the cache ends here
    return run;
}

/// A node's nine RGB coefficients into its 27 floats of the volume (null: the volume stores
/// another basis) and, for a pass a later one reads, its reflected light into `reflected`
/// (nine coefficients; null otherwise).
inline void storeNode(const detail::NodeSampler& sampler, const Rgbd coeffs[sh::kCoeffs], float* dst, Rgb* reflected) {
    for (int j = 0; dst && j < sh::kCoeffs; ++j) {
        dst[3 * j + 0] = float(coeffs[j].x);
        dst[3 * j + 1] = float(coeffs[j].y);
        dst[3 * j + 2] = float(coeffs[j].z);
    }
    if (!reflected) return;
    Rgbd r[sh::kCoeffs];
    sampler.reflectedCoefficients(r);
    for (int j = 0; j < sh::kCoeffs; ++j) reflected[j] = Rgb(r[j]);
}

}  // namespace vdblight::bake_detail
