// A real-SH volume cut to fewer bands: what an engine's L1/L2 probes hold of a volume baked
// with a higher order (bake --basis sh:4, the default's point gather).
//
//   Volume v = readVolume("room.vdb");          // sh:4, 25 channels
//   Volume l2 = truncateSh(v, 2);               // sh2, the first 9 channels of each node
//   IrradianceQuery q(l2);                      // what export --layout sh2 / sh2-packed holds
//
// Truncating orthonormal SH is the projection onto the kept bands, so the result is the SH of
// lower order of the same bake's radiance (docs/engines.md, "basis"). `vdblight query
// --sh-order N` answers with it.
#pragma once

#include "vdblight/volume/volume.h"

namespace vdblight {

/// The real-SH order a volume stores (2 for sh2, N for sh:N), or -1 for any other basis.
int storedShOrder(const Volume& volume);

/// `volume` with bands 0..order of its real SH (order 2: basis sh2, so the SH order-2
/// lookups apply; otherwise sh:order). Depth moments, validity, light visibility, lights and
/// metadata are kept. Throws ValueError if the volume stores no real SH or fewer bands than
/// `order`, or if order < 1.
Volume truncateSh(Volume volume, int order);

}  // namespace vdblight
