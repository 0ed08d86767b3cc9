// Greger bins: the equal-area sphere map, bin names, basis parsing and quadrature weights.
#include "vdblight/basis/bins.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"

namespace vdblight {
namespace bins {

namespace {
/// Strict positive integer from text (ValueError naming `what`).
int parsePositive(const std::string& text, const std::string& whole) {
    if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos)
        throw ValueError("--basis '" + whole + "': expected a positive integer, got '" + text + "'");
    const int value = std::atoi(text.c_str());
    if (value < 1) throw ValueError("--basis '" + whole + "': the number must be at least 1, got " + text);
    return value;
}

/// Shirley-Chiu concentric map in double (the float version is in sampling.h).
void concentricDouble(double u, double v, double& dx, double& dy) {
    const double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
    if (a == 0.0 && b == 0.0) {
        dx = dy = 0.0;
        return;
    }
    double r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4) * (b / a);
    } else {
        r = b;
        phi = kPi / 2 - (kPi / 4) * (a / b);
    }
    dx = r * std::cos(phi);
    dy = r * std::sin(phi);
}

double powInt(double x, int n) {
    double p = 1.0;
    for (int k = 0; k < n; ++k) p *= x;
    return p;
}
}  // namespace

BasisSpec parseBasisSpec(const std::string& text) {
    BasisSpec spec;
    if (text == "sh2") return spec;
    const std::size_t colon = text.find(':');
    const std::string head = text.substr(0, colon);
    if (colon == std::string::npos || (head != "bins" && head != "moment"))
        throw ValueError("--basis must be sh2, bins:N or moment:N[:R], got '" + text + "'");
    const std::string rest = text.substr(colon + 1);
    if (head == "bins") {
        spec.kind = BasisSpec::Kind::Bins;
        spec.resolution = parsePositive(rest, text);
        spec.order = 1;
    } else {
        spec.kind = BasisSpec::Kind::Moment;
        const std::size_t second = rest.find(':');
        spec.order = parsePositive(rest.substr(0, second), text);
        if (second != std::string::npos) spec.resolution = parsePositive(rest.substr(second + 1), text);
    }
    if (spec.resolution > 64)
        throw ValueError("--basis '" + text + "': resolution " + std::to_string(spec.resolution) +
                         " gives " + std::to_string(spec.binCount()) + " bins per node; use at most 64");
    if (spec.order > 1000) throw ValueError("--basis '" + text + "': moment order above 1000 is absurd");
    return spec;
}

bool viewDependent(const BasisDesc& basis) { return basis.kind.rfind("moment:", 0) == 0; }

std::string kindName(const BasisSpec& spec) {
    switch (spec.kind) {
        case BasisSpec::Kind::Bins: return "bins:" + std::to_string(spec.resolution);
        case BasisSpec::Kind::Moment: return "moment:" + std::to_string(spec.order);
        default: return "sh2";
    }
}

bool specFromVolume(const BasisDesc& basis, BasisSpec& spec) {
    const std::string& k = basis.kind;
    const bool isBins = k.rfind("bins:", 0) == 0, isMoment = k.rfind("moment:", 0) == 0;
    if (!isBins && !isMoment) return false;
    const int channels = basis.channelCount();
    const int r = int(std::lround(std::sqrt(channels / 2.0)));
    if (r < 1 || 2 * r * r != channels) return false;
    try {
        spec = parseBasisSpec(isBins ? k : k + ":" + std::to_string(r));
    } catch (const ValueError&) {
        return false;
    }
    if (spec.resolution != r) return false;
    for (int c = 0; c < channels; ++c)
        if (basis.channelNames[std::size_t(c)] != channelName(r, c)) return false;
    return true;
}

std::string channelName(int resolution, int channel) {
    const int rr = resolution * resolution;
    const int h = channel / rr, iv = channel % rr / resolution, iu = channel % resolution;
    return "bin_h" + std::to_string(h) + "_u" + std::to_string(iu) + "_v" + std::to_string(iv);
}

BasisDesc basis(const BasisSpec& spec) {
    BasisDesc desc;
    desc.kind = kindName(spec);
    for (int c = 0; c < spec.binCount(); ++c) desc.channelNames.push_back(channelName(spec.resolution, c));
    return desc;
}

Vec3f squareToDirection(int h, float u, float v) {
    float dx, dy;
    concentricSquareToDisk(u, v, dx, dy);
    const float r2 = std::min(dx * dx + dy * dy, 1.0f);
    const float s = std::sqrt(2.0f - r2);
    return {dx * s, dy * s, h ? r2 - 1.0f : 1.0f - r2};
}

Vec3d squareToDirection(int h, double u, double v) {
    double dx, dy;
    concentricDouble(u, v, dx, dy);
    const double r2 = std::min(dx * dx + dy * dy, 1.0);
    const double s = std::sqrt(2.0 - r2);
    return {dx * s, dy * s, h ? r2 - 1.0 : 1.0 - r2};
}

void directionToSquare(const Vec3f& w, int& h, float& u, float& v) {
    h = w.z < 0.0f ? 1 : 0;
    // r^2 = 1 - |z| and |(x, y)| = r sqrt(2 - r^2) = r sqrt(1 + |z|): the disk point is
    // (x, y) / sqrt(1 + |z|), without the cancellation of 1 - |z| near the poles.
    const float inv = 1.0f / std::sqrt(1.0f + std::abs(w.z));
    concentricDiskToSquare(w.x * inv, w.y * inv, u, v);
}

int binOf(int resolution, const Vec3f& w) {
    int h;
    float u, v;
    directionToSquare(w, h, u, v);
    const int iu = std::min(int(u * float(resolution)), resolution - 1);
    const int iv = std::min(int(v * float(resolution)), resolution - 1);
    return channel(resolution, h, std::max(iu, 0), std::max(iv, 0));
}

int lookupWeights(int R, bool interpolate, const Vec3f& d, int channels[4], float weights[4]) {
    int h;
    float u, v;
    directionToSquare(d, h, u, v);
    if (!interpolate) {
        const int iu = std::max(0, std::min(int(u * float(R)), R - 1));
        const int iv = std::max(0, std::min(int(v * float(R)), R - 1));
        channels[0] = channel(R, h, iu, iv);
        weights[0] = 1.0f;
        return 1;
    }
    const float gu = u * float(R) - 0.5f, gv = v * float(R) - 0.5f;
    const int iu0 = int(std::floor(gu)), iv0 = int(std::floor(gv));
    const float fu = gu - float(iu0), fv = gv - float(iv0);
    int count = 0;
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            // Across an edge of the square (the equator) lies the other hemisphere's border bin
            // at the mirrored position; across a corner, both edges: back to this hemisphere.
            int iu = iu0 + a, iv = iv0 + b, hh = h;
            if (iu < 0 || iu >= R) hh = 1 - hh, iu = std::max(0, std::min(iu, R - 1));
            if (iv < 0 || iv >= R) hh = 1 - hh, iv = std::max(0, std::min(iv, R - 1));
            channels[count] = channel(R, hh, iu, iv);
            weights[count] = (a ? fu : 1.0f - fu) * (b ? fv : 1.0f - fv);
            ++count;
        }
    return count;
}

Vec3d binCentre(int resolution, int c) {
    const int rr = resolution * resolution;
    const int h = c / rr, iv = c % rr / resolution, iu = c % resolution;
    return squareToDirection(h, (iu + 0.5) / resolution, (iv + 0.5) / resolution);
}

std::vector<float> quadratureWeights(const BasisSpec& spec, int sub) {
    const int R = spec.resolution, bins = spec.binCount(), n = spec.order;
    if (sub <= 0) {
        const double perPair = 2.0e7 / (double(bins) * bins);
        sub = std::min(64, std::max(4, int(std::sqrt(perPair))));
    }
    // Midpoint sample directions of every bin, and each bin's angular radius (for skipping
    // bins entirely behind a row's direction).
    const int ss = sub * sub;
    std::vector<Vec3d> dirs(std::size_t(bins) * ss);
    std::vector<Vec3d> centre(static_cast<std::size_t>(bins));
    std::vector<double> behind(static_cast<std::size_t>(bins));  // dot(centre_i, w_j) below this: bin i is behind w_j
    for (int c = 0; c < bins; ++c) {
        const int rr = R * R, h = c / rr, iv = c % rr / R, iu = c % R;
        centre[std::size_t(c)] = binCentre(R, c);
        double minCos = 1.0;
        for (int b = 0; b < sub; ++b)
            for (int a = 0; a < sub; ++a) {
                const Vec3d d = squareToDirection(h, (iu + (a + 0.5) / sub) / R, (iv + (b + 0.5) / sub) / R);
                dirs[std::size_t(c) * ss + std::size_t(b * sub + a)] = d;
            }
        for (int b = 0; b <= 2; ++b)  // corners and edge midpoints bound the bin's extent
            for (int a = 0; a <= 2; ++a)
                minCos = std::min(minCos, dot(centre[std::size_t(c)],
                                              squareToDirection(h, (iu + 0.5 * a) / R, (iv + 0.5 * b) / R)));
        const double radius = std::min(kPi / 2, 1.5 * std::acos(std::max(-1.0, std::min(1.0, minCos))));
        behind[std::size_t(c)] = -std::sin(radius);
    }
    const double scale = 0.5 * (n + 1) * binSolidAngle(R) / ss;
    std::vector<float> w(std::size_t(bins) * bins, 0.0f);
    for (int j = 0; j < bins; ++j) {
        const Vec3d& wj = centre[std::size_t(j)];
        for (int i = 0; i < bins; ++i) {
            if (dot(centre[std::size_t(i)], wj) < behind[std::size_t(i)]) continue;
            double sum = 0.0;
            const Vec3d* d = &dirs[std::size_t(i) * ss];
            for (int s = 0; s < ss; ++s) {
                const double c = dot(d[s], wj);
                if (c > 0.0) sum += powInt(c, n);
            }
            w[std::size_t(j) * bins + i] = float(sum * scale);
        }
    }
    return w;
}

}  // namespace bins
}  // namespace vdblight
