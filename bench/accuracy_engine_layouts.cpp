// vdblight_bench_accuracy: what the engine-size export layouts (sh1-16, sh2-32; issue 33) hold
// of the default bake, beside its bands 0..2 (default_l2, `query --sh-order 2`).
//
// The three rows read one bake: the default is baked once per scene and seed in this process
// and kept (the bake is deterministic, so a second bake would give the same bits), and each
// row reads it its own way. `--config default_l2` runs just these rows.
#include "accuracy.h"

#include <memory>

#include <half.h>

#include "../libvdblight/src/export/compact_sh.h"  // internal: the texel encoding, for the filtered read
#include "export/export_compact.h"
#include "vdblight/query/query.h"
#include "basis/sh.h"
#include "volume/sh_truncate.h"

namespace vdblight::accuracy {

namespace {
struct KeptBake {
    const Scene* scene = nullptr;
    uint64_t seed = 0;
    std::shared_ptr<const Volume> volume;
    double seconds = 0;
    std::string note;
};

// The default bake of (scene, seed), baked on first use. Only the current scene's are kept.
const KeptBake& defaultBake(const Ctx& c, const TrySpec& def) {
    static std::vector<KeptBake> kept;
    for (const KeptBake& k : kept)
        if (k.scene == &c.scene && k.seed == c.seed) return k;
    kept.erase(std::remove_if(kept.begin(), kept.end(), [&](const KeptBake& k) { return k.scene != &c.scene; }),
               kept.end());
    KeptBake k;
    k.scene = &c.scene;
    k.seed = c.seed;
    const double t0 = bench::now();
    k.volume = std::make_shared<const Volume>(tryVolume(c, def, k.note));
    k.seconds = bench::now() - t0;
    kept.push_back(std::move(k));
    return kept.back();
}

Baked readDefault(const Ctx& c, const TrySpec& def, const std::function<Volume(const Volume&)>& read,
                  const std::string& what) {
    const KeptBake& k = defaultBake(c, def);
    Baked b = fromVolume(read(*k.volume), k.seconds, k.volume->levels[0].grid.nodeCount());
    b.note = k.note.empty() ? what : k.note + ", " + what;
    return b;
}
// What the layout adds by itself, whatever the ground truth: its relative difference from the
// same bake's bands it stores (`reference`), at the benchmark's points (the same fixed-seed set),
// guarded below by 1 % of the mean as the errors are.
std::string addedByLayout(const Ctx& c, const Baked& layout, const Baked& reference, const char* bands) {
    const Points pts = freeSpacePoints(c.scene, c.tracer, c.settings.points);
    const std::vector<double> got = values(layout.irradiance, pts), want = values(reference.irradiance, pts);
    double mean = 0;
    for (double w : want) mean += w / double(want.size());
    double s2 = 0, worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const double d = (got[i] - want[i]) / std::max(want[i], 0.01 * mean);
        s2 += d * d;
        worst = std::max(worst, std::fabs(d));
    }
    char buf[160];
    std::snprintf(buf, sizeof buf, "vs %s of the same bake: RMS %.3f %%, max %.2f %%", bands,
                  100 * std::sqrt(s2 / double(got.size())), 100 * worst);
    return buf;
}
// The shortcut docs/engine_layouts.md warns about ("Decode before blending"): APV filters the encoded
// textures in hardware and decodes once with the filtered L0. At each point, the SH part of the
// layout's export read that way against the same texels decoded first and then blended (both
// trilinear between the export's texel points, which are the bake's nodes): RMS and max of the
// relative difference, guarded by 1 % of the mean.
std::string filteredDecodeCost(const Ctx& c, const Volume& baked, ExportLayout layout) {
    using namespace exporter;
    const Volume l2 = truncateSh(baked, 2);
    const IrradianceQuery query(l2);
    double finest = 0;
    for (const VolumeLevel& level : l2.levels) finest = finest > 0 ? std::min(finest, level.grid.spacing) : level.grid.spacing;
    const TextureLattice lattice = chooseLattice(query.bounds(), finest, 0);
    const std::size_t floats = compactShTextures(layout).size() * 4;
    auto stored = [&](int i, int j, int k) {  // one texel as the files hold it
        Rgb L[9];
        query.lookup().shRadiance(lattice.point(i, j, k), L);
        std::vector<float> t(floats);
        packCompactTexel(layout, L, t.data());
        for (std::size_t q = 0; q < floats; ++q) t[q] = q < 4 ? float(Imath::half(t[q])) : float(unorm8(t[q])) / 255.0f;
        return t;
    };
    const Points pts = freeSpacePoints(c.scene, c.tracer, c.settings.points);
    std::vector<double> filtered, blended;
    const Vec3d h = lattice.spacing();
    for (std::size_t p = 0; p < pts.x.size(); ++p) {
        int i0[3];
        double f[3];
        for (int a = 0; a < 3; ++a) {
            const double g = std::clamp((double(pts.x[p][a]) - lattice.lo[a]) / h[a], 0.0, double(lattice.dims[a] - 1));
            i0[a] = std::min(int(g), std::max(lattice.dims[a] - 2, 0));
            f[a] = g - i0[a];
        }
        std::vector<float> encoded(floats, 0.0f);
        Rgb decodedSum[9] = {};
        for (int k = 0; k < 8; ++k) {
            const int b[3] = {k & 1, (k >> 1) & 1, k >> 2};
            const double w = (b[0] ? f[0] : 1 - f[0]) * (b[1] ? f[1] : 1 - f[1]) * (b[2] ? f[2] : 1 - f[2]);
            const std::vector<float> t = stored(std::min(i0[0] + b[0], lattice.dims[0] - 1),
                                                std::min(i0[1] + b[1], lattice.dims[1] - 1),
                                                std::min(i0[2] + b[2], lattice.dims[2] - 1));
            for (std::size_t q = 0; q < floats; ++q) encoded[q] += float(w) * t[q];
            Rgb L[9];
            unpackCompactTexel(layout, t.data(), L);
            for (int j = 0; j < 9; ++j) decodedSum[j] = decodedSum[j] + L[j] * float(w);
        }
        Rgb L[9];
        unpackCompactTexel(layout, encoded.data(), L);
        filtered.push_back(luminance(sh::irradiance(L, pts.n[p])));
        blended.push_back(luminance(sh::irradiance(decodedSum, pts.n[p])));
    }
    double mean = 0;
    for (double v : blended) mean += v / double(blended.size());
    double s2 = 0, worst = 0;
    for (std::size_t i = 0; i < blended.size(); ++i) {
        const double d = (filtered[i] - blended[i]) / std::max(std::fabs(blended[i]), 0.01 * mean);
        s2 += d * d;
        worst = std::max(worst, std::fabs(d));
    }
    char buf[160];
    std::snprintf(buf, sizeof buf, "decoding after hardware filtering instead (APV's way) moves the SH part by RMS %.2f %%, max %.1f %%",
                  100 * std::sqrt(s2 / double(blended.size())), 100 * worst);
    return buf;
}
}  // namespace

void addEngineLayoutConfigs(std::vector<Config>& v, const TrySpec& def) {
    // What an engine's L2 probes hold of the default: its bands 0..2 (export sh2 / sh2-packed,
    // query --sh-order 2; sh_truncate.h). Measured with noise, as the default.
    v.push_back({"default_l2", "the default's bands 0..2 (what export's SH order-2 layouts and an engine's L2 probes hold)",
                 [def](const Ctx& c) {
                     return readDefault(c, def, [](const Volume& vol) { return truncateSh(vol, 2); }, "bands 0..2");
                 },
                 true});
    // Bands 0..1 of the same bake (export --layout sh1 holds them; query --sh-order 1).
    v.push_back({"default_l2_l1", "the default's bands 0..1 (what export --layout sh1 and an engine's L1 probes hold)",
                 [def](const Ctx& c) {
                     return readDefault(c, def, [](const Volume& vol) { return truncateSh(vol, 1); }, "bands 0..1");
                 },
                 true});
    // The same bake through the 32 B and 16 B layouts: what their textures decode to at every
    // node (L0 in half, the other bands / L0 and the light visibility in 8 bits), read by the
    // library's lookup with the depth weights, as docs/engine_visibility.md's shader reads the files.
    const std::pair<ExportLayout, const char*> layouts[] = {
        {ExportLayout::Sh2x32, "export --layout sh2-32: bands 0..2 in 32 B per probe (L0 half, the rest / L0 in UNORM8), "
                               "visibility in 8 bits"},
        {ExportLayout::Sh1x16, "export --layout sh1-16: bands 0..1 in 16 B per probe (L0 half, L1 / L0 in UNORM8), "
                               "visibility in 8 bits"}};
    for (const auto& [layout, what] : layouts)
        v.push_back({std::string("default_l2_") + (layout == ExportLayout::Sh2x32 ? "sh2_32" : "sh1_16"), what,
                     [def, layout = layout](const Ctx& c) {
                         Baked b = readDefault(c, def, [layout](const Volume& vol) { return compactShRoundTrip(vol, layout); },
                                               layoutName(layout));
                         const int order = layout == ExportLayout::Sh2x32 ? 2 : 1;
                         const Baked bands = readDefault(c, def, [order](const Volume& vol) { return truncateSh(vol, order); }, "");
                         b.note += "; " + addedByLayout(c, b, bands, order == 2 ? "bands 0..2" : "bands 0..1");
                         // B/node: the exported textures' (ktx2, dds, raw), not a .vdb's: the layout,
                         // one RGBA8 texel per four listed lights, 12 B of depth moments.
                         const Volume& baked = *defaultBake(c, def).volume;
                         const std::size_t lights = baked.direct.hasVisibility() ? baked.direct.lights.size() : 0;
                         const uint64_t perNode = (order == 2 ? 32 : 16) + 4 * ((lights + 3) / 4) + (baked.hasDepth() ? 12 : 0);
                         b.bytes = perNode * b.nodes;
                         b.note += "; B/node = the export's; " + filteredDecodeCost(c, baked, layout);
                         return b;
                     },
                     true});
}

}  // namespace vdblight::accuracy
