// makeStreamingQuery (query_stream.h): which streamed lookup reads a file, anchored far from
// the origin, wrapped for per-light visibility, as IrradianceQuery builds the in-memory one
// (registry.cpp).
#include "vdblight/query/query.h"

#include "shifted_lookup.h"
#include "stream_lookups.h"
#include "vdblight/core/errors.h"
#include "core/world_frame.h"

namespace vdblight {

namespace {
/// The registered real-SH basis of an `sh:N` volume, or null (sh2 has its own lookups).
std::unique_ptr<Basis> shBasis(const Volume& header) {
    if (header.basis.isSh2()) return nullptr;
    std::unique_ptr<Basis> basis = basisOf(header.basis);
    return basis && basis->shCoefficients() > 0 ? std::move(basis) : nullptr;
}
}  // namespace

std::string streamingSupported(const StreamedVolume& volume) {
    const Volume& h = volume.header();
    if (h.basis.isSh2()) return {};
    if (!shBasis(h))
        return "its basis is '" + h.basis.kind + "' (streaming looks up real-SH volumes: sh2 and sh:N)";
    // ChannelLookup, the in-memory lookup of sh:N, reads no culled level 0 either.
    if (h.levels.size() > 1 && metaString(h.meta, "culling") == "solid-regions")
        return "it is a culled '" + h.basis.kind + "' volume (bake --cull-solids), which no lookup reads";
    return {};
}

IrradianceQuery makeStreamingQuery(std::shared_ptr<const StreamedVolume> volume, OutsidePolicy outside,
                                   bool depthWeights) {
    const std::string why = streamingSupported(*volume);
    if (!why.empty()) throw FormatError("cannot stream this volume: " + why);
    const Volume& h = volume->header();
    // Far from the origin: the lookup works relative to the anchor, as createAnchored does
    // for in-memory volumes (shifted_lookup.cpp), so the float arithmetic is the same.
    GridSpec grid = h.levels[0].grid;
    const Vec3d anchor = recenteringAnchor(grid.nodeBounds());
    grid.origin += -anchor;
    const bool levels = h.levels.size() > 1;
    std::unique_ptr<Basis> basis = shBasis(h);
    const char* kind = basis ? (!h.basis.isSh2() && h.basis.shOrder() == 4 && !levels ? "sh4-uniform-streamed" : "basis-streamed")
                             : (levels ? "sh2-levels-streamed" : "sh2-uniform-streamed");
    std::unique_ptr<VolumeLookup> lookup = basis ? query_detail::streamingChannelLookup(volume, grid, outside, std::move(basis))
                                                 : query_detail::streamingShLookup(volume, grid, outside);
    if (anchor != Vec3d(0, 0, 0)) lookup = shiftLookup(std::move(lookup), anchor);
    // bake --direct occlusion: the listed lights' direct light, outside the anchoring (as
    // IrradianceQuery wraps OcclusionLookup around the anchored lookup).
    if (volume->hasVisibility()) lookup = query_detail::streamingOcclusionLookup(std::move(lookup), volume);
    lookup->setDepthWeights(depthWeights);
    return IrradianceQuery(std::move(lookup), kind);
}

}  // namespace vdblight
