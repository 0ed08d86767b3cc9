// vdblight_bench_accuracy: the decomposition of a scene's error (bench_accuracy.cpp):
// the representation floors at the points, then what interpolation between nodes adds
// (spatial), each with the Monte Carlo noise extrapolated out.
#include "accuracy.h"

namespace vdblight::accuracy {

void decompose(const bench::AccuracyScene& as, const Tracer& tracer, const Points& pts, const Truth& truth,
               const Settings& st, FILE* csv) {
    const Scene& s = as.scene;
    const double t0 = bench::now();
    const Floor quarter = floorAt(s, tracer, pts, st.floorRays / 4, st.refBounces);
    const Floor full = floorAt(s, tracer, pts, st.floorRays, st.refBounces);
    const Errors shQ = summarise(relative(quarter.sh, truth.e, truth)), shF = summarise(relative(full.sh, truth.e, truth));
    const Errors ivQ = summarise(relative(quarter.iv, truth.e, truth)), ivF = summarise(relative(full.iv, truth.e, truth));
    const Errors eF = summarise(relative(full.e, truth.e, truth));
    const Errors ivP = summarise(relative(full.ivPaper, truth.e, truth));
    const Errors ivQd = summarise(relative(full.ivQuadratic, truth.e, truth));
    std::printf("  decomposition (floor: a node at each point, %u rays; noise-free: extrapolated from %u and %u rays; %.1f s)\n",
                st.floorRays, st.floorRays / 4, st.floorRays, bench::now() - t0);
    std::printf("    cosine-weighted E at the point from the same samples (no representation): RMS %.1f %%, bias %+.1f %%\n",
                100 * eF.rms, 100 * eF.bias);
    std::printf("    SH order-2 floor:          RMS %.1f %% (noise-free %.1f %%), p95 %.1f %%, max %.1f %%, bias %+.1f %%\n",
                100 * shF.rms, 100 * noiseFree(shQ.rms, shF.rms), 100 * shF.p95, 100 * shF.max, 100 * shF.bias);
    std::printf("    irradiance-vector floor:   RMS %.1f %% (noise-free %.1f %%), p95 %.1f %%, max %.1f %%, bias %+.1f %%\n",
                100 * ivF.rms, 100 * noiseFree(ivQ.rms, ivF.rms), 100 * ivF.p95, 100 * ivF.max, 100 * ivF.bias);
    std::printf("    irradiance vectors, the paper's n^2 blend (before issue 15 item 5): RMS %.1f %%, p95 %.1f %%, "
                "bias %+.1f %%\n", 100 * ivP.rms, 100 * ivP.p95, 100 * ivP.bias);
    writeCsvRow(csv, Row{as.name, "floor_iv_paper_blend", ivP});
    std::printf("    irradiance vectors, the quadratic blend unclamped: RMS %.1f %%, p95 %.1f %%, bias %+.1f %%\n",
                100 * ivQd.rms, 100 * ivQd.p95, 100 * ivQd.bias);
    writeCsvRow(csv, Row{as.name, "floor_iv_quadratic_blend", ivQd});
    Row fr{as.name, "floor_sh2", shF};
    fr.note = "noise-free " + std::to_string(noiseFree(shQ.rms, shF.rms));
    writeCsvRow(csv, fr);
    Row fi{as.name, "floor_iv", ivF};
    fi.note = "noise-free " + std::to_string(noiseFree(ivQ.rms, ivF.rms));
    writeCsvRow(csv, fi);
    Row fe{as.name, "floor_exact_at_point", eF};
    writeCsvRow(csv, fe);

    // Spatial: bakes at the default resolution with the ground truth's bounces against the
    // floors at the points, at N/4 and N rays (photons) with the noise extrapolated out.
    const Ctx ctx{s, tracer, st, 1};
    auto spatial = [&](const std::function<Baked(uint64_t)>& bake, uint64_t budget, const std::vector<double>& floorValues,
                       const char* label) {
        const Baked lo = bake(budget / 4), hi = bake(budget);
        const std::vector<double> loGot = values(lo.irradiance, pts), hiGot = values(hi.irradiance, pts);
        const Errors loE = summarise(relative(loGot, floorValues, truth)), hiE = summarise(relative(hiGot, floorValues, truth));
        const Errors total = summarise(relative(hiGot, truth.e, truth));
        std::printf("    spatial, %s (%llu and %llu, %.1f s): against the floor RMS %.1f %% (noise-free %.1f %%), bias %+.1f %%; "
                    "against the truth RMS %.1f %%, bias %+.1f %%\n",
                    label, (unsigned long long)(budget / 4), (unsigned long long)budget, hi.seconds, 100 * hiE.rms,
                    100 * noiseFree(loE.rms, hiE.rms), 100 * hiE.bias, 100 * total.rms, 100 * total.bias);
        Row r{as.name, std::string("spatial_") + label, hiE};
        r.seconds = hi.seconds;
        r.note = "noise-free " + std::to_string(noiseFree(loE.rms, hiE.rms));
        writeCsvRow(csv, r);
    };
    spatial([&](uint64_t rays) { return pointGather(ctx, st.res(16), uint32_t(rays), st.refBounces); }, st.spatialRays,
            full.sh, "sh2");
    spatial([&](uint64_t n) { return photons(ctx, st.res(16), n, st.refBounces); }, st.spatialPhotons, full.iv, "iv");
    // The same six vectors projected at the nodes (no photon estimator): interpolation only,
    // and the photon volume against it: what the face-averaged flux estimator adds.
    {
        const double t1 = bench::now();
        const Baked pointIv = fromVolume(ivPointVolume(s, tracer, st.res(16), st.spatialRays / 4, st.refBounces), 0, 0);
        const std::vector<double> pGot = values(pointIv.irradiance, pts);
        const Errors vsFloor = summarise(relative(pGot, full.iv, truth));
        const Baked ph = photons(ctx, st.res(16), st.spatialPhotons, st.refBounces);
        const Errors phVsPoint = summarise(relative(values(ph.irradiance, pts), pGot, truth));
        std::printf("    irradiance vectors projected at the nodes (%u rays, %.1f s): against the floor RMS %.1f %%, bias %+.1f %%; "
                    "the photon volume against them: RMS %.1f %%, bias %+.1f %%\n",
                    st.spatialRays / 4, bench::now() - t1, 100 * vsFloor.rms, 100 * vsFloor.bias, 100 * phVsPoint.rms,
                    100 * phVsPoint.bias);
        writeCsvRow(csv, Row{as.name, "iv_nodes_vs_floor", vsFloor});
        writeCsvRow(csv, Row{as.name, "photons_vs_iv_nodes", phVsPoint});
    }
}

}  // namespace vdblight::accuracy
