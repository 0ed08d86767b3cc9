// The one metadata writer of the bake passes: the keys every pass shares (scene identity,
// transport, seed, ray counts, time), written the same way by each, and typed setters for a
// pass's own keys. (Internal to the bake module; keys in docs/format.md.)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdblight/layout/layout.h"
#include "vdblight/light/light.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

struct Scene;

namespace bake_detail {

struct ParallelRun;

class PassMetadata {
public:
    explicit PassMetadata(Metadata& m) : m_(m) {}

    /// scene_name, scene_hash, scene_triangles.
    PassMetadata& scene(const Scene& scene);
    /// seed, bounces, roulette_start and (with `maxSurvival`) roulette_max_survival.
    PassMetadata& transport(const TransportOptions& transport, uint64_t seed, bool maxSurvival = true);
    /// nodes, rays_intersect, rays_occluded, bake_seconds, threads.
    PassMetadata& run(uint64_t nodes, const RayCount& rays, double seconds, int threads);
    PassMetadata& run(uint64_t nodes, const ParallelRun& run);
    /// What every gather-style pass writes: scene, transport (with roulette_max_survival), run.
    PassMetadata& common(const Scene& scene, const TransportOptions& transport, uint64_t seed, uint64_t nodes,
                         const ParallelRun& run);
    /// method and sampling.
    PassMetadata& method(const std::string& method, const std::string& sampling);

    /// The per-node error summary of the point gathers (BakeStats::estimatedError, one value
    /// per node of `grid`): error_estimate (what it is), estimated_error_p50 / _p95 / _max and
    /// estimated_error_worst_nodes ("i,j,k:error;..." for the five worst nodes): addErrorSummary
    /// (error_summary.h), which the merge of tiles uses too.
    PassMetadata& errorSummary(const std::vector<float>& estimatedError, const GridSpec& grid);
    /// rays_per_node_mean and samples_saved_vs_max of an error-targeted bake from the
    /// samples_total, nodes and max_rays written before: addSampleSummary (error_summary.h).
    PassMetadata& sampleSummary();
    /// depth_moments and depth_rays_per_node of a volume with depth moments from `rays` rays per node.
    PassMetadata& depthMoments(uint32_t rays);

    /// scene_file and sky: where the scene came from and its sky, as the caller names them
    /// (BakeRequest::sceneFile, BakeRequest::sky).
    PassMetadata& provenance(const std::string& sceneFile, const std::string& sky);

    PassMetadata& text(const std::string& key, const std::string& value);
    PassMetadata& count(const std::string& key, int64_t value);
    PassMetadata& number(const std::string& key, double value);

private:
    Metadata& m_;
};

}  // namespace bake_detail
}  // namespace vdblight
