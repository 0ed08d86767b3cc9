// Summaries of per-node statistics (error_summary.h), shared by the bakes and the merge.
#include "vdblight/volume/volume.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/grid_index.h"

namespace vdblight {

std::size_t nodesInsideSolids(const std::vector<float>& values) {
    return std::size_t(std::count_if(values.begin(), values.end(), [](float e) { return e < 0.0f; }));
}

double errorQuantile(const std::vector<float>& values, double q) {
    std::vector<float> sorted;
    sorted.reserve(values.size());
    for (float e : values)
        if (!(e < 0.0f)) sorted.push_back(e);  // kNodeInsideSolid: not read by free-space lookups
    if (sorted.empty()) return 0.0;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t i = std::min(sorted.size() - 1, std::size_t(std::ceil(q * sorted.size())) - (q > 0 ? 1 : 0));
    return sorted[i];
}

void addErrorSummary(Metadata& m, const std::vector<float>& estimatedError, const GridSpec& grid) {
    const std::size_t inside = nodesInsideSolids(estimatedError);
    m["error_estimate"] = std::string(
        "relative standard error of each node's mean irradiance over normals (SH DC term), from the per-sample "
        "variance (noise only: not bias, SH truncation or interpolation)") +
        (inside > 0 ? "; over the nodes that lookups in free space read (nodes_inside_solids: the nodes inside closed "
                      "solids, which the depth weights keep out of every such lookup, are left out)"
                    : "");
    if (inside > 0) m["nodes_inside_solids"] = int64_t(inside);
    m["estimated_error_p50"] = errorQuantile(estimatedError, 0.5);
    m["estimated_error_p95"] = errorQuantile(estimatedError, 0.95);
    m["estimated_error_max"] = errorQuantile(estimatedError, 1.0);
    std::vector<std::size_t> order(estimatedError.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    // Nodes inside solids (negative) sort last and are never among the worst.
    const std::size_t worst = std::min<std::size_t>(5, order.size() - inside);
    // Ties broken by node index: the same text for any thread count.
    std::partial_sort(order.begin(), order.begin() + worst, order.end(), [&](std::size_t a, std::size_t b) {
        return estimatedError[a] != estimatedError[b] ? estimatedError[a] > estimatedError[b] : a < b;
    });
    std::ostringstream text;
    for (std::size_t k = 0; k < worst; ++k) {
        const std::size_t n = order[k];
        const core::Index3 node = core::unflatten(n, uint64_t(grid.nx), uint64_t(grid.ny));
        text << (k ? ";" : "") << node.i << ',' << node.j << ',' << node.k << ':' << estimatedError[n];
    }
    m["estimated_error_worst_nodes"] = text.str();
}

void addSampleSummary(Metadata& m) {
    const auto samples = uint64_t(std::get<int64_t>(m.at("samples_total")));
    const auto nodes = uint64_t(std::get<int64_t>(m.at("nodes")));
    const auto maxRays = uint64_t(std::get<int64_t>(m.at("max_rays")));
    m["rays_per_node_mean"] = double(samples) / double(nodes);
    m["samples_saved_vs_max"] = int64_t(maxRays * nodes - samples);
}

}  // namespace vdblight
