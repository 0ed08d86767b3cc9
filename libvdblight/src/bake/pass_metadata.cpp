#include "pass_metadata.h"

#include "parallel_nodes.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/volume/volume.h"
#include "vdblight/scene/scene.h"

namespace vdblight::bake_detail {

PassMetadata& PassMetadata::scene(const Scene& scene) {
    m_["scene_name"] = scene.name;
    m_["scene_hash"] = scene.contentHash();
    m_["scene_triangles"] = int64_t(scene.triangleCount());
    return *this;
}

PassMetadata& PassMetadata::transport(const TransportOptions& transport, uint64_t seed, bool maxSurvival) {
    m_["seed"] = int64_t(seed);
    m_["bounces"] = int64_t(transport.maxBounces);
    m_["roulette_start"] = int64_t(transport.rouletteStart);
    if (maxSurvival) m_["roulette_max_survival"] = double(kRouletteMaxSurvival);
    return *this;
}

PassMetadata& PassMetadata::run(uint64_t nodes, const RayCount& rays, double seconds, int threads) {
    m_["nodes"] = int64_t(nodes);
    m_["rays_intersect"] = int64_t(rays.intersect);
    m_["rays_occluded"] = int64_t(rays.occluded);
    m_["bake_seconds"] = seconds;
    m_["threads"] = int64_t(threads);
    return *this;
}

PassMetadata& PassMetadata::run(uint64_t nodes, const ParallelRun& r) { return run(nodes, r.rays, r.seconds, r.threads); }

PassMetadata& PassMetadata::common(const Scene& s, const TransportOptions& t, uint64_t seed, uint64_t nodes,
                                   const ParallelRun& r) {
    return scene(s).transport(t, seed).run(nodes, r);
}

PassMetadata& PassMetadata::method(const std::string& method, const std::string& sampling) {
    m_["method"] = method;
    m_["sampling"] = sampling;
    return *this;
}

PassMetadata& PassMetadata::errorSummary(const std::vector<float>& estimatedError, const GridSpec& grid) {
    addErrorSummary(m_, estimatedError, grid);  // the merge of tiles writes the same (error_summary.h)
    return *this;
}

PassMetadata& PassMetadata::sampleSummary() {
    addSampleSummary(m_);  // the merge of tiles recomputes it the same way
    return *this;
}

PassMetadata& PassMetadata::depthMoments(uint32_t rays) {
    m_["depth_moments"] = std::string("axial depth per cube face, mean and sigma, 8-bit (depth_moments.h)");
    m_["depth_rays_per_node"] = int64_t(rays);
    return *this;
}

PassMetadata& PassMetadata::provenance(const std::string& sceneFile, const std::string& sky) {
    m_["scene_file"] = sceneFile;
    m_["sky"] = sky;
    return *this;
}

PassMetadata& PassMetadata::text(const std::string& key, const std::string& value) {
    m_[key] = value;
    return *this;
}

PassMetadata& PassMetadata::count(const std::string& key, int64_t value) {
    m_[key] = value;
    return *this;
}

PassMetadata& PassMetadata::number(const std::string& key, double value) {
    m_[key] = value;
    return *this;
}

}  // namespace vdblight::bake_detail
