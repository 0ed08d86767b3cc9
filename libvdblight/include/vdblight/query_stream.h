// Lookups on a volume read through delayed loading (vdb_stream.h): the same answers, bit for
// bit, as IrradianceQuery on readVolume's Volume, but only the leaves around the points looked
// up are read from the file, so a world larger than memory can be queried.
//
//   auto file = std::make_shared<StreamedVolume>("world.vdb");
//   if (streamingSupported(*file).empty()) {
//       IrradianceQuery q = makeStreamingQuery(file, OutsidePolicy::Clamp, true);
//       Rgb e = q.irradianceWorld({12.0, 1.5, -40.0}, {0, 1, 0});
//   }
//
// Kinds: SH order 2, uniform (`sh2-uniform`) or bilevel / adaptive levels (`sh2-levels`, culled
// or not), with or without depth moments, near or far from the origin, --direct baked and
// runtime. Every other kind (bins, moments, irradiance vectors, --direct occlusion) is refused
// with the reason; `vdblight query` then reads the whole file unless told --stream on.
#pragma once

#include <memory>
#include <string>

#include "vdblight/query.h"
#include "vdblight/vdb_stream.h"

namespace vdblight {

/// Empty if makeStreamingQuery supports the file's kind, else the reason (one sentence).
std::string streamingSupported(const StreamedVolume& volume);

/// The lookup for `volume` (kind name "sh2-uniform-streamed" or "sh2-levels-streamed"; the
/// arithmetic of ShUniformLookup or ShLevelsLookup). A missing node of a refined cell (a corrupt
/// file, which readVolume refuses) reads as 0 instead of being refused. `depthWeights` as in
/// IrradianceQuery(volume, outside, depthWeights). Throws FormatError for unsupported kinds.
IrradianceQuery makeStreamingQuery(std::shared_ptr<const StreamedVolume> volume, OutsidePolicy outside,
                                   bool depthWeights = true);

}  // namespace vdblight
