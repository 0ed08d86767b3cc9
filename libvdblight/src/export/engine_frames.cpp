// Engines' axes and units (export_engines.h) and the sh2-packed textures rewritten for them.
#include <cstdio>

#include "engine_internal.h"
#include "vdblight/core/errors.h"

namespace vdblight {

using namespace exporter;

Vec3d EngineFrame::point(const Vec3d& p) const { return direction(p) * metresToUnit; }
Vec3d EngineFrame::direction(const Vec3d& d) const {
    Vec3d out;
    for (int a = 0; a < 3; ++a) out[a] = sign[a] * d[axis[a]];
    return out;
}
Vec3d EngineFrame::volumeDirection(const Vec3d& e) const {
    Vec3d out;
    for (int a = 0; a < 3; ++a) out[axis[a]] = sign[a] * e[a];
    return out;
}

EngineFrame engineFrame(EnginePreset preset) {
    EngineFrame f;
    switch (preset) {
        case EnginePreset::Unity:  // glTF's right is -X (spec 3.4), Unity's +X: the importers negate x
            f.sign[0] = -1;
            f.description = "left-handed, +Y up, +Z forward, metres (Unity)";
            break;
        case EnginePreset::Unreal:  // X forward (= glTF +Z), Y right (= glTF -X), Z up (= glTF +Y)
            f.axis[0] = 2, f.axis[1] = 0, f.axis[2] = 1;
            f.sign[1] = -1;
            f.metresToUnit = 100.0;
            f.description = "left-handed, +Z up, +X forward, centimetres (Unreal)";
            break;
        case EnginePreset::Godot: f.description = "right-handed, +Y up, metres (Godot)"; break;
        case EnginePreset::Three: f.description = "right-handed, +Y up, metres (three.js)"; break;
        case EnginePreset::Bevy: f.description = "right-handed, +Y up, metres (Bevy)"; break;
    }
    return f;
}

namespace exporter {

std::string jsonNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

TextureLattice engineLattice(const EngineFrame& f, const TextureLattice& v) {
    TextureLattice e;
    for (int a = 0; a < 3; ++a) {
        const int s = f.axis[a];
        e.dims[a] = v.dims[s];
        e.lo[a] = f.metresToUnit * (f.sign[a] > 0 ? v.lo[s] : -v.hi[s]);
        e.hi[a] = f.metresToUnit * (f.sign[a] > 0 ? v.hi[s] : -v.lo[s]);
    }
    return e;
}

void volumeTexel(const EngineFrame& f, const TextureLattice& v, const int e[3], int out[3]) {
    for (int a = 0; a < 3; ++a) out[f.axis[a]] = f.sign[a] > 0 ? e[a] : v.dims[f.axis[a]] - 1 - e[a];
}

namespace {
// One colour's E(n) = c + b.n + n'Qn from the packed texels (docs/engines.md, sh2-packed):
// A = (b, c), B = (2 Qxy, 2 Qyz, Qzz, 2 Qzx), C = Qxx = -Qyy.
struct Quadratic {
    double c = 0, b[3] = {0, 0, 0}, q[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};
Quadratic unpack(const float* A, const float* B, float C) {
    Quadratic e;
    for (int a = 0; a < 3; ++a) e.b[a] = A[a];
    e.c = A[3];
    e.q[0][0] = C, e.q[1][1] = -C, e.q[2][2] = B[2];
    e.q[0][1] = e.q[1][0] = 0.5 * B[0];
    e.q[1][2] = e.q[2][1] = 0.5 * B[1];
    e.q[2][0] = e.q[0][2] = 0.5 * B[3];
    return e;
}
// Packs again; on unit normals x^2 + y^2 + z^2 = 1, so t = (Qxx + Qyy) / 2 moves into c.
void pack(const Quadratic& e, float* A, float* B, float* C) {
    const double t = 0.5 * (e.q[0][0] + e.q[1][1]);
    for (int a = 0; a < 3; ++a) A[a] = float(e.b[a]);
    A[3] = float(e.c + t);
    B[0] = float(2 * e.q[0][1]), B[1] = float(2 * e.q[1][2]), B[2] = float(e.q[2][2] - t), B[3] = float(2 * e.q[2][0]);
    *C = float(e.q[0][0] - t);
}
Quadratic toEngine(const EngineFrame& f, const Quadratic& v) {
    Quadratic e;
    e.c = v.c;
    for (int a = 0; a < 3; ++a) {
        e.b[a] = f.sign[a] * v.b[f.axis[a]];
        for (int b = 0; b < 3; ++b) e.q[a][b] = f.sign[a] * f.sign[b] * v.q[f.axis[a]][f.axis[b]];
    }
    return e;
}
}  // namespace

std::vector<std::vector<float>> reorientSh2Packed(const EngineFrame& f, const TextureLattice& v,
                                                  const std::vector<std::vector<float>>& in) {
    if (in.size() != 7) throw FormatError("reorientSh2Packed needs the 7 sh2-packed textures");
    const TextureLattice e = engineLattice(f, v);
    std::vector<std::vector<float>> out(7, std::vector<float>(in[0].size()));
    std::size_t target = 0;
    int idx[3], src[3];
    for (idx[2] = 0; idx[2] < e.dims[2]; ++idx[2])
        for (idx[1] = 0; idx[1] < e.dims[1]; ++idx[1])
            for (idx[0] = 0; idx[0] < e.dims[0]; ++idx[0], ++target) {
                volumeTexel(f, v, idx, src);
                const std::size_t from = 4 * (src[0] + std::size_t(v.dims[0]) * (src[1] + std::size_t(v.dims[1]) * src[2]));
                const std::size_t to = 4 * target;
                for (int c = 0; c < 3; ++c) {  // textures: shAr shAg shAb shBr shBg shBb shC
                    const Quadratic q = toEngine(f, unpack(&in[c][from], &in[3 + c][from], in[6][from + c]));
                    pack(q, &out[c][to], &out[3 + c][to], &out[6][to + c]);
                }
                out[6][to + 3] = in[6][from + 3];
            }
    return out;
}

}  // namespace exporter
}  // namespace vdblight
