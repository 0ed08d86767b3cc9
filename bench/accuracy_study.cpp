// vdblight_bench_accuracy --study R: where the default bake's error comes from.
#include "accuracy.h"

#include <tbb/parallel_for.h>

#include "vdblight/bake/each_pass.h"
#include "vdblight/light/light.h"

namespace vdblight::accuracy {

// ---------------------------------------------------------------------------------------
// --study: where the default bake's error comes from, per scene and region (issue 15).
//
// floor   the default's representation at each point itself: the SH2 of the light the default
//         bake keeps in SH (its transport, with the chosen lights' direct light left out at the
//         receiver) projected at the point (F/4 and F rays, noise extrapolated out), plus each
//         chosen light's exact irradiance times its visibility from the point (256 samples);
// bakes   the default's grid with {no probe pass, one probe pass} x {R, 4R rays}, looked up
//         {depth-weighted, plain trilinear}; each against the truth and against the floor, with
//         the noise extrapolated out of R and 4R (squared noise ~ 1/N). "interp" = the bake
//         against the floor (what interpolation between nodes adds), "bias" = mean signed error.

namespace {
struct StudyBake {
    std::string name;
    std::vector<double> lo, hi;  ///< values at the points at R and 4R rays
    double seconds = 0;
};

void printStudy(const char* region, const std::vector<std::size_t>& idx, const Truth& truth, const std::vector<double>& floorQ,
                const std::vector<double>& floorF, const std::vector<double>& cosF, const std::vector<double>& sh4F, const std::vector<StudyBake>& bakes, FILE* csv,
                const std::string& scene) {
    auto pick = [&](const std::vector<double>& v) {
        std::vector<double> o;
        for (std::size_t i : idx) o.push_back(v[i]);
        return o;
    };
    Truth t;
    t.mean = truth.mean;
    t.guard = truth.guard;
    t.e = pick(truth.e);
    t.se = pick(truth.se);
    const Errors fq = summarise(relative(pick(floorQ), t.e, t)), ff = summarise(relative(pick(floorF), t.e, t));
    // SH2 against the cosine-weighted E of the same samples: the representation alone (the
    // samples' noise is common to both and mostly cancels).
    const Errors rep = summarise(relative(pick(floorF), pick(cosF), t));
    const Errors rep4 = summarise(relative(pick(sh4F), pick(cosF), t));
    std::printf("    %-10s %3zu points: floor RMS %.1f %% (noise-free %.1f %%), bias %+.1f %%; SH2 vs the same samples' cosine-weighted "
                "E: RMS %.1f %%, bias %+.1f %%; SH4 vs them: RMS %.1f %%, bias %+.1f %%\n", region, idx.size(), 100 * ff.rms,
                100 * noiseFree(fq.rms, ff.rms), 100 * ff.bias, 100 * rep.rms, 100 * rep.bias, 100 * rep4.rms, 100 * rep4.bias);
    Row fr{scene + (region[0] ? std::string(":") + region : ""), "study_floor", ff};
    fr.note = "noise-free " + std::to_string(noiseFree(fq.rms, ff.rms));
    writeCsvRow(csv, fr);
    for (const StudyBake& b : bakes) {
        const Errors lo = summarise(relative(pick(b.lo), t.e, t)), hi = summarise(relative(pick(b.hi), t.e, t));
        // Bake at R against the floor at F/4, at 4R against the floor at F: both noises fall 4x in squares.
        const Errors ilo = summarise(relative(pick(b.lo), pick(floorQ), t)), ihi = summarise(relative(pick(b.hi), pick(floorF), t));
        const double nf = noiseFree(lo.rms, hi.rms), inf = noiseFree(ilo.rms, ihi.rms);
        const double noiseR = std::sqrt(std::max(0.0, (lo.rms * lo.rms - nf * nf)));
        std::printf("      %-24s truth: R %5.1f %% (%+.1f), 4R %5.1f %% (%+.1f), noise-free %5.1f %% (noise at R %4.1f %%); "
                    "vs floor: 4R %5.1f %% (%+.1f), noise-free %5.1f %%\n",
                    b.name.c_str(), 100 * lo.rms, 100 * lo.bias, 100 * hi.rms, 100 * hi.bias, 100 * nf, 100 * noiseR,
                    100 * ihi.rms, 100 * ihi.bias, 100 * inf);
        Row r{fr.scene, "study_" + b.name, hi};
        r.seconds = b.seconds;
        r.note = "noise-free " + std::to_string(nf) + " interp-noise-free " + std::to_string(inf);
        writeCsvRow(csv, r);
    }
}
}  // namespace

DefaultPlan defaultPlan(const Scene& s, const Tracer& tracer, const Settings& st) {
    DefaultPlan p;
    p.grid = tryGrid(s, parseTry("nodes=16384"), st);
    DirectOptions d;
    d.mode = p.mode = sceneLights(s).empty() ? DirectMode::Baked : DirectMode::Occlusion;
    d.threads = st.threads;
    p.lights = planDirectLight(s, tracer, p.grid, d);
    p.transport.skipAtReceiver = p.lights.filter;
    return p;
}

Rgb exactDirectAt(const Scene& s, const Tracer& tracer, const DefaultPlan& p, const Points& pts, std::size_t i) {
    const Vec3f n = normalize(pts.n[i]);
    Rgb direct(0, 0, 0);
    if (p.mode != DirectMode::Occlusion) return direct;
    const std::vector<SceneLight>& lights = p.lights.lights;
    for (std::size_t l = 0; l < lights.size(); ++l) {
        RayCount rc;
        const double vis = lightVisibility(s, tracer, lights[l], pts.x[i], 256, hashCombine(4242, i * 31 + l), rc);
        direct += exactIrradiance(lights[l].light, Vec3d(pts.x[i]), Vec3d(n)) * float(vis);
    }
    return direct;
}

void studyDefault(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth, const Settings& st,
                  uint32_t rays, uint32_t floorRays, FILE* csv) {
    const Scene& s = as.scene;
    const double t0 = bench::now();
    const DefaultPlan dp = defaultPlan(s, tracer, st);
    const GridSpec& grid = dp.grid;
    const RadianceEstimator est(s, tracer, dp.transport);
    const std::size_t np = pts.x.size();
    std::vector<double> floorQ(np), floorF(np), cosF(np), sh4F(np);
    tbb::parallel_for(std::size_t(0), np, [&](std::size_t i) {
        const Vec3f n = normalize(pts.n[i]);
        const Rgb direct = exactDirectAt(s, tracer, dp, pts, i);
        for (int pass = 0; pass < 2; ++pass) {
            const uint32_t r = pass ? floorRays : floorRays / 4;
            const AtPoint a = projectAtPoint(est, pts.x[i], n, r, hashCombine(777 + pass, i));
            Rgb c[sh::kCoeffs];
            for (int j = 0; j < sh::kCoeffs; ++j) c[j] = Rgb(a.sh[j]);
            (pass ? floorF : floorQ)[i] = luminance(sh::irradiance(c, n) + direct);
            if (pass) cosF[i] = luminance(Rgb(a.e) + direct);
            if (pass) sh4F[i] = luminance(sh4Irradiance(a, n) + direct);
        }
    });
    std::printf("  study of the default (grid %d x %d x %d, spacing %.3f; %zu chosen lights; floor %.1f s)\n", grid.nx, grid.ny,
                grid.nz, grid.spacing, dp.lights.lights.size(), bench::now() - t0);
    std::vector<StudyBake> bakes;
    Settings full = st;  // the study takes R as given (tryBake's rays scale with --quick)
    full.quick = false;
    for (const int passes : {0, 1}) {
        const std::string kind = passes ? "probe" : "plain";
        StudyBake on, off;
        on.name = kind + " depth";
        off.name = kind + " no-depth";
        for (const uint32_t r : {rays, 4 * rays}) {
            TrySpec ts = parseTry("nodes=16384,depth=1");
            ts.rays = r;
            ts.passes = passes;
            const double t1 = bench::now();
            std::string note;
            const Volume v = tryVolume(Ctx{s, tracer, full, 1}, ts, note);
            on.seconds = off.seconds = bench::now() - t1;
            const IrradianceQuery qOn(v), qOff(v, OutsidePolicy::Clamp, false);
            (r == rays ? on.lo : on.hi) = values([&](const Vec3f& x, const Vec3f& n) { return qOn.irradiance(x, n); }, pts);
            (r == rays ? off.lo : off.hi) = values([&](const Vec3f& x, const Vec3f& n) { return qOff.irradiance(x, n); }, pts);
            {
                const std::vector<double>& a = r == rays ? on.lo : on.hi;
                const std::vector<double>& b = r == rays ? off.lo : off.hi;
                double dmax = 0;
                for (std::size_t i = 0; i < a.size(); ++i) dmax = std::max(dmax, std::abs(a[i] - b[i]));
                std::printf("    (%s %u rays: %.1f s, depth grids %zu, weighted %d/%d, largest on-off difference %.3g)\n", kind.c_str(), r,
                            on.seconds, v.levels[0].depth.size(), int(qOn.depthWeighted()), int(qOff.depthWeighted()), dmax);
            }
        }
        bakes.push_back(on);
        bakes.push_back(off);
    }
    std::vector<std::size_t> all(np);
    for (std::size_t i = 0; i < np; ++i) all[i] = i;
    printStudy("all", all, truth, floorQ, floorF, cosF, sh4F, bakes, csv, as.name);
    for (const bench::AccuracyRegion& region : as.regions) {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < np; ++i)
            if (region.contains(pts.x[i])) idx.push_back(i);
        if (!idx.empty()) printStudy(region.name.c_str(), idx, truth, floorQ, floorF, cosF, sh4F, bakes, csv, as.name);
    }
}

}  // namespace vdblight::accuracy
