// The compact colour + direction form of a whole irradiance-vector volume (Pacanowski et al.
// 2009, section 4.2; the per-node form and its basis are in irradiance_vectors_compact.h).
#pragma once

#include "vdblight/volume/volume.h"

namespace vdblight {
namespace iv {

/// The compact form of a (single-level) irradiance-vector volume: same grid, metadata plus
/// `compact_form`. Throws FormatError for another kind of volume.
Volume compact(const Volume& full);

}  // namespace iv
}  // namespace vdblight
