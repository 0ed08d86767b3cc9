#include "vdblight/irradiance_vectors.h"

namespace vdblight {
namespace iv {

BasisDesc basis() {
    static const char* kAxis[3] = {"x", "y", "z"};
    static const char* kColour[3] = {"r", "g", "b"};
    BasisDesc desc;
    desc.kind = "irradiance_vectors";
    for (int d = 0; d < kDirections; ++d)
        for (int c = 0; c < 3; ++c)
            desc.channelNames.push_back(std::string("iv_") + kAxis[d / 2] + (d % 2 ? "neg" : "pos") + "_" + kColour[c]);
    return desc;
}

Rgb irradiance(const float* v, const Vec3f& n) {
    Rgb e{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        const float w = n[a] * n[a];
        if (w == 0.0f) continue;
        const float* p = v + 9 * direction(a, n[a] < 0.0f);
        e += Rgb(p[0] * n.x + p[1] * n.y + p[2] * n.z, p[3] * n.x + p[4] * n.y + p[5] * n.z,
                 p[6] * n.x + p[7] * n.y + p[8] * n.z) * w;
    }
    return e;
}

}  // namespace iv
}  // namespace vdblight
