// BasisDesc::sh2 beside the SH code it names (the other bases build theirs in their files).
#include "vdblight/basis_desc.h"

#include "vdblight/sh.h"

namespace vdblight {

BasisDesc BasisDesc::sh2() {
    BasisDesc desc;
    desc.kind = "sh2";
    for (int j = 0; j < sh::kCoeffs; ++j) desc.channelNames.emplace_back(sh::gridName(j));
    return desc;
}

}  // namespace vdblight
