#include "vdblight/sampling/sampling.h"

namespace vdblight {

double radicalInverse(uint32_t base, uint64_t i) {
    const double invBase = 1.0 / base;
    double invBi = 1.0, result = 0.0;
    while (i > 0) {
        const uint64_t next = i / base;
        const uint64_t digit = i - next * base;
        invBi *= invBase;
        result += double(digit) * invBi;
        i = next;
    }
    return result < 1.0 ? result : 0x1.fffffffffffffp-1;
}

Vec3f uniformSphere(float u, float v) {
    const float z = 1.0f - 2.0f * u;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = float(2.0 * kPi) * v;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

void concentricSquareToDisk(float u, float v, float& dx, float& dy) {
    // Shirley & Chiu 1997: concentric squares map to concentric circles, preserving
    // area fractions, which keeps stratification intact.
    const float a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
    if (a == 0.0f && b == 0.0f) {
        dx = dy = 0.0f;
        return;
    }
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = float(kPi / 4) * (b / a);
    } else {
        r = b;
        phi = float(kPi / 2) - float(kPi / 4) * (a / b);
    }
    dx = r * std::cos(phi);
    dy = r * std::sin(phi);
}

void concentricDiskToSquare(float dx, float dy, float& u, float& v) {
    const float r = std::sqrt(dx * dx + dy * dy);
    float phi = std::atan2(dy, dx);  // (-pi, pi]
    if (phi < float(-kPi / 4)) phi += float(2 * kPi);
    float a, b;
    if (phi < float(kPi / 4)) {  // region 1: a = r
        a = r;
        b = phi * a / float(kPi / 4);
    } else if (phi < float(3 * kPi / 4)) {  // region 2: b = r
        b = r;
        a = -(phi - float(kPi / 2)) * b / float(kPi / 4);
    } else if (phi < float(5 * kPi / 4)) {  // region 3: a = -r
        a = -r;
        b = (phi - float(kPi)) * a / float(kPi / 4);
    } else {  // region 4: b = -r
        b = -r;
        a = -(phi - float(3 * kPi / 2)) * b / float(kPi / 4);
    }
    u = std::min(std::max(0.5f * (a + 1.0f), 0.0f), 1.0f);
    v = std::min(std::max(0.5f * (b + 1.0f), 0.0f), 1.0f);
}

Vec3f cosineHemisphere(float u, float v) {
    float dx, dy;
    concentricSquareToDisk(u, v, dx, dy);
    const float z = std::sqrt(std::max(0.0f, 1.0f - dx * dx - dy * dy));
    return {dx, dy, z};
}

void uniformTriangle(float u, float v, float& b1, float& b2) {
    // Square-root parameterisation: area-uniform and smooth in (u, v).
    const float su = std::sqrt(u);
    b1 = 1.0f - su;
    b2 = v * su;
}

}  // namespace vdblight
