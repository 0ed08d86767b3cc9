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
// Kinds: every kind the default bake and the presets write. SH order 2 (`sh2`: uniform, or
// bilevel / adaptive levels culled or not) and real SH of any order (`sh:N`, the default bake's
// `sh:4`: uniform or levels), with or without depth moments, near or far from the origin,
// --direct baked, runtime and occlusion (the default: per-light visibility). The arithmetic is
// the in-memory lookup's (ShUniformLookup, ShLevelsLookup, ChannelLookup / ShFourUniformLookup,
// OcclusionLookup). Other kinds (bins, moments, irradiance vectors, culled sh:N) are refused
// with the reason; `vdblight query` then reads the whole file unless told --stream on.
#pragma once

#include <memory>
#include <string>

#include "vdblight/query.h"
#include "vdblight/vdb_stream.h"

namespace vdblight {

/// Empty if makeStreamingQuery supports the file's kind, else the reason (one sentence).
std::string streamingSupported(const StreamedVolume& volume);

/// The lookup for `volume`, kind name "sh2-uniform-streamed", "sh2-levels-streamed",
/// "sh4-uniform-streamed" (sh:4 on one level) or "basis-streamed" (other sh:N); with
/// per-light visibility its lookup is also a LightVisibility (light_visibility.h), as
/// OcclusionLookup is. A missing node of a refined cell (a corrupt file, which readVolume
/// refuses) reads as 0 instead of being refused. `depthWeights` as in IrradianceQuery(volume,
/// outside, depthWeights). Throws FormatError for unsupported kinds.
IrradianceQuery makeStreamingQuery(std::shared_ptr<const StreamedVolume> volume, OutsidePolicy outside,
                                   bool depthWeights = true);

}  // namespace vdblight
