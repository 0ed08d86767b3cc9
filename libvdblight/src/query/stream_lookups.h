// The lookups on a streamed volume (vdb_stream.h) behind makeStreamingQuery (query_stream.h),
// one per in-memory lookup whose arithmetic they repeat operation for operation, so that the
// answers are the same bits (query_stream_test checks it). Internal to the query module.
#pragma once

#include <memory>

#include "vdblight/basis/basis.h"
#include "vdblight/query/query.h"
#include "vdblight/volume/vdb_io.h"

namespace vdblight::query_detail {

/// SH order 2 (`sh2`): ShUniformLookup's arithmetic on one level, ShLevelsLookup's on several
/// (sh_stream_lookup.cpp). `grid0`: level 0's grid, relative to the anchor.
std::unique_ptr<VolumeLookup> streamingShLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0,
                                                OutsidePolicy outside);

/// Any registered basis on a dense level 0, uniform or levels (`sh:N`): ChannelLookup's
/// arithmetic, so ShFourUniformLookup's too, which gives ChannelLookup's bits
/// (channel_stream_lookup.cpp).
std::unique_ptr<VolumeLookup> streamingChannelLookup(std::shared_ptr<const StreamedVolume> volume, const GridSpec& grid0,
                                                     OutsidePolicy outside, std::unique_ptr<Basis> basis);

/// bake --direct occlusion: `base` plus the listed lights' exact direct light times their
/// visibility interpolated from level 0's nodes, OcclusionLookup's arithmetic
/// (occlusion_stream_lookup.cpp). `base` answers in world coordinates (anchored if needed).
std::unique_ptr<VolumeLookup> streamingOcclusionLookup(std::unique_ptr<VolumeLookup> base,
                                                       std::shared_ptr<const StreamedVolume> volume);

}  // namespace vdblight::query_detail
