// The engine-size SH layouts (export --layout sh1-16 | sh2-32; docs/engines.md): what their
// textures decode to, as a volume, so that its error can be measured with the library's own
// lookup (vdblight_bench_accuracy) and checked against the files an export writes.
//
//   Volume v = readVolume("room.vdb");                        // sh:4, depth, visibility
//   Volume engine = compactShRoundTrip(v, ExportLayout::Sh2x32);
//   IrradianceQuery q(engine);   // = the shader of docs/engines.md on the exported textures
#pragma once

#include "vdblight/export/export.h"
#include "vdblight/volume/volume.h"

namespace vdblight {

/// `volume` (real SH of order 2 or more) cut to SH order 2, with every node's coefficients
/// replaced by what its texel of `layout` decodes to: L0 rounded to half (float with
/// halfFloat false), the higher bands to UNORM8 after division by L0 (band 2 zero for
/// sh1-16), the light visibility of --direct occlusion to 8 bits and its shadow edges to half
/// (with halfFloat). Depth moments are kept (the depth textures hold them exactly). For a uniform volume exported at its nodes (no
/// --resolution) the nodes are the texels, so IrradianceQuery on the result is what the
/// exported textures give through docs/engines.md's shader, to float rounding.
/// Throws FormatError for another layout or a volume without real SH of order >= 2.
Volume compactShRoundTrip(const Volume& volume, ExportLayout layout, bool halfFloat = true);

}  // namespace vdblight
