// The passes of the bake module (pass.h), one class each; registered in pass_registry.cpp.
// (Internal to the bake module.)
#pragma once

#include "vdblight/bake_volume.h"
#include "vdblight/pass.h"

namespace vdblight::bake_detail {

/// The point gather on a uniform grid (pass_gather.cpp).
class GatherPass : public Pass {
public:
    std::string name() const override { return "gather"; }
    std::string description() const override {
        return "point gather: SH order 2 of the incident radiance at each node of a uniform grid (bake.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesDirectLight() const override { return true; }
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};

/// The error-targeted point gather (pass_adaptive.cpp, bake_adaptive.h).
class AdaptivePass : public Pass {
public:
    std::string name() const override { return "adaptive"; }
    std::string description() const override {
        return "error-targeted point gather: each node sampled until its irradiance reaches a relative standard "
               "error (bake_adaptive.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesDirectLight() const override { return true; }
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};

/// The anti-aliased gather of Kontkanen and Laine (pass_antialiased.cpp, bake_antialiased.h).
class AntialiasedPass : public Pass {
public:
    std::string name() const override { return "antialiased"; }
    std::string description() const override {
        return "anti-aliased gather (Kontkanen-Laine eq. 6): origins over each cell, domain of interest, validity "
               "(bake_antialiased.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};

/// The point gather on bilevel / adaptive levels (pass_levels.cpp, bake_levels.h).
class LevelsPass : public Pass {
public:
    std::string name() const override { return "levels"; }
    std::string description() const override {
        return "point gather on bilevel / adaptive levels (Greger et al.), seams from the coarser level, optional "
               "solid culling (bake_levels.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesShWindow() const override { return true; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};

/// Greger bins and moments on any layout (pass_bins.cpp, bake_bins.h).
class BinsPass : public Pass {
public:
    std::string name() const override { return "bins"; }
    std::string description() const override {
        return "Greger bins / moments: radiance sampled through every bin, one value per bin direction "
               "(bake_bins.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
};

/// The photon pass of Pacanowski et al. (pass_photons.cpp, photons.h).
class PhotonsPass : public Pass {
public:
    std::string name() const override { return "photons"; }
    std::string description() const override {
        return "photon pass (Pacanowski et al.): irradiance vectors from photons crossing the node lattice "
               "(photons.h)";
    }
    std::vector<PassOption> options() const override;
    void validate(const BakeRequest& request) const override;
    std::size_t bytesPerNode(const BakeRequest& request) const override;
    std::string untileable(const BakeRequest& request) const override;
    bool takesDepthMoments() const override { return false; }
    Volume run(const BakeContext& context, const BakeRequest& request, const GridSpec& grid,
               BakeReport& report) const override;
    void finish(Volume& volume, WriteOptions& write, const BakeRequest& request) const override;
};

}  // namespace vdblight::bake_detail
