// vdblight_bench_accuracy: the table of methods and modes it measures. A new method or mode
// is one entry here.
#include "accuracy.h"

#include "vdblight/bake/each_pass.h"

namespace vdblight::accuracy {

/// The table of methods and modes. Resolutions and budgets are the full run's; --quick
/// scales them down (Settings::res / rays / photons).
std::vector<Config> configurations() {
    std::vector<Config> v;
    // What `vdblight bake SCENE -o OUT` does with no other option: the library's own resolution
    // of an empty request (bake_request.cpp, --quality default), so that this row cannot drift
    // from it: --direct occlusion (baked in a scene without lights), about 16384 nodes in the
    // scene box (node_budget.h), 1024 rays of full paths + one probe-to-probe pass that reads the
    // surface probe cache, depth moments from the gather's own first hits and depth-weighted
    // lookups, SH order 4 stored.
    // --quick: 1/8 of the nodes, 1/16 of the rays.
    const TrySpec def = defaultTry();
    v.push_back({"default", "vdblight bake SCENE -o OUT (" + describeTry(def) + ", --direct occlusion)",
                 [def](const Ctx& c) { return tryBake(c, def); }, true});
    // The default with --probe-cache nodes (the default before issue 15's twelfth session): the
    // probe pass reads the nodes' reflected light around a path's first hit, not the surface
    // bins (bake/surface_bins.h).
    TrySpec nodes = def;
    nodes.surfaceCache = false;
    v.push_back({"default_node_cache", "the default bake with --probe-cache nodes (the default before)",
                 [nodes](const Ctx& c) { return tryBake(c, nodes); }, true});
    // The default with --direct runtime: the volume holds indirect light only and each lookup
    // adds every light's direct light with shadow rays (an engine's real-time lights): what the
    // interpolated visibility of --direct occlusion costs (outdoor: the sun's shadow edges).
    TrySpec runtime = def;
    runtime.direct = DirectMode::Runtime;
    v.push_back({"default_direct_runtime", "the default bake with --direct runtime (direct light with shadow rays at lookup)",
                 [runtime](const Ctx& c) { return tryBake(c, runtime); }});
    // The default without the shadow edges (bake --no-shadow-edges): what they cost and give.
    TrySpec noEdges = def;
    noEdges.shadowEdges = false;
    v.push_back({"default_no_edges", "the default bake with --no-shadow-edges (the visibility channels alone)",
                 [noEdges](const Ctx& c) { return tryBake(c, noEdges); }});
    // The default with one pass of the node filter (--node-filter 1, bilateral): the candidate
    // default since a tiled bake's merge runs the filter (volume/node_filter.h).
    TrySpec filtered = def;
    filtered.filter = 1;
    v.push_back({"default_filter", "the default bake with --node-filter 1 (one bilateral pass of the node filter)",
                 [filtered](const Ctx& c) { return tryBake(c, filtered); }});
    // The default with the light visibility interpolated trilinearly (as before issue 15 item 2).
    v.push_back({"default_vis_trilinear", "the default bake, light visibility looked up trilinearly (not depth-weighted)",
                 [def](const Ctx& c) { return tryBake(c, def, &fromVolumeVisibilityTrilinear); }});
    // What an engine's L2 probes hold of the default (default_l2), and the engine-size export
    // layouts' share of it (accuracy_engine_layouts.cpp): one bake read three ways.
    addEngineLayoutConfigs(v, def);
    // The default before SH order 4 (issue 15, tenth session): SH order 2, 768 rays.
    v.push_back({"default_sh2_768", "the default before it stored SH order 4: ~16384 nodes, 768 rays + 1 probe pass, "
                                    "depth moments, SH order 2",
                 [](const Ctx& c) { return tryBake(c, parseTry("nodes=16384,rays=768,passes=1,depth=1")); }, true});
    // The default before this choice (issue 15 merges): 16 nodes on the longest axis, 256 rays
    // + one probe pass, no depth moments.
    v.push_back({"default_16_256", "16 nodes, 256 rays + 1 probe pass, --direct occlusion (the default before)",
                 [](const Ctx& c) { return tryBake(c, parseTry("res=16,rays=256,passes=1")); }});
    for (const auto& [mode, name] : {std::pair{DirectMode::Baked, "baked"}, std::pair{DirectMode::Runtime, "runtime"},
                                     std::pair{DirectMode::Occlusion, "occlusion"}})
        v.push_back({std::string("direct_") + name, std::string("--direct ") + name + ", 16 nodes, 256 rays",
                     [mode = mode](const Ctx& c) { return directGather(c, c.settings.res(16), c.settings.rays(256), mode); }});
    // --direct occlusion without the shadow edges (as before issue 32 item 2): the same bake's
    // visibility channels, looked up trilinearly.
    v.push_back({"direct_occlusion_no_edges", "--direct occlusion --no-shadow-edges, 16 nodes, 256 rays",
                 [](const Ctx& c) { return directGather(c, c.settings.res(16), c.settings.rays(256), DirectMode::Occlusion, 0, false); }});
    for (const uint32_t rays : {64u, 1024u})
        v.push_back({"point_16_" + std::to_string(rays), "point gather, 16 nodes, " + std::to_string(rays) + " rays",
                     [rays](const Ctx& c) { return pointGather(c, c.settings.res(16), c.settings.rays(rays)); },
                     rays == 1024});
    v.push_back({"point_16_1024_depth", "point gather, 16 nodes, 1024 rays, --depth-moments (weighted lookup)",
                 [](const Ctx& c) { return pointGather(c, c.settings.res(16), c.settings.rays(1024), 0, true); }});
    v.push_back({"point_32_256", "point gather, 32 nodes, 256 rays",
                 [](const Ctx& c) { return pointGather(c, c.settings.res(32), c.settings.rays(256)); }});
    // --quality preview, from the library's own resolution (bake_request.cpp), with noise.
    const TrySpec preview = presetTry("preview");
    v.push_back({"preview", "vdblight bake --quality preview (" + describeTry(preview) + ", --direct occlusion)",
                 [preview](const Ctx& c) { return tryBake(c, preview); }, true});
    // The same without the guided probe directions (direction_guide.h) and pass 0's blend
    // (volume/first_pass_blend.h): the preview until issue 32's second session.
    TrySpec unguided = preview;
    unguided.guide = false;
    unguided.blend = false;
    v.push_back({"preview_unguided", "--quality preview with uniform probe directions and without pass 0 blended in (" + describeTry(unguided) + ")",
                 [unguided](const Ctx& c) { return tryBake(c, unguided); }, true});
    // The preview without its extra paths for the surface cache (extra_cache_paths.h).
    TrySpec previewNoExtra = preview;
    previewNoExtra.extraPaths = false;
    v.push_back({"preview_no_extra_paths", "--quality preview --no-extra-cache-paths (" + describeTry(previewNoExtra) + ")",
                 [previewNoExtra](const Ctx& c) { return tryBake(c, previewNoExtra); }, true});
    // The preview with pass 0's rays the same at every node (first_pass_by_error.h).
    TrySpec previewEvenFirstPass = preview;
    previewEvenFirstPass.byError = false;
    v.push_back({"preview_even_first_pass", "--quality preview --no-first-pass-by-error (" + describeTry(previewEvenFirstPass) + ")",
                 [previewEvenFirstPass](const Ctx& c) { return tryBake(c, previewEvenFirstPass); }, true});
    // The preview until issue 32's third session: ~2048 nodes, 128 rays (the rest as now but the
    // extra cache paths).
    TrySpec previewFewerNodes = previewNoExtra;
    previewFewerNodes.nodes = 2048;
    previewFewerNodes.rays = 128;
    previewFewerNodes.byError = false;
    v.push_back({"preview_2048", "--quality preview until issue 32's third session (" + describeTry(previewFewerNodes) + ")",
                 [previewFewerNodes](const Ctx& c) { return tryBake(c, previewFewerNodes); }, true});
    // The preview's error taken apart (issue 32, third session), one component changed per row:
    // the light visibility (exact at the lookup, or without the shadow edges), the noise (8 x
    // the rays) and the interpolation (the default's ~16384 nodes at the preview's rays).
    TrySpec previewRuntime = preview;
    previewRuntime.direct = DirectMode::Runtime;
    v.push_back({"preview_direct_runtime", "--quality preview --direct runtime (the lights' visibility exact at the lookup)",
                 [previewRuntime](const Ctx& c) { return tryBake(c, previewRuntime); }, true});
    TrySpec previewNoEdges = preview;
    previewNoEdges.shadowEdges = false;
    v.push_back({"preview_no_edges", "--quality preview --no-shadow-edges",
                 [previewNoEdges](const Ctx& c) { return tryBake(c, previewNoEdges); }});
    TrySpec previewRays = preview;
    previewRays.rays *= 8;
    v.push_back({"preview_8x_rays", "--quality preview with 8 x the rays (" + describeTry(previewRays) + "): its noise nearly out",
                 [previewRays](const Ctx& c) { return tryBake(c, previewRays); }, true});
    TrySpec previewNodes = preview;
    previewNodes.nodes = def.nodes;
    v.push_back({"preview_default_nodes", "--quality preview on the default's grid (" + describeTry(previewNodes) + ")",
                 [previewNodes](const Ctx& c) { return tryBake(c, previewNodes); }, true});
    // The preview before issue 32.
    v.push_back({"preview_before", "--quality preview before issue 32: 16 nodes, 256 rays of full paths, no probe pass, "
                                   "no depth moments, SH order 2, --direct occlusion",
                 [](const Ctx& c) { return tryBake(c, parseTry("res=16,rays=256,passes=0")); }, true});
    v.push_back({"probe_32_128", "--resolution 32 --rays 128 --probe-passes 1 (issue 15)",
                 [](const Ctx& c) {
                     GatherOptions g;
                     g.raysPerNode = c.settings.rays(128);
                     g.probePasses = 1;
                     g.seed = c.seed;
                     g.threads = c.settings.threads;
                     const double t0 = bench::now();
                     Volume vol = bakeShGather(c.scene, c.tracer, gridFor(c.scene, c.settings.res(32)), g);
                     const double t = bench::now() - t0;
                     const uint64_t nodes = vol.levels[0].grid.nodeCount();
                     return fromVolume(std::move(vol), t, nodes);
                 }});
    v.push_back({"antialiased", "--sampling antialiased (interior), 16 nodes, 256 rays/cell",
                 [](const Ctx& c) { return antialiased(c, c.settings.res(16), c.settings.rays(256), NodeFit::Projection); }});
    v.push_back({"antialiased_lsq", "--sampling antialiased --fit least-squares, 16 nodes, 256 rays/cell",
                 [](const Ctx& c) { return antialiased(c, c.settings.res(16), c.settings.rays(256), NodeFit::LeastSquares); }});
    v.push_back({"adaptive", "--layout adaptive --levels 3 --refine 2, 16 nodes, 128 rays",
                 [](const Ctx& c) { return adaptiveLayout(c, c.settings.res(16), c.settings.rays(128), 3, 2); }});
    v.push_back({"adaptive_depth", "--layout adaptive --levels 3 --refine 2 --depth-moments, 16 nodes, 128 rays",
                 [](const Ctx& c) { return adaptiveLayout(c, c.settings.res(16), c.settings.rays(128), 3, 2, true); }});
    v.push_back({"target_0.03", "--target-error 0.03 --max-rays 2048, 16 nodes",
                 [](const Ctx& c) { return targetError(c, c.settings.res(16), 0.03, c.settings.rays(2048)); }});
    v.push_back({"photons", "--method photons --photons 4000000, 16 nodes",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(4'000'000)); }, true});
    v.push_back({"photons_1M", "--method photons --photons 1000000, 16 nodes",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(1'000'000)); }});
    v.push_back({"photons_16k", "--method photons --photons 4000000 on the default's grid (~16384 nodes)",
                 [](const Ctx& c) { return photons(c, 0, c.settings.photons(4'000'000)); }, true});
    v.push_back({"photons_16k_1M", "--method photons --photons 1000000 on the default's grid (~16384 nodes)",
                 [](const Ctx& c) { return photons(c, 0, c.settings.photons(1'000'000)); }, true});
    // The photon pass with --depth-moments (256 first-hit rays per node, the bake's default for
    // the photon pass): the same lookups, weighted by visibility (issue 15 item 4). On the
    // default's grid, what `bake --method photons` does by default.
    v.push_back({"photons_depth", "--method photons --photons 4000000 --depth-moments, 16 nodes",
                 [](const Ctx& c) {
                     return photons(c, c.settings.res(16), c.settings.photons(4'000'000), 0, iv::kDefaultBlend, c.settings.rays(256));
                 }});
    v.push_back({"photons_16k_depth", "--method photons --depth-moments on the default's grid (4000000 photons): "
                                      "what `bake --method photons` does by default",
                 [](const Ctx& c) { return photons(c, 0, c.settings.photons(4'000'000), 0, iv::kDefaultBlend, c.settings.rays(256)); }});
    v.push_back({"photons_paper", "--method photons --photons 4000000, 16 nodes, read with query --iv-blend paper "
                                  "(the lookup before issue 15 item 5)",
                 [](const Ctx& c) { return photons(c, c.settings.res(16), c.settings.photons(4'000'000), 0, iv::Blend::Paper); }});
    v.push_back({"bins_11", "--basis bins:11 (242 bins, 1 ray each), 16 nodes",
                 [](const Ctx& c) { return binsBake(c, c.settings.res(16), c.settings.quick ? 3 : 11); }});
    return v;
}

}  // namespace vdblight::accuracy
