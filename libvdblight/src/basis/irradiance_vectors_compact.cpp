#include "basis/irradiance_vectors_compact.h"

#include <cmath>

#include "vdblight/core/errors.h"

namespace vdblight {
namespace iv {

BasisDesc compactBasis() {
    static const char* kAxis[3] = {"x", "y", "z"};
    BasisDesc desc;
    desc.kind = "irradiance_vectors_compact";
    for (int d = 0; d < kDirections; ++d) {
        const std::string stem = std::string("ivc_") + kAxis[d / 2] + (d % 2 ? "neg" : "pos");
        desc.channelNames.push_back(stem + "_rgb");
        desc.channelNames.push_back(stem + "_dir");
    }
    return desc;
}

void compactNode(const float* full, float* out) {
    for (int d = 0; d < kDirections; ++d) {
        const float* v = full + 9 * d;  // colour-major: v[3 c + k]
        float* colour = out + 6 * d;
        float* dir = colour + 3;
        double sum[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c) {
            double n2 = 0;
            for (int k = 0; k < 3; ++k) {
                n2 += double(v[3 * c + k]) * v[3 * c + k];
                sum[k] += v[3 * c + k];
            }
            colour[c] = float(std::sqrt(n2));
        }
        const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        for (int k = 0; k < 3; ++k) dir[k] = len > 0 ? float(sum[k] / len) : 0.0f;
    }
}

void expandNode(const float* compactValues, float* full) {
    for (int d = 0; d < kDirections; ++d) {
        const float* colour = compactValues + 6 * d;
        const float* dir = colour + 3;
        float* v = full + 9 * d;  // colour-major: v[3 c + k]
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) v[3 * c + k] = colour[c] * dir[k];
    }
}

Rgb compactIrradiance(const float* v, const Vec3f& n, Blend blend) {
    float full[kFloatsPerNode] = {};
    for (int d = 0; d < kDirections; ++d) {
        // Paper reads only the directions of n's signs (the others stay zero, unread).
        if (blend == Blend::Paper && d != direction(d / 2, n[d / 2] < 0.0f)) continue;
        const float* colour = v + 6 * d;
        const Vec3f dir(colour[3], colour[4], colour[5]);
        const float len = length(dir);
        if (!(len > 0.0f)) continue;
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) full[9 * d + 3 * c + k] = colour[c] * (dir[k] / len);
    }
    return irradiance(full, n, blend);
}

}  // namespace iv
}  // namespace vdblight
