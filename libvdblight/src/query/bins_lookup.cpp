// Bins / moment lookup: the generic ChannelLookup with the bins basis, and the simple
// reference it is tested against.
#include "query/bins_lookup.h"

#include "vdblight/core/errors.h"
#include "vdblight/layout/layout.h"

namespace vdblight {

namespace {
bins::BasisSpec binsSpec(const Volume& volume) {
    bins::BasisSpec spec;
    if (!bins::specFromVolume(volume.basis, spec))
        throw FormatError("volume basis '" + volume.basis.kind + "' is not a bins or moment basis");
    return spec;
}
}  // namespace

bool BinsLookup::accepts(const Volume& volume) {
    bins::BasisSpec spec;
    return bins::specFromVolume(volume.basis, spec);
}

BinsLookup::BinsLookup(const Volume& volume, OutsidePolicy outside, bool interpolateBins)
    : ChannelLookup(volume, outside, bins::makeBinsBasis(binsSpec(volume), interpolateBins)), spec_(binsSpec(volume)), interpolate_(interpolateBins) {}

Rgbd referenceBinsLookup(const Volume& volume, const Vec3d& x, const Vec3f& d) {
    bins::BasisSpec spec;
    if (!bins::specFromVolume(volume.basis, spec)) throw FormatError("not a bins or moment volume");
    int cell[3];
    double frac[3];
    const std::size_t l = finestCellAt(volume.levels, volume.refineFactor(), x, cell, frac);
    const VolumeLevel& level = volume.levels[l];
    const int dims[3] = {level.grid.nx, level.grid.ny, level.grid.nz};  // a one-node axis stays one node
    const int bin = bins::binOf(spec.resolution, d);
    Rgbd e{0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        int c[3];
        double w = 1.0;
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            if (dims[a] < 2 && bit) w = 0.0;
            c[a] = cell[a] + (dims[a] < 2 ? 0 : bit);
            w *= bit ? frac[a] : 1.0 - frac[a];
        }
        if (w == 0.0) continue;
        const int64_t at = findNode(level, level.grid.index(c[0], c[1], c[2]));
        if (at < 0) throw FormatError("lookup would read a node of level " + std::to_string(l) + " that was not baked");
        const float* p = level.nodeData(std::size_t(at), volume.basis.channelCount()) + 3 * bin;
        e += Rgbd(p[0], p[1], p[2]) * w;
    }
    return e;
}

}  // namespace vdblight
