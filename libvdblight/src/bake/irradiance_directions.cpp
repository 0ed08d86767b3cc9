#include "irradiance_directions.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdblight::bake_detail::cache_dirs {

namespace {

float signOf(float x) { return x < 0.0f ? -1.0f : 1.0f; }

/// Octahedral map [-1, 1]^2 -> unit sphere (+z at the centre, -z at the corners).
Vec3f decode(float u, float v) {
    const float z = 1.0f - std::abs(u) - std::abs(v);
    float x = u, y = v;
    if (z < 0.0f) {
        x = (1.0f - std::abs(v)) * signOf(u);
        y = (1.0f - std::abs(u)) * signOf(v);
    }
    return normalize(Vec3f(x, y, z));
}

Table build() {
    Table t{};
    int count = 0;
    for (int j = 0; j <= kN; ++j)
        for (int i = 0; i <= kN; ++i) {
            const Vec3f d = decode(-1.0f + 2.0f * float(i) / kN, -1.0f + 2.0f * float(j) / kN);
            int found = -1;
            for (int k = 0; k < count && found < 0; ++k)
                if (length(t.dir[k] - d) < 1e-5f) found = k;
            if (found < 0) {
                if (count == kDirections) throw std::logic_error("octahedral vertex directions: more than kN^2 + 2");
                t.dir[count] = d;
                found = count++;
            }
            t.vertex[j * (kN + 1) + i] = found;
        }
    if (count != kDirections) throw std::logic_error("octahedral vertex directions: fewer than kN^2 + 2");
    return t;
}

}  // namespace

const Table& table() {
    static const Table t = build();
    return t;
}

void weights(const Vec3f& n, int idx[4], float w[4]) {
    const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    float u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0f) {
        const float fu = (1.0f - std::abs(v)) * signOf(u), fv = (1.0f - std::abs(u)) * signOf(v);
        u = fu;
        v = fv;
    }
    const float s = std::clamp((u + 1.0f) * 0.5f * float(kN), 0.0f, float(kN));
    const float t = std::clamp((v + 1.0f) * 0.5f * float(kN), 0.0f, float(kN));
    const int i0 = std::min(int(s), kN - 1), j0 = std::min(int(t), kN - 1);
    const float fs = s - float(i0), ft = t - float(j0);
    const Table& tab = table();
    const int row0 = j0 * (kN + 1), row1 = row0 + kN + 1;
    idx[0] = tab.vertex[row0 + i0];
    idx[1] = tab.vertex[row0 + i0 + 1];
    idx[2] = tab.vertex[row1 + i0];
    idx[3] = tab.vertex[row1 + i0 + 1];
    w[0] = (1.0f - fs) * (1.0f - ft);
    w[1] = fs * (1.0f - ft);
    w[2] = (1.0f - fs) * ft;
    w[3] = fs * ft;
}

}  // namespace vdblight::bake_detail::cache_dirs
