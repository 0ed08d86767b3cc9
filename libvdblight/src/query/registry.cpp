// The kinds of volume that IrradianceQuery can read. A new kind adds one line here.
#include "sh_uniform_lookup.h"
#include "sh4_uniform_lookup.h"
#include "vdblight/basis/basis.h"
#include "query/channel_lookup.h"
#include "vdblight/core/errors.h"
#include "vdblight/query/query.h"
#include "query/query_levels.h"
#include "query/bins_lookup.h"
#include "query/query_direct.h"
#include "shifted_lookup.h"

namespace vdblight {

namespace {
template <typename Lookup>
std::unique_ptr<VolumeLookup> make(const Volume& volume, OutsidePolicy outside) {
    return std::make_unique<Lookup>(volume, outside);
}
}  // namespace

const std::vector<LookupKind>& lookupKinds() {
    static const std::vector<LookupKind> kinds = {
        {"sh2-uniform", &ShUniformLookup::accepts, &make<ShUniformLookup>},
        {"sh4-uniform", &ShFourUniformLookup::accepts, &make<ShFourUniformLookup>},  // the default bake's
        {"irradiance-vectors-uniform", &VectorGridLookup::accepts, &make<VectorGridLookup>},
        {"sh2-levels", &ShLevelsLookup::accepts, &make<ShLevelsLookup>},
        {"bins", &BinsLookup::accepts, &make<BinsLookup>},
        // Every other basis of the registry (basis.h), through the basis's own terms.
        {"basis", &ChannelLookup::accepts, &make<ChannelLookup>},
    };
    return kinds;
}

IrradianceQuery::IrradianceQuery(const Volume& volume, OutsidePolicy outside) {
    volume.validate();
    for (const LookupKind& kind : lookupKinds()) {
        if (!kind.accepts(volume)) continue;
        lookup_ = createAnchored(volume, outside, kind.create);  // shifted_lookup.cpp
        // bake --direct occlusion: add the listed lights' direct light (query_direct.h).
        if (volume.direct.hasVisibility()) lookup_ = std::make_unique<OcclusionLookup>(std::move(lookup_), volume);
        bounds_ = lookup_->bounds();
        kind_ = kind.name;
        const std::unique_ptr<Basis> basis = basisOf(volume.basis);
        viewDependent_ = basis && basis->viewDependent();
        return;
    }
    throw FormatError("no lookup for volumes with basis '" + volume.basis.kind + "' and " +
                      std::to_string(volume.levels.size()) + " levels");
}

IrradianceQuery::IrradianceQuery(const Volume& volume, OutsidePolicy outside, bool depthWeights)
    : IrradianceQuery(volume, outside) {
    lookup_->setDepthWeights(depthWeights);
}

IrradianceQuery::IrradianceQuery(std::unique_ptr<VolumeLookup> lookup, const char* kind)
    : lookup_(std::move(lookup)), bounds_(lookup_->bounds()), kind_(kind) {}

}  // namespace vdblight
