// BasisDesc::sh2 beside the SH code it names (the other bases build theirs in their files).
#include "vdblight/basis/basis.h"

#include "vdblight/basis/irradiance_vectors.h"
#include "basis/irradiance_vectors_compact.h"
#include "basis/sh.h"

namespace vdblight {

BasisDesc BasisDesc::sh2() {
    BasisDesc desc;
    desc.kind = "sh2";
    for (int j = 0; j < sh::kCoeffs; ++j) desc.channelNames.emplace_back(sh::gridName(j));
    return desc;
}

bool BasisDesc::isSh2() const { return kind == "sh2"; }

bool BasisDesc::isRealSh() const { return isSh2() || kind.rfind("sh:", 0) == 0; }

int BasisDesc::shOrder() const {
    if (isSh2()) return 2;
    // Digits as the registry writes them ("sh:4", not "sh:04").
    if (kind.rfind("sh:", 0) != 0 || kind.size() == 3 || (kind.size() > 4 && kind[3] == '0')) return -1;
    int order = 0;
    for (std::size_t i = 3; i < kind.size(); ++i) {
        if (kind[i] < '0' || kind[i] > '9' || order > 1000) return -1;
        order = order * 10 + (kind[i] - '0');
    }
    return order;
}

bool BasisDesc::isIrradianceVectors() const { return kind == iv::basis().kind; }

bool BasisDesc::isCompactIrradianceVectors() const { return kind == iv::compactBasis().kind; }

bool BasisDesc::sameKind(const BasisDesc& other) const { return kind == other.kind; }

}  // namespace vdblight
