// vdblight check-scene [SCENE]: faces whose back side is seen from open space (scene_check.h).
#include <iostream>
#include <sstream>

#include "app_common.h"
#include "commands.h"
#include "vdblight/bake/scene_check.h"
#include "vdblight/trace/trace.h"

namespace vdblight::app {

namespace {
struct CheckSceneCommand {
    SceneOptions scene;  // path, --scale, --up
    SceneCheckOptions options;
    int limit = 50;
    bool quiet = false;
};

void run(const CheckSceneCommand& c) {
    SceneOptions so = c.scene;
    so.allowDark = true;  // lighting does not matter here
    const Scene scene = loadSceneFromOptions(so, c.quiet);
    const Tracer tracer(scene);
    const SceneCheckResult r = findBackfacingTriangles(scene, tracer, c.options);
    std::ostringstream out;
    if (!c.quiet)
        out << "Scene '" << scene.name << "': " << scene.triangleCount() << " triangles; " << r.openProbes << " of "
            << r.probes << " probe points in open space (at most " << c.options.maxBackfaceFraction * 100
            << " % of " << c.options.raysPerPoint << " rays hit back-faces)\n";
    if (r.openProbes == 0) {
        std::cout << out.str();
        std::cerr << "vdblight: warning: no probe point sees mostly front faces: the normals look reversed "
                     "everywhere (or the scene has no open space)\n";
        return;
    }
    if (r.backfacing.empty()) {
        if (!c.quiet) out << "No face is seen from behind from open space.\n";
        std::cout << out.str();
        return;
    }
    if (!c.quiet)
        out << r.backfacing.size() << " faces are seen from behind from open space (reversed normals?):\n";
    out << "triangle,material,backface_hits\n";
    int shown = 0;
    for (const BackfacingTriangle& t : r.backfacing) {
        if (c.limit > 0 && shown++ == c.limit) {
            out << "... " << r.backfacing.size() - std::size_t(c.limit) << " more (--limit 0 lists all)\n";
            break;
        }
        out << t.triangle << "," << scene.material(t.triangle).name << "," << t.hits << "\n";
    }
    std::cout << out.str();
}
}  // namespace

void addCheckSceneCommand(CLI::App& app) {
    auto c = std::make_shared<CheckSceneCommand>();
    CLI::App* cmd = app.add_subcommand(
        "check-scene", "List faces whose back side is seen from open space (reversed normals, K&L section 7)");
    addSceneFileOptions(*cmd, c->scene);
    cmd->add_option("--resolution", c->options.resolution, "Probe points along the longest side of the bounds")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    cmd->add_option("--rays", c->options.raysPerPoint, "Ray directions per probe point")
        ->check(CLI::Range(1u, 1u << 20))
        ->capture_default_str();
    cmd->add_option("--max-backface", c->options.maxBackfaceFraction,
                    "A probe whose back-face hit fraction exceeds this is not open space")
        ->check(CLI::Range(0.0, 0.99))
        ->capture_default_str();
    cmd->add_option("--min-hits", c->options.minHits, "Back-face hits from open space needed to list a face")
        ->check(CLI::Range(1u, 1u << 30))
        ->capture_default_str();
    cmd->add_option("--limit", c->limit, "List at most this many faces (0 = all)")
        ->check(CLI::Range(0, 1 << 30))
        ->capture_default_str();
    cmd->add_option("--threads", c->options.threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 4096));
    cmd->add_flag("-q,--quiet", c->quiet, "Print only the CSV list");
    cmd->callback([c] { run(*c); });
}

}  // namespace vdblight::app
